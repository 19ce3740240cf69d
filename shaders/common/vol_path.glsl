// Volumetric path tracing: the medium stage of a path vertex, run in shade before
// path_shade (Mitsuba's volpath; Pharr, Jakob, Humphreys, PBR 4th ed., sec. 14.2).
// The ray of a path is followed through its medium and through every null surface
// (index-matched medium boundaries) it meets, until it scatters in a medium, is
// absorbed, reaches a surface with a BSDF, or escapes; the last two go on to
// path_shade with the distance measured from the ray's origin (the last scattering
// vertex), so MIS weights of emitters found behind null surfaces stay right.
//   vol_path_simple: phase and BSDF sampling only.
//   vol_path_mis   : emitter sampling with transmittance at medium and surface
//                    vertices, balance heuristic against phase and BSDF sampling.
// Needs wavefront.glsl, scene_bindings.glsl, bvh.glsl, emitter.glsl, path.glsl and
// medium.glsl.
#ifndef VOL_PATH_GLSL
#define VOL_PATH_GLSL

#include "phase.glsl"
#include "medium.glsl"

// Null surfaces one ray may cross before the path is dropped (a guard against
// degenerate geometry; a closed boundary is crossed twice).
#define VOL_PATH_MAX_CROSSINGS 64u

// A real scattering event in medium `medium` at p for the path of ray r (its state
// `path` with the throughput up to p): emitter sampling through a shadow ray
// (vol_path_mis, where the medium asks for it), then phase sampling for the next ray.
void vol_path_scatter(uint integrator, RayItem r, PathState path, uint medium, vec3 p) {
    uint depth = push.depth;
    // This vertex ends segment depth + 1; a longer path must fit in max_depth.
    if (depth + 2u > frame.max_depth) return;
    MediumRecord m = media[medium];
    vec3 wo = -r.dir;
    bool nee = integrator == INTEGRATOR_VOL_PATH_MIS && (m.flags & MEDIUM_SAMPLE_EMITTERS) != 0u;
    if (nee) {
        vec4 u = rng_4d(path.pixel, path.sample_index, rng_dim_bounce(depth, 0u), frame.seed);
        EmitterSample es = emitter_sample(p, u);
        if (es.pdf > 0.0 && any(greaterThan(es.Le, vec3(0.0)))) {
            float ph = phase_eval(m.g, wo, es.wi);
            float w = es.delta ? 1.0 : mis_balance(es.pdf, ph);
            float tmax = isinf(es.dist) ? es.dist : es.dist * (1.0 - 1e-4);
            queue_push_shadow_in(medium, p, r.path, es.wi, tmax, path.throughput * es.Le * (ph * w / es.pdf));
        }
    }
    vec4 u = rng_4d(path.pixel, path.sample_index, rng_dim_bounce(depth, 1u), frame.seed);
    PhaseSample ps = phase_sample(m.g, wo, u.xy);
    // The phase function is sampled exactly: its weight is 1.
    vec3 throughput = path.throughput;
    if (depth + 1u >= frame.rr_depth) {
        float q = min(max(throughput.x, max(throughput.y, throughput.z)), 0.99);
        if (u.w >= q) return;
        throughput /= q;
    }
    paths[r.path].throughput = throughput;
    paths[r.path].bsdf_pdf = ps.pdf;
    // Without emitter sampling here, emitters the next ray finds count in full.
    paths[r.path].flags = nee ? 0u : PATH_DELTA;
    paths[r.path].medium = medium;
    queue_push_ray(p, r.path, ps.wi, EMITTER_INFINITY);
}

// The medium stage of ray r with closest hit h. Returns true when path_shade should
// shade (r, h): h is then the surface the ray reaches (or a miss), h.t its distance
// from r.origin, and the path's throughput and medium are updated. Returns false when
// the path scattered in a medium (handled here) or ended. Integrators that are not
// volumetric ignore media and only pass through null surfaces.
bool vol_path_traverse(uint integrator, RayItem r, inout HitItem h) {
    PathState path = paths[r.path];
    bool vol = integrator_is_volumetric(integrator);
    uint medium = vol ? path.medium : NONE;
    MediumRng rng = medium_rng(path.pixel, path.sample_index, push.depth, 0u, frame.seed);
    vec3 throughput = path.throughput;
    vec3 o = r.origin;
    float t_base = 0.0; // distance from r.origin to o
    for (uint crossing = 0u;; crossing++) {
        float seg = h.prim == NONE ? r.tmax - t_base : h.t;
        if (medium != NONE) {
            MediumEvent ev = medium_sample(medium, o, r.dir, seg, rng);
            throughput *= ev.weight;
            if (ev.scattered) {
                path.throughput = throughput;
                vol_path_scatter(integrator, r, path, medium, o + ev.t * r.dir);
                return false;
            }
            if (!any(greaterThan(throughput, vec3(0.0)))) return false;
        }
        if (h.prim == NONE) break;
        Surface s = surface_at(h.prim, h.u, h.v, o, r.dir, h.t);
        if ((shapes[s.shape].flags & SHAPE_NULL_BSDF) == 0u) break;
        if (crossing >= VOL_PATH_MAX_CROSSINGS) return false;
        if (vol) medium = medium_after(s.shape, medium, r.dir, s.ng);
        vec3 next = surface_spawn_origin(s, dot(r.dir, s.ng) > 0.0 ? s.ng : -s.ng);
        t_base += dot(next - o, r.dir);
        o = next;
        Hit nh = bvh_closest(o, r.dir, 0.0, max(r.tmax - t_base, 0.0));
        h = HitItem(nh.t, nh.u, nh.v, nh.prim);
    }
    if (h.prim != NONE) h.t += t_base;
    paths[r.path].throughput = throughput;
    paths[r.path].medium = medium;
    return true;
}

#endif
