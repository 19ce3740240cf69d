// Environment maps (Mitsuba 3's envmap): lat-long lookups and importance sampling by
// a piecewise-constant 2D distribution (distribution2d.glsl). Needs
// scene_bindings.glsl, texture.glsl.
// Conventions and the distribution's construction: src/scene/envmap.rs (its CPU
// reference). Directions here are world-space and point away from the scene.
#ifndef ENVMAP_GLSL
#define ENVMAP_GLSL

#include "sampling/warp.glsl"
#include "sampling/distribution2d.glsl"
#include "numeric/convert.glsl"

// World direction -> the map's frame (to_world is a rotation: its inverse is the
// transpose).
vec3 envmap_to_local(EmitterRecord e, vec3 d) {
    return vec3(dot(e.to_world_x.xyz, d), dot(e.to_world_y.xyz, d), dot(e.to_world_z.xyz, d));
}

vec3 envmap_to_world(EmitterRecord e, vec3 d) {
    return d.x * e.to_world_x.xyz + d.y * e.to_world_y.xyz + d.z * e.to_world_z.xyz;
}

// Lat-long coordinates of a unit direction in the map's frame: u = atan2(x, −z)/2π
// in [0, 1), v = acos(y)/π.
vec2 envmap_uv(vec3 d) {
    float u = atan(d.x, -d.z) * (0.5 * INV_PI);
    if (u < 0.0) u += 1.0;
    return vec2(u, acos(clamp(d.y, -1.0, 1.0)) * INV_PI);
}

// Radiance arriving from world direction d (towards the environment): the map
// bilinear, periodic in u (texel i at (i + ½)/W), pole to pole in v (y = v (H − 1)),
// times scale (in e.radiance).
vec3 envmap_eval(EmitterRecord e, vec3 d) {
    TextureRecord t = texture_load(e.texture - 1u);
    vec2 uv = envmap_uv(envmap_to_local(e, d));
    int w = int(t.width), h = int(t.height);
    float x = uv.x * float(w) - 0.5;
    float y = uv.y * float(h - 1);
    float x0f = floor(x), y0f = floor(y);
    float fx = x - x0f, fy = y - y0f;
    int x0 = trunc_to_int(x0f), y0 = trunc_to_int(y0f); // |x|, |y| <= w, h: convert.glsl
    int xa = texture_wrap(x0, w, TEXTURE_WRAP_REPEAT);
    int xb = texture_wrap(x0 + 1, w, TEXTURE_WRAP_REPEAT);
    int ya = clamp(y0, 0, h - 1), yb = clamp(y0 + 1, 0, h - 1);
    vec3 a = mix(texture_texel(t, xa, ya), texture_texel(t, xb, ya), fx);
    vec3 b = mix(texture_texel(t, xa, yb), texture_texel(t, xb, yb), fx);
    return e.radiance * mix(a, b, fy);
}

// Density per unit solid angle with which envmap_sample picks world direction d.
float envmap_pdf(EmitterRecord e, vec3 d) {
    vec3 local = envmap_to_local(e, d);
    vec2 uv = envmap_uv(local);
    // sin θ from the horizontal components: exact near the poles, where
    // sqrt(1 - y²) rounds to 0 within 3.5e-4 rad of them.
    float st = length(local.xz);
    if (st <= 0.0) return 0.0;
    uint i = min(floor_to_uint(uv.x * float(e.dist_width)), e.dist_width - 1u);
    uint j = min(floor_to_uint(uv.y * float(e.dist_height)), e.dist_height - 1u);
    return dist2d_cell_density(e.dist_offset, e.dist_width, e.dist_height, i, j) / (2.0 * PI * PI * st);
}

// Samples a world direction towards the map, with density envmap_pdf per unit solid
// angle, p(ω) = p(u, v) / (2π² sin θ) (PBR 3rd ed., sec. 14.2.4).
vec3 envmap_sample_direction(EmitterRecord e, vec2 u) {
    vec2 uv = dist2d_sample(e.dist_offset, e.dist_width, e.dist_height, u);
    // Off the poles themselves (u.x = 0 exactly there), where the direction has no
    // density.
    float theta = clamp(uv.y, 1e-7, 1.0 - 1e-6) * PI, phi = uv.x * (2.0 * PI);
    float st = sin(theta);
    return envmap_to_world(e, vec3(st * sin(phi), cos(theta), -st * cos(phi)));
}

// envmap_sample_direction with its density: the density of the direction as
// envmap_pdf finds it, so that MIS sees the very same number on a hit (they differ
// from the cell's only by rounding at its edges).
vec3 envmap_sample(EmitterRecord e, vec2 u, out float pdf) {
    vec3 d = envmap_sample_direction(e, u);
    pdf = envmap_pdf(e, d);
    return d;
}

#endif
