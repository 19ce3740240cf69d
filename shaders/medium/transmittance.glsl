// Transmittance of a shadow ray through media and null surfaces: the ray passes every
// null surface (switching medium there as Mitsuba's target_medium does) and is blocked
// by any other; each medium segment contributes its transmittance (medium.glsl). With
// THIN_NULL (volumetric integrators), a thin dielectric without emission is passed too,
// attenuated by its null transmission (1 - R') specular_transmittance, as Mitsuba's
// volpath weighs shadow rays by eval_null_transmission.
// Needs wavefront.glsl, scene_bindings.glsl, bvh.glsl, surface.glsl, medium.glsl,
// bsdf_textured.glsl.
#ifndef TRANSMITTANCE_GLSL
#define TRANSMITTANCE_GLSL

#include "medium/medium.glsl"
#include "bsdf/fresnel.glsl"
#include "bsdf/mask_crossing.glsl"

#ifndef THIN_NULL
#define THIN_NULL false
#endif
// The bounce of the shadow rays (first_bounce.comp defines its own).
#ifndef PATH_DEPTH
#define PATH_DEPTH push.depth
#endif

// TRANSMITTANCE_DEFER (a bool constant): only the shadow ray's first traversal runs.
// Where the ray passes more surfaces than it found, transmittance_shadow_from sets
// transmittance_deferred, leaves in transmittance_rest the rest of the ray (from where
// it stopped, its contribution times the transmittance so far) and in
// transmittance_rest_draws the random numbers its tracking drew, and returns 0: the
// kernel leaves the rest to its full twin (deferral.glsl), which goes on with the
// next of those numbers: the same result as one traversal loop, but for the rounding
// of the contribution's product.
#ifndef TRANSMITTANCE_DEFER
#define TRANSMITTANCE_DEFER false
#endif
bool transmittance_deferred = false;
ShadowItem transmittance_rest;
uint transmittance_rest_draws;

// Surfaces one shadow ray may pass before it counts as blocked.
#define TRANSMITTANCE_MAX_CROSSINGS 64u

// The transmittance of shadow ray s of the path at `pixel` and `sample_index` (whose
// numbers draw its tracking's random numbers), `draws` of them drawn already (the rest
// of a deferred ray; 0 for a whole one).
vec3 transmittance_shadow_from(ShadowItem s, uint pixel, uint sample_index, uint draws) {
    MediumRng rng = medium_rng(pixel, sample_index, PATH_DEPTH, 1u, frame.seed);
    rng.n = draws;
    vec3 T = vec3(1.0);
    vec3 o = s.origin;
    uint medium = s.medium;
    float remaining = s.tmax;
    // Each traversal finds the two nearest surfaces (bvh_closest_two): a ray that passes
    // the first goes on to the second without tracing again where it may
    // (bvh_second_goes_on). A shadow ray out of a medium cube crosses its boundary and
    // meets nothing else: one traversal instead of two.
    Hit next;
    bool have_next = false;
    // Deferring, the one traversal runs before the loop, which then holds none.
    Hit first;
    if (TRANSMITTANCE_DEFER) first = bvh_closest_two(o, s.dir, 0.0, remaining, next);
    // Whether the ray got out (else it was blocked, or passed too many surfaces). One
    // return, at the end (medium.glsl says why).
    bool through = false;
    for (uint crossing = 0u; crossing < TRANSMITTANCE_MAX_CROSSINGS; crossing++) {
        Hit h;
        if (TRANSMITTANCE_DEFER && crossing == 0u) {
            h = first;
        } else if (have_next) {
            h = next;
        } else if (TRANSMITTANCE_DEFER) {
            transmittance_deferred = true;
            transmittance_rest = ShadowItem(o, s.path, s.dir, remaining, s.contribution * T, medium);
            transmittance_rest_draws = rng.n;
            break;
        } else {
            h = bvh_closest_two(o, s.dir, 0.0, remaining, next);
        }
        ShapeRecord shape;
        Prim hp;
        bool thin = false;
        bool masked = false;
        uint mask_cross = MASK_CROSSING_NONE;
        if (h.prim != NONE) {
            hp = prim_load(instance_prim(h.prim));
            shape = shape_load(hp.shape);
            thin = THIN_NULL && (shape.flags & SHAPE_THIN_DIELECTRIC) != 0u && shape.emitter == NONE;
            // A mask (THIN_NULL too) lets 1 - opacity through (Mitsuba's
            // eval_null_transmission).
            mask_cross = THIN_NULL && !thin && (shape.flags & SHAPE_NULL_BSDF) == 0u && shape.emitter == NONE
                ? bsdf_mask_crossing(shape.bsdf) : MASK_CROSSING_NONE;
            masked = mask_cross != MASK_CROSSING_NONE;
            // An opaque surface blocks the ray whatever the media before it.
            if ((shape.flags & SHAPE_NULL_BSDF) == 0u && !thin && !masked) break;
        }
        if (medium != NONE) {
            T *= medium_transmittance(medium, o, s.dir, h.prim == NONE ? remaining : h.t, rng);
            if (!any(greaterThan(T, vec3(0.0)))) break;
        }
        if (h.prim == NONE) {
            through = true;
            break;
        }
        Surface sf = surface_at_as(h.prim, h.u, h.v, o, s.dir, h.t, THIN_NULL);
        if (masked) {
            // A tree: its pass-throughs' weight, none below a bump map (mask_crossing.glsl).
            T *= mask_cross == MASK_CROSSING_ROOT ? 1.0 - bsdf_mask_opacity(shape.bsdf, sf.uv)
                                                : bsdf_null_weight(shape.bsdf, sf.uv);
            if (!any(greaterThan(T, vec3(0.0)))) break;
        }
        if (thin) {
            BsdfRecord b = bsdf_textured(bsdf_load(shape.bsdf), sf.uv);
            T *= b.transmittance * (1.0 - fresnel_thin_slab(dot(s.dir, sf.ns), b.eta));
            if (!any(greaterThan(T, vec3(0.0)))) break;
        }
        medium = medium_after(sf.shape, medium, s.dir, sf.ng);
        vec3 next_o = surface_spawn_origin(sf, dot(s.dir, sf.ng) > 0.0 ? sf.ng : -sf.ng);
        float advance = dot(next_o - o, s.dir);
        remaining = max(remaining - advance, 0.0);
        o = next_o;
        // The second surface of the last traversal, unless it was just used.
        have_next = !have_next && bvh_second_goes_on(hp, advance, remaining, next);
    }
    return through ? T : vec3(0.0);
}

// What reaches the end of shadow ray s: its transmittance through media and null
// surfaces where the scene has them (MEDIA_ENABLED; transmittance_shadow_from), else 1 or 0
// by whether anything blocks it. shadow.comp and first_bounce.comp add
// s.contribution times it to the path's radiance where it is not 0. `draws`: as in
// transmittance_shadow_from.
vec3 shadow_transmittance_from(ShadowItem s, uint pixel, uint sample_index, uint draws) {
#if defined(MEDIA_ENABLED)
    if (MEDIA_ENABLED) return transmittance_shadow_from(s, pixel, sample_index, draws);
#endif
    return bvh_any(s.origin, s.dir, 0.0, s.tmax) ? vec3(0.0) : vec3(1.0);
}

vec3 shadow_transmittance(ShadowItem s, uint pixel, uint sample_index) {
    return shadow_transmittance_from(s, pixel, sample_index, 0u);
}

#endif
