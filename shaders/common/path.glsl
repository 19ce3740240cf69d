// One path vertex of the direct-lighting and path-tracing integrators: emission found
// by the ray (weighted by MIS), emitter sampling through a shadow ray, and BSDF
// sampling for the next ray, with Russian roulette. Which of these run is fixed by the
// integrator (specialization constants), so absent strategies compile away:
//   direct_ems  : emitter sampling          direct_mats : BSDF sampling
//   direct_mis  : both, balance heuristic    path_mats   : BSDF sampling, any depth
//   path_mis    : both at every vertex, power or balance heuristic (Veach 1997, ch. 9)
//   vol_path_simple, vol_path_mis, single_scatter: as path_mats, path_mis and
//                 direct_mis at surfaces; their
//                 medium stage runs first (vol_path.glsl), and the rays they spawn
//                 carry the medium they enter.
// Needs wavefront.glsl, scene_bindings.glsl, surface.glsl, emitter.glsl, bsdf.glsl.
#ifndef PATH_GLSL
#define PATH_GLSL

#include "integrator.glsl"
#include "frame.glsl"
#include "rng.glsl"
#include "queue.glsl"
#include "bsdf_textured.glsl"
#include "normal_map.glsl"

// MIS weight of a strategy with density a against one with density b (Veach 1997,
// sec. 9.2): the balance heuristic a / (a + b), or with MIS_POWER (a bool constant
// defined before including this file) the power heuristic a² / (a² + b²).
#ifndef MIS_POWER
#define MIS_POWER false
#endif
float mis_weight(float a, float b) {
    if (MIS_POWER) {
        // a, b may exceed sqrt(FLT_MAX) (delta-like lobes): scale by the larger one.
        float m = max(a, b);
        if (!(m > 0.0)) return 0.0;
        float x = a / m;
        float y = b / m;
        return x * x / (x * x + y * y);
    }
    return a / (a + b);
}

// The medium a ray leaving surface `shape` along d enters, for volumetric integrators
// in scenes with media (MEDIA_ENABLED, set where medium.glsl is included); NONE
// otherwise.
uint path_medium_after(uint integrator, uint shape, uint current, vec3 d, vec3 ng) {
#ifdef MEDIUM_GLSL
    if (MEDIA_ENABLED && integrator_is_volumetric(integrator)) {
        return medium_after(shape, current, d, ng);
    }
#endif
    return NONE;
}

// Shades ray r (path vertex number push.depth + 1) with its hit h; `path` is the
// state of r's path (path_load(r.path), as the medium stage may have left it: a path
// state written in this dispatch is passed on, never read back through the texel view).
void path_shade(uint integrator, RayItem r, HitItem h, PathState path) {
    bool ems = integrator == INTEGRATOR_DIRECT_EMS || integrator == INTEGRATOR_DIRECT_MIS
        || integrator == INTEGRATOR_PATH_MIS || integrator == INTEGRATOR_VOL_PATH_MIS
        || integrator_is_single_scatter(integrator);
    bool mats = integrator != INTEGRATOR_DIRECT_EMS;
    bool mis = integrator == INTEGRATOR_DIRECT_MIS || integrator == INTEGRATOR_PATH_MIS
        || integrator == INTEGRATOR_VOL_PATH_MIS || integrator_is_single_scatter(integrator);
    bool path_tracer = integrator == INTEGRATOR_PATH_MATS || integrator == INTEGRATOR_PATH_MIS
        || integrator_is_volumetric(integrator);

    uint depth = push.depth;
    // Emission found by this ray counts for camera rays (unless hidden) and for rays
    // that BSDF sampling chose; with MIS it is weighted against emitter sampling,
    // except after a delta lobe, which emitter sampling cannot reproduce.
    bool count_emission = depth == 0u ? frame.hide_emitters == 0u : mats;
    bool weigh = depth > 0u && mis && (path.flags & PATH_DELTA) == 0u;

    if (h.prim == NONE) {
        if ((EMITTER_HAS(EMITTER_CONSTANT) || EMITTER_HAS(EMITTER_ENVMAP)) && count_emission
            && frame.env_emitter != NONE) {
            float w = weigh ? mis_weight(path.bsdf_pdf, emitter_pdf_env(r.dir)) : 1.0;
            path.radiance += path.throughput * emitter_env_radiance(emitter_load(frame.env_emitter), r.dir) * w;
            path_store_radiance(r.path, path);
        }
        return;
    }

    Surface s = surface_at(h.prim, h.u, h.v, r.origin, r.dir, h.t);
    ShapeRecord shape = shape_load(s.shape);
    if (count_emission && shape.emitter != NONE) {
        vec3 Le = emitter_area_radiance(emitter_load(shape.emitter), s.ng, r.dir, s.uv);
        float w = weigh ? mis_weight(path.bsdf_pdf, emitter_pdf_hit(shape.emitter, r.origin, r.dir, h.t, s.ng)) : 1.0;
        path.radiance += path.throughput * Le * w;
        path_store_radiance(r.path, path);
    }

    // A longer path must fit in max_depth segments (this vertex ends segment depth+1).
    if (depth + 2u > frame.max_depth) return;

    BsdfRecord bsdf = bsdf_textured(bsdf_load(shape.bsdf), s.uv);
    // A normal map (normal_map.glsl) replaces the shading normal and weighs the light
    // of each direction wi by normal_map_weight: 0 on different sides of the old and
    // the new normal, else its shadowing term. A twosided record mirrors the old
    // normal towards the viewer there, so the nested model is one-sided, as in
    // Mitsuba's twosided around a normalmap.
    bool mapped = TEXTURE_USES(TEXTURE_FEATURE_NORMALMAP) && bsdf.normal_map != 0u;
    NormalMapFrame nm;
    if (mapped) {
        nm = normal_map_frame(bsdf, s, -r.dir);
        s.ns = nm.n;
        bsdf.flags &= ~BSDF_TWOSIDED;
    }
    vec3 wo = frame_to_local(s.ns, -r.dir);

    if (ems && !bsdf_is_delta(bsdf)) {
        vec4 u = rng_4d(path.pixel, path.sample_index, rng_dim_bounce(depth, 0u), frame.seed);
        EmitterSample es = emitter_sample(s.p, u);
        if (es.pdf > 0.0 && any(greaterThan(es.Le, vec3(0.0)))) {
            vec3 wi = frame_to_local(s.ns, es.wi);
            float m = mapped ? normal_map_weight(nm, es.wi) : 1.0;
            vec3 f = m > 0.0 ? m * bsdf_eval(bsdf, wo, wi, s.uv) : vec3(0.0);
            if (any(greaterThan(f, vec3(0.0)))) {
                float w = (mis && !es.delta) ? mis_weight(es.pdf, bsdf_pdf(bsdf, wo, wi, s.uv)) : 1.0;
                vec3 origin = surface_spawn_origin(s, dot(es.wi, s.ng) > 0.0 ? s.ng : -s.ng);
                // Stop short of the light's own surface (PBR's shadow epsilon).
                float tmax = isinf(es.dist) ? es.dist : length(s.p + es.wi * es.dist - origin) * (1.0 - 1e-4);
                uint medium = path_medium_after(integrator, s.shape, path.medium, es.wi, s.ng);
                queue_push_shadow_in(medium, origin, r.path, es.wi, tmax, path.throughput * f * es.Le * (w / es.pdf));
            }
        }
    }

    if (mats) {
        vec4 u = rng_4d(path.pixel, path.sample_index, rng_dim_bounce(depth, 1u), frame.seed);
        // The medium stage already chose a thin dielectric's reflection (probability
        // R', vol_path_traverse): u.x = 0 selects that lobe, weight f/P = specular.
        if ((path.flags & PATH_THIN_REFLECT) != 0u) u.x = 0.0;
        BsdfSample bs = bsdf_sample(bsdf, wo, u.xyz, s.uv);
        vec3 wi = frame_to_world(s.ns, bs.wi);
        vec3 throughput = path.throughput * bs.weight * (mapped ? normal_map_weight(nm, wi) : 1.0);
        if (!any(greaterThan(throughput, vec3(0.0)))) return;
        // Refraction scaled the radiance by (η_i/η_t)² (dielectrics, rough or smooth;
        // not a thin dielectric's undeflected transmission).
        if ((bs.flags & (BSDF_FLAG_TRANSMISSION | BSDF_FLAG_NULL)) == BSDF_FLAG_TRANSMISSION) {
            path.eta_scale *= wo.z > 0.0 ? bsdf.eta * bsdf.eta : 1.0 / (bsdf.eta * bsdf.eta);
        }
        // Russian roulette: survive with probability min(max throughput, 0.99), the
        // throughput taken without the refractions' radiance scaling.
        if (path_tracer && depth + 1u >= frame.rr_depth) {
            vec3 rr = throughput * path.eta_scale;
            float q = min(max(rr.x, max(rr.y, rr.z)), 0.99);
            if (u.w >= q) return;
            throughput /= q;
        }
        path.throughput = throughput;
        path.bsdf_pdf = bs.pdf;
        path.flags = (bs.flags & BSDF_FLAG_DELTA) != 0u ? PATH_DELTA : 0u;
        path.medium = path_medium_after(integrator, s.shape, path.medium, wi, s.ng);
        path_store_bounce(r.path, path); // the radiance word is stored where it changed
        queue_push_ray(surface_spawn_origin(s, dot(wi, s.ng) > 0.0 ? s.ng : -s.ng), r.path, wi, EMITTER_INFINITY);
    }
}

#endif
