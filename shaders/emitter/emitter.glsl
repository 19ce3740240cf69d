// Emitters: sampling a point of light as seen from a shading point, and the density
// of that sampling for a point that a BSDF-sampled ray found (for MIS). Needs
// scene_bindings.glsl and wavefront.glsl (frame).
//
// An emitter is chosen in proportion to its sampling weight (Mitsuba's
// `sampling_weight`, 1 by default: uniformly, as Mitsuba 3 and Nori choose) through the
// alias table at entries [0, emitter_count) (render::scene_buffers; SPPM's photons
// leave by power from their own table at photon_alias); a mesh emitter then picks a
// triangle by area and a uniform point on it, so points are uniform over its whole
// surface; a disk or
// cylinder a uniform point of its surface (as Mitsuba's sample_position: the
// concentric map on the disk, uniform angle and height on the cylinder); a sphere
// emitter samples the cone of directions it subtends (PBR 4th ed., sec. 6.2.4). A
// textured emitter on a rectangle (an affine-mapped mesh) or a sphere draws its point
// by its texture instead, as Mitsuba does (emitter_texture.glsl); on other shapes it
// is sampled as an untextured one and weighted by the texture.
// Every pdf here is per unit solid angle at the shading point and includes the
// probability of choosing the emitter.
#ifndef EMITTER_GLSL
#define EMITTER_GLSL

// Kinds a scene does not use compile away (llvmpipe runs both sides of every branch
// under a mask): define EMITTER_KINDS (a bit per EMITTER_* kind, area meaning on
// meshes, EMITTER_KIND_BIT_SPHERE_AREA, EMITTER_KIND_BIT_QUADRIC_AREA and
// EMITTER_KIND_BIT_TEXTURE_SAMPLED) before including this file.
#ifndef EMITTER_KINDS
#define EMITTER_KINDS 0xffffffffu
#endif
#define EMITTER_HAS(k) ((EMITTER_KINDS & (1u << (k))) != 0u)
// Any of the kinds of mask m (one test: glslang 11 emits invalid SPIR-V for a chain
// of || over specialization constants).
#define EMITTER_HAS_ANY(m) ((EMITTER_KINDS & (m)) != 0u)
// Area emitters on meshes, spheres, disks and cylinders.
#define EMITTER_AREA_BITS ((1u << EMITTER_AREA) | (1u << EMITTER_KIND_BIT_SPHERE_AREA) | (1u << EMITTER_KIND_BIT_QUADRIC_AREA) \
                           | (1u << EMITTER_KIND_BIT_TEXTURE_SAMPLED))
// Area emitters that may lie on spheres, disks and cylinders (a texture-sampled one
// may lie on any shape).
#define EMITTER_QUADRIC_AREA_BITS ((1u << EMITTER_KIND_BIT_SPHERE_AREA) | (1u << EMITTER_KIND_BIT_QUADRIC_AREA) \
                                   | (1u << EMITTER_KIND_BIT_TEXTURE_SAMPLED))
// Whether the emitter choice may be stratified (frame.emitter_strata > 0); a kernel
// whose sampler never stratifies it (the independent sampler:
// render::sampler::emitter_strata) defines it false, so that the code of the
// stratified choice compiles away (llvmpipe would run it, masked, for every lane).
#ifndef EMITTER_STRATA
#define EMITTER_STRATA true
#endif

#include "sampling/alias.glsl"
#include "sampling/frame.glsl"
#include "sampling/warp.glsl"
#include "shape/intersect_sphere.glsl"
#include "shape/surface.glsl"
#include "texture/texture.glsl"
#include "emitter/envmap.glsl"
#include "emitter/emitter_texture.glsl"

#define EMITTER_INFINITY uintBitsToFloat(0x7f800000u)

struct EmitterSample {
    vec3 wi;     // unit direction from the shading point towards the light
    float dist;  // distance to the sampled point; EMITTER_INFINITY for the environment
    vec3 Le;     // radiance arriving along -wi (for point and spot lights: I / d²)
    float pdf;   // solid angle (delta lights: the probability of choosing the light)
    bool delta;  // a point or spot light: no MIS, BSDF sampling can never hit it
    uint emitter; // which emitter was chosen
};

// Spot light falloff as Mitsuba's spotlight: 1 inside the beam width, falling linearly
// in angle to 0 at the cutoff.
float emitter_spot_falloff(EmitterRecord e, vec3 w_out) {
    float cos_theta = dot(w_out, e.axis);
    if (cos_theta <= e.cos_cutoff) return 0.0;
    float theta = acos(clamp(cos_theta, -1.0, 1.0));
    return clamp((e.cutoff - theta) * e.inv_transition, 0.0, 1.0);
}

// A spot light's texture (Mitsuba's `texture`) in direction w_out leaving it: the
// direction (x, y, z) in the light's frame (rows to_world_*) is looked up at
// uv = ½ + ½ (x, y) / (z tan cutoff) (e.area holds 1 / tan cutoff; emitter::spot).
vec3 emitter_spot_texture(EmitterRecord e, vec3 w_out) {
    vec3 l = vec3(dot(e.to_world_x.xyz, w_out), dot(e.to_world_y.xyz, w_out), dot(e.to_world_z.xyz, w_out));
    return texture_eval(e.texture, vec2(0.5) + (0.5 * e.area / l.z) * l.xy);
}

// A spot light's intensity in direction w_out leaving it: falloff and texture.
vec3 emitter_spot_intensity(EmitterRecord e, vec3 w_out) {
    float falloff = emitter_spot_falloff(e, w_out);
    vec3 I = e.radiance * falloff;
    if (TEXTURE_USES(TEXTURE_FEATURE_EMITTER_PROFILE) && e.texture != 0u && falloff > 0.0) {
        I *= emitter_spot_texture(e, w_out);
    }
    return I;
}

// Light a projector (emitter::projector) sends to point x, wi the unit direction from
// x to the projector: π scale irradiance(uv) / (z² cos θ) with (x, y, z) the point in
// the projector's frame (rows to_world_*), uv its image coordinate
// (½ - ½ x / (z tan_x), ½ - ½ y / (z tan_y)), tan_x, tan_y in cutoff, inv_transition,
// and cos θ = -axis · wi (Mitsuba's projector sample_direction); 0 outside the image.
vec3 emitter_projector_light(EmitterRecord e, vec3 x, vec3 wi) {
    vec4 xp = vec4(x, 1.0);
    vec3 l = vec3(dot(e.to_world_x, xp), dot(e.to_world_y, xp), dot(e.to_world_z, xp));
    if (!(l.z > 0.0)) return vec3(0.0);
    vec2 uv = vec2(0.5) - (0.5 / l.z) * l.xy / vec2(e.cutoff, e.inv_transition);
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return vec3(0.0);
    vec3 c = e.radiance;
    if (TEXTURE_USES(TEXTURE_FEATURE_EMITTER_PROFILE) && e.texture != 0u) c *= texture_eval(e.texture, uv);
    return c / (l.z * l.z * -dot(e.axis, wi));
}

// Radiance leaving an area emitter towards -d, at a point with geometric normal ng
// and texture coordinates uv: one-sided, from the front face only; a textured
// emitter's radiance is its texture at uv times e.radiance (the scale).
vec3 emitter_area_radiance(EmitterRecord e, vec3 ng, vec3 d, vec2 uv) {
    if (dot(ng, d) >= 0.0) return vec3(0.0);
    // A directional area light is never seen (Mitsuba's directionalarea eval is 0).
    if (EMITTER_HAS(EMITTER_DIRECTIONAL_AREA) && e.kind == EMITTER_DIRECTIONAL_AREA) return vec3(0.0);
    if (TEXTURE_USES(TEXTURE_FEATURE_AREA) && e.texture != 0u) {
        return e.radiance * texture_eval(e.texture, uv);
    }
    return e.radiance;
}

// emitter_area_radiance with e's texture (if it has one) already looked up at the
// point: texel (bsdf_textured_point).
vec3 emitter_area_radiance_texel(EmitterRecord e, vec3 ng, vec3 d, vec3 texel) {
    if (dot(ng, d) >= 0.0) return vec3(0.0);
    if (EMITTER_HAS(EMITTER_DIRECTIONAL_AREA) && e.kind == EMITTER_DIRECTIONAL_AREA) return vec3(0.0);
    if (TEXTURE_USES(TEXTURE_FEATURE_AREA) && e.texture != 0u) return e.radiance * texel;
    return e.radiance;
}

// Radiance arriving from the environment along world direction d (away from the
// scene): the constant emitter or the environment map.
vec3 emitter_env_radiance(EmitterRecord e, vec3 d) {
    if (TEXTURE_USES(TEXTURE_FEATURE_ENVMAP) && e.kind == EMITTER_ENVMAP) return envmap_eval(e, d);
    return e.radiance;
}

// 1 - cos θmax of the cone a sphere (centre c, radius r) subtends from x; 0 if x is
// inside it. Written as sin²/(1 + cos) to stay accurate for small, far spheres.
float emitter_sphere_cone(vec3 x, vec3 c, float r) {
    float dc2 = dot(c - x, c - x);
    float sin2 = r * r / dc2;
    if (sin2 >= 1.0) return 0.0;
    return sin2 / (1.0 + sqrt(1.0 - sin2));
}

// The choice of an emitter by one uniform number. By default it inverts the emitters'
// cumulative pmf (by sampling weight: render::scene_buffers). With a stratifying sampler,
// frame.emitter_strata = k > 0 is the number of strata the sampler cuts the number
// into, and emitter i owns the whole strata [Q_i, Q_{i+1}) of k, with
//     Q_i = i + round((k - n) C_i),
// C_i the weights' cdf before emitter i, n the emitter count: one stratum each plus its
// weight's share of the rest. Every pixel then sends each emitter the same number of
// its samples, stratified within (render::sampler::emitter_strata says why and what it
// measured). Q_n = k; Q_{i+1} - Q_i >= 1, so no emitter is left out.
float emitter_interval_start(uint i) {
    uint n = frame.emitter_count;
    float k = float(frame.emitter_strata);
    if (i >= n) return k;
    return float(i) + floor((k - float(n)) * uintBitsToFloat(alias_load(i).prim) + 0.5);
}

// The emitter u picks, with the probability of picking it; u is remapped to its position
// within the emitter's interval, rescaled (sample reuse: it stays stratified).
uint emitter_choose(inout float u, out float pmf) {
    if (!EMITTER_STRATA || frame.emitter_strata == 0u) {
        return alias_sample_cdf(0u, frame.emitter_count, u, pmf);
    }
    float x = u * float(frame.emitter_strata);
    uint lo = 0u, hi = frame.emitter_count;
    while (hi - lo > 1u) {
        uint mid = (lo + hi) >> 1;
        if (emitter_interval_start(mid) <= x) lo = mid; else hi = mid;
    }
    float a = emitter_interval_start(lo);
    float b = emitter_interval_start(lo + 1u);
    pmf = (b - a) / float(frame.emitter_strata);
    u = clamp((x - a) / (b - a), 0.0, 0.99999994);
    return lo;
}

// The probability that emitter_choose picks emitter i.
float emitter_choice_pmf(uint i) {
    if (!EMITTER_STRATA || frame.emitter_strata == 0u) return alias_load(i).pmf;
    return (emitter_interval_start(i + 1u) - emitter_interval_start(i)) / float(frame.emitter_strata);
}

// A point uniform over the surface of area emitter e (density 1 / e.area per unit
// area), as the Surface a ray finds there, from one 2-D sample u: a mesh picks a
// triangle by area with u.y, which is then reused (alias_sample_reuse), and a uniform
// point on it; a sphere a uniform direction from its centre; a disk the concentric map
// of the unit disk; a cylinder a uniform height and angle (Mitsuba's sample_position
// of each; their area elements are constant). In a scene without area lights on
// quadrics (nor texture-sampled ones, which may be quadrics) the quadrics' code
// compiles away. `shading` (a constant): as surface_at_as's, false where only the
// point, the geometric normal (its side) and the shape are read.
Surface emitter_area_point_as(EmitterRecord e, vec2 u, bool shading) {
    // (Photon emission takes texture-sampled emitters' points here too.)
    if (!EMITTER_HAS_ANY(EMITTER_QUADRIC_AREA_BITS)
        || (EMITTER_HAS_ANY((1u << EMITTER_AREA) | (1u << EMITTER_KIND_BIT_TEXTURE_SAMPLED)) && e.tri_count > 0u)) {
        float tri_pmf;
        uint t = alias_sample_reuse(e.tri_first, e.tri_count, u.y, tri_pmf);
        vec2 b = warp_uniform_triangle(u);
        return surface_at_as(alias_load(e.tri_first + t).prim, b.x, b.y, vec3(0.0), vec3(0.0), 0.0, shading);
    }
    if (e.prim_kind == PRIM_DISK) {
        vec2 xy = warp_square_to_disk(u);
        return surface_at(e.prim, xy.x, xy.y, vec3(0.0), vec3(0.0), 0.0);
    }
    Prim p = prim_load(e.prim);
    vec3 y;
    if (e.prim_kind == PRIM_SPHERE) {
        y = p.p0 + length(p.p1) * warp_uniform_sphere(u);
    } else {
        float phi = 2.0 * PI * u.y;
        vec3 a2 = cross(normalize(p.p2), p.p1);
        y = p.p0 + cos(phi) * p.p1 + sin(phi) * a2 + u.x * p.p2;
    }
    return surface_at(e.prim, 0.0, 0.0, y, vec3(0.0), 0.0);
}

Surface emitter_area_point(EmitterRecord e, vec2 u) { return emitter_area_point_as(e, u, true); }

// Samples light arriving at x from one 2-D sample u: the emitter is chosen by u.x, which
// is then reused (emitter_choose), and the point on it drawn from the 2-D sample
// (emitter_area_point; as Mitsuba does), which a stratified sampler stratifies.
//
// With env = true, the environment emitter (frame.env_emitter) is taken instead, with
// the direction d instead of a sampled one: Le and pdf are its radiance along d and
// the density of sampling d, emitter_env_radiance and emitter_pdf_env bit for bit.
// A path that left the scene (path.glsl) shares this lookup with emitter sampling.
EmitterSample emitter_sample_env(vec3 x, vec2 u, bool env, vec3 d) {
    EmitterSample s;
    s.delta = false;
    s.Le = vec3(0.0);
    s.pdf = 0.0;
    s.dist = 0.0;
    s.wi = vec3(0.0, 0.0, 1.0);
    s.emitter = NONE;
    if (frame.emitter_count == 0u) return s;
    float pmf;
    uint index = emitter_choose(u.x, pmf);
    if (env) {
        index = frame.env_emitter;
        pmf = emitter_choice_pmf(index);
    }
    s.emitter = index;
    EmitterRecord e = emitter_load(index);
    if ((EMITTER_HAS(EMITTER_POINT) && e.kind == EMITTER_POINT)
        || (EMITTER_HAS(EMITTER_SPOT) && e.kind == EMITTER_SPOT)) {
        vec3 d = e.position - x;
        float d2 = dot(d, d);
        s.dist = sqrt(d2);
        s.wi = d / s.dist;
        s.Le = e.radiance / d2;
        if (EMITTER_HAS(EMITTER_SPOT) && e.kind == EMITTER_SPOT) s.Le = emitter_spot_intensity(e, -s.wi) / d2;
        s.pdf = pmf;
        s.delta = true;
    } else if (EMITTER_HAS(EMITTER_DIRECTIONAL_AREA) && e.kind == EMITTER_DIRECTIONAL_AREA) {
        // Nothing: a shading point is not on its normal's line but by chance (Mitsuba's
        // directionalarea sample_direction returns zero).
    } else if (EMITTER_HAS(EMITTER_DIRECTIONAL) && e.kind == EMITTER_DIRECTIONAL) {
        // Irradiance from infinity against the light's direction (Mitsuba's
        // directional sample_direction).
        s.wi = -e.axis;
        s.dist = EMITTER_INFINITY;
        s.Le = e.radiance;
        s.pdf = pmf;
        s.delta = true;
    } else if (EMITTER_HAS(EMITTER_PROJECTOR) && e.kind == EMITTER_PROJECTOR) {
        vec3 d = e.position - x;
        s.dist = length(d);
        s.wi = d / s.dist;
        s.Le = emitter_projector_light(e, x, s.wi);
        s.pdf = pmf;
        s.delta = true;
    } else if (EMITTER_HAS(EMITTER_CONSTANT) && e.kind == EMITTER_CONSTANT) {
        s.wi = env ? d : warp_uniform_sphere(u);
        s.dist = EMITTER_INFINITY;
        s.Le = e.radiance;
        s.pdf = pmf * warp_uniform_sphere_pdf(s.wi);
    } else if (EMITTER_HAS(EMITTER_ENVMAP) && e.kind == EMITTER_ENVMAP) {
        if (!TEXTURE_USES(TEXTURE_FEATURE_ENVMAP)) return s;
        s.wi = env ? d : envmap_sample_direction(e, u);
        s.dist = EMITTER_INFINITY;
        s.Le = envmap_eval(e, s.wi);
        s.pdf = pmf * envmap_pdf(e, s.wi);
    } else if (emitter_texture_sampled(e)) {
        // A textured area emitter whose point its texture draws (emitter_texture.glsl).
        EmitterTexturePoint tp = emitter_texture_point(e, u);
        vec3 d = tp.p - x;
        float d2 = dot(d, d);
        s.dist = sqrt(d2);
        s.wi = d / s.dist;
        float cos_light = -dot(tp.ng, s.wi);
        if (cos_light <= 0.0 || d2 == 0.0 || !(tp.pdf > 0.0)) return s;
        s.Le = e.radiance * tp.texel;
        // Area density to solid angle: d² / cos.
        s.pdf = pmf * tp.pdf * d2 / cos_light;
    } else if ((EMITTER_HAS(EMITTER_AREA) && e.tri_count > 0u)
               || (EMITTER_HAS(EMITTER_KIND_BIT_QUADRIC_AREA) && e.tri_count == 0u
                   && e.prim_kind != PRIM_SPHERE)) {
        // A point uniform over the shape's area, as the surface a ray finds there: its
        // front side follows the vertex normals where a mesh has them (as in Mitsuba
        // and Nori), so a mirroring to_world does not turn a light around.
        // Its uvs only for a textured emitter's radiance (a scene without them reads
        // no vertex of a mesh light whose normals agree with its faces).
        Surface ls = emitter_area_point_as(e, u, TEXTURE_USES(TEXTURE_FEATURE_AREA));
        vec3 y = ls.p;
        vec3 ng = ls.ng;
        vec3 d = y - x;
        float d2 = dot(d, d);
        s.dist = sqrt(d2);
        s.wi = d / s.dist;
        float cos_light = -dot(ng, s.wi);
        if (cos_light <= 0.0 || d2 == 0.0) return s;
        s.Le = emitter_area_radiance(e, ng, s.wi, ls.uv);
        // Area density 1/area, to solid angle: d² / cos.
        s.pdf = pmf * d2 / (e.area * cos_light);
    } else if (EMITTER_HAS(EMITTER_KIND_BIT_SPHERE_AREA)) {
        // A sphere: directions uniform in the cone it subtends.
        float one_minus_cos_max = emitter_sphere_cone(x, e.position, e.radius);
        if (one_minus_cos_max <= 0.0) return s; // inside the light: it emits outwards
        vec3 wc = normalize(e.position - x);
        s.wi = frame_to_world(wc, warp_uniform_cone(u, one_minus_cos_max));
        float t;
        if (!intersect_sphere(x, s.wi, e.position, e.radius, 0.0, EMITTER_INFINITY, t)) {
            t = dot(e.position - x, s.wi); // grazing the rim: the closest approach
        }
        s.dist = t;
        s.Le = e.radiance;
        if (TEXTURE_USES(TEXTURE_FEATURE_AREA) && e.texture != 0u) {
            s.Le *= texture_eval(e.texture, surface_at(e.prim, 0.0, 0.0, x, s.wi, t).uv);
        }
        s.pdf = pmf * warp_uniform_cone_pdf(one_minus_cos_max);
    }
    return s;
}

EmitterSample emitter_sample(vec3 x, vec2 u) { return emitter_sample_env(x, u, false, vec3(0.0)); }

// How far a shadow ray for sample es may go from `origin` (the shading point x moved off
// its surface) along es.wi: to the sampled point, short by Mitsuba's ShadowEpsilon
// (~1e-3 of the distance). For a sphere light the end is where the ray from `origin`
// itself first meets the sphere: near the rim of the cone, the line through the offset
// origin parallel to es.wi meets the sphere before the point sampled from x (by up to
// sqrt(2 r |offset|)), and a shadow ray to that point would find the light occluding
// itself (0.07% of a near sphere's light: tests/sphere_light_closed_form.rs).
float emitter_shadow_tmax(EmitterSample es, vec3 x, vec3 origin) {
    if (isinf(es.dist)) return es.dist;
    float t = length(x + es.wi * es.dist - origin);
    if (EMITTER_HAS(EMITTER_KIND_BIT_SPHERE_AREA)) {
        EmitterRecord e = emitter_load(es.emitter);
        float ts;
        if (e.kind == EMITTER_AREA && e.tri_count == 0u && e.prim_kind == PRIM_SPHERE && !emitter_texture_sampled(e)
            && intersect_sphere(origin, es.wi, e.position, e.radius, 0.0, EMITTER_INFINITY, ts)) {
            t = min(t, ts);
        }
    }
    return t * (1.0 - 1e-3);
}

// Density with which emitter_sample, called at x_prev, picks the point at distance t
// along the unit direction d where a ray hit area emitter `index` (geometric normal ng
// and surface uv there).
float emitter_pdf_hit(uint index, vec3 x_prev, vec3 d, float t, vec3 ng, vec2 uv) {
    EmitterRecord e = emitter_load(index);
    float pmf = emitter_choice_pmf(index);
    if (emitter_texture_sampled(e)) {
        float cos_light = abs(dot(ng, d));
        return cos_light > 0.0 ? pmf * emitter_texture_pdf_area(e, uv) * t * t / cos_light : 0.0;
    }
    if (!EMITTER_HAS(EMITTER_KIND_BIT_SPHERE_AREA) || e.tri_count > 0u || e.prim_kind != PRIM_SPHERE) {
        float cos_light = abs(dot(ng, d));
        return cos_light > 0.0 ? pmf * t * t / (e.area * cos_light) : 0.0;
    }
    float one_minus_cos_max = emitter_sphere_cone(x_prev, e.position, e.radius);
    return one_minus_cos_max > 0.0 ? pmf * warp_uniform_cone_pdf(one_minus_cos_max) : 0.0;
}

// Density with which emitter_sample picks direction d towards the environment.
float emitter_pdf_env(vec3 d) {
    EmitterRecord e = emitter_load(frame.env_emitter);
    float pmf = emitter_choice_pmf(frame.env_emitter);
    if (TEXTURE_USES(TEXTURE_FEATURE_ENVMAP) && e.kind == EMITTER_ENVMAP) return pmf * envmap_pdf(e, d);
    return pmf * INV_FOUR_PI;
}

#endif
