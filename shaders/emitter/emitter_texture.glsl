// Textured area emitters sampled by their texture, as Mitsuba 3's area emitter samples
// a spatially varying radiance (src/emitters/area.cpp, sample_direction; the bitmap's
// sample_position): a texture point p from the bitmap's luminance, the surface uv
// s = to_uv⁻¹(p), the surface point x(s); density per unit area
// p_tex(p) / |∂x/∂u × ∂x/∂v| (to_uv is a symmetry of the unit square: |det| = 1).
// Which emitters qualify (EmitterRecord.dist_width > 0: affine-mapped meshes such as
// rectangles, and spheres), the texture-space density for nearest and bilinear
// filtering and the buffer layout: src/scene/textured_emitter.rs, the CPU reference.
// Needs scene_bindings.glsl, texture.glsl, warp.glsl, distribution2d.glsl, and
// EMITTER_HAS (emitter.glsl).
#ifndef EMITTER_TEXTURE_GLSL
#define EMITTER_TEXTURE_GLSL

// Whether area emitter e is sampled by its texture (else uniformly by area). False at
// compile time in scenes without such an emitter (EMITTER_KIND_BIT_TEXTURE_SAMPLED).
bool emitter_texture_sampled(EmitterRecord e) {
    return EMITTER_HAS(EMITTER_KIND_BIT_TEXTURE_SAMPLED) && e.kind == EMITTER_AREA && e.dist_width != 0u;
}

// Texture point of surface uv s: to_uv, as texture_eval applies it.
vec2 emitter_texture_point_of(TextureRecord t, vec2 s) {
    return vec2(dot(t.to_uv_u.xyz, vec3(s, 1.0)), dot(t.to_uv_v.xyz, vec3(s, 1.0)));
}

// Surface uv of texture point p: to_uv⁻¹, the transpose of its linear part (a signed
// permutation) applied to p minus its translation.
vec2 emitter_texture_uv_of(TextureRecord t, vec2 p) {
    vec2 q = p - vec2(t.to_uv_u.z, t.to_uv_v.z);
    return vec2(t.to_uv_u.x * q.x + t.to_uv_v.x * q.y, t.to_uv_u.y * q.x + t.to_uv_v.y * q.y);
}

// Density of emitter_texture_sample at texture point p, per unit area of texture
// coordinates: the texel densities stored after e's CDFs, looked up as texture_bitmap
// looks up texels (texture_footprint: nearest the texel's own; bilinear interpolated).
float emitter_texture_density(EmitterRecord e, TextureRecord t, vec2 p) {
    uint w = e.dist_width, h = e.dist_height;
    uint base = e.dist_offset + h + 1u + h * (w + 1u);
    TexelFootprint f = texture_footprint(t.flags, int(w), int(h), p);
    uint xa = uint(f.xa), xb = uint(f.xb), ya = uint(f.ya), yb = uint(f.yb);
    float a = mix(dist_value(base + ya * w + xa), dist_value(base + ya * w + xb), f.fx);
    float b = mix(dist_value(base + yb * w + xa), dist_value(base + yb * w + xb), f.fx);
    return mix(a, b, f.fy);
}

// A texture point in [0, 1]² drawn from u with density emitter_texture_density: a
// texel by the 2-D distribution, then (nearest) uniform in its cell, or (bilinear,
// Mitsuba's) a tent of one texel around its centre, wrapped (repeat) or reflected
// (clamp, mirror) back into [0, 1].
vec2 emitter_texture_sample(EmitterRecord e, TextureRecord t, vec2 u) {
    uvec2 cell;
    vec2 f;
    dist2d_sample_cell(e.dist_offset, e.dist_width, e.dist_height, u, cell, f);
    vec2 res = vec2(float(e.dist_width), float(e.dist_height));
    if ((t.flags & TEXTURE_NEAREST) != 0u) return (vec2(cell) + f) / res;
    vec2 p = (vec2(cell) + 0.5 + warp_square_to_tent(f)) / res;
    if (((t.flags >> TEXTURE_WRAP_SHIFT) & 3u) == TEXTURE_WRAP_REPEAT) {
        p += mix(vec2(0.0), vec2(1.0), lessThan(p, vec2(0.0)));
        p -= mix(vec2(0.0), vec2(1.0), greaterThan(p, vec2(1.0)));
    } else {
        p = abs(p);
        p = mix(p, 2.0 - p, greaterThan(p, vec2(1.0)));
    }
    return p;
}

// Whether texture-sampled emitter e is an affine-mapped mesh, not a sphere: true at
// compile time where no texture-sampled emitter is a sphere
// (EMITTER_KIND_BIT_TEXTURE_SPHERE), so that the sphere's code compiles away.
bool emitter_texture_on_mesh(EmitterRecord e) {
    return !EMITTER_HAS(EMITTER_KIND_BIT_TEXTURE_SPHERE) || e.tri_count > 0u;
}

// |∂x/∂u × ∂x/∂v| at surface uv s: surface area per unit uv area. A mesh's affine map
// has it constant; a sphere (uv = (φ/2π, θ/π)) 2π² r² sin θ.
float emitter_texture_jacobian(EmitterRecord e, vec2 s) {
    if (emitter_texture_on_mesh(e)) return length(cross(e.to_world_y.xyz, e.to_world_z.xyz));
    return 2.0 * PI * PI * e.radius * e.radius * sin(PI * s.y);
}

// Density per unit area with which emitter_texture_point picks the point of e at
// surface uv s (for MIS on a hit).
float emitter_texture_pdf_area(EmitterRecord e, vec2 s) {
    TextureRecord t = texture_load(e.texture - 1u);
    float jac = emitter_texture_jacobian(e, s);
    return jac > 0.0 ? emitter_texture_density(e, t, emitter_texture_point_of(t, s)) / jac : 0.0;
}

struct EmitterTexturePoint {
    vec3 p;      // the point on the surface
    vec3 ng;     // its geometric normal, as a ray hitting it finds it
    vec3 texel;  // the texture there
    float pdf;   // per unit area
};

// A point of texture-sampled area emitter e from the 2-D sample u.
EmitterTexturePoint emitter_texture_point(EmitterRecord e, vec2 u) {
    TextureRecord t = texture_load(e.texture - 1u);
    vec2 pt = emitter_texture_sample(e, t, u);
    vec2 s = emitter_texture_uv_of(t, pt);
    EmitterTexturePoint r;
    r.texel = texture_bitmap(t, pt);
    float jac = emitter_texture_jacobian(e, s);
    r.pdf = jac > 0.0 ? emitter_texture_density(e, t, pt) / jac : 0.0;
    if (emitter_texture_on_mesh(e)) {
        r.p = e.to_world_x.xyz + s.x * e.to_world_y.xyz + s.y * e.to_world_z.xyz;
        r.ng = vec3(e.to_world_x.w, e.to_world_y.w, e.to_world_z.w);
    } else {
        // The sphere's object-space direction at θ = π s.y, φ = 2π s.x, in the frame
        // surface_quadric uses (p1, p2, and a3 = ±p1 × p2 / r), outward unless its
        // normals are flipped.
        Prim prim = prim_load(e.prim);
        ShapeRecord shape = shape_load(e.shape);
        float r_len = length(prim.p1);
        float mirror = (shape.flags & SHAPE_MIRRORED) != 0u ? -1.0 : 1.0;
        vec3 a3 = mirror * cross(prim.p1, prim.p2) / r_len;
        float theta = PI * s.y, phi = 2.0 * PI * s.x;
        float st = sin(theta);
        vec3 n = (st * cos(phi) * prim.p1 + st * sin(phi) * prim.p2 + cos(theta) * a3) / r_len;
        r.p = prim.p0 + r_len * n;
        r.ng = (shape.flags & SHAPE_FLIP_NORMALS) != 0u ? -n : n;
    }
    return r;
}

#endif
