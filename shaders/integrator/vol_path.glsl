// Volumetric path tracing: the medium stage of a path vertex, run in shade before
// path_shade (Mitsuba's volpath; Pharr, Jakob, Humphreys, PBR 4th ed., sec. 14.2).
// The ray of a path is followed through its medium and through every null surface
// (index-matched medium boundaries) it meets, until it scatters in a medium, is
// absorbed, reaches a surface with a BSDF, or escapes. All but absorption go on to
// path_shade: a scattering event as a medium vertex (PathVertex), a surface or an
// escape with the distance measured from the ray's origin (the last scattering
// vertex), so MIS weights of emitters found behind null surfaces stay right.
//   vol_path_simple: phase and BSDF sampling only.
//   vol_path_mis   : emitter sampling with transmittance at medium and surface
//                    vertices, balance heuristic against phase and BSDF sampling.
//   single_scatter : one vertex: in a medium, emitter sampling only (it samples every
//                    kind of light, so it is the whole in-scattered estimate); at a
//                    surface, direct_mis. Distances on camera rays by free flight, or
//                    equiangular towards the light (vol_path_equiangular).
// Needs wavefront.glsl, scene_bindings.glsl, bvh.glsl, emitter.glsl, path.glsl (its
// PATH_DEPTH: the bounce) and medium.glsl.
#ifndef VOL_PATH_GLSL
#define VOL_PATH_GLSL

#include "medium/phase.glsl"
#include "medium/medium.glsl"
#include "medium/equiangular.glsl"
#include "bsdf/mask_crossing.glsl"

// VOL_PATH_DEFER (a bool constant): the stage never traces. Where a ray passes more
// surfaces than its traversal found, vol_path_traverse sets vol_path_deferred and
// returns false, having changed nothing: the kernel leaves the ray to its full twin
// (deferral.glsl), which runs the stage again from the start with the trace.
#ifndef VOL_PATH_DEFER
#define VOL_PATH_DEFER false
#endif
bool vol_path_deferred = false;

// Null surfaces one ray may cross before the path is dropped (a guard against
// degenerate geometry; a closed boundary is crossed twice).
#define VOL_PATH_MAX_CROSSINGS 64u

// Thin dielectrics are null crossings with probability 1 - R' (set where the
// integrator is volumetric and the scene has them; see vol_path_traverse).
#ifndef THIN_NULL
#define THIN_NULL false
#endif

// Scattering coefficient σs = albedo σt of medium m at world point p.
vec3 vol_path_sigma_s(MediumRecord m, vec3 p) {
    if (MEDIUM_IS_HOMOGENEOUS(m)) return medium_albedo(m, p) * m.sigma_t;
    vec3 pl = (m.world_to_grid * vec4(p, 1.0)).xyz;
    return medium_albedo(m, p) * medium_grid_sigma_t(m, pl);
}

// Outcomes of vol_path_equiangular.
#define VOL_PATH_BEYOND 0
#define VOL_PATH_SCATTERED 1
#define VOL_PATH_DEAD 2

// single_scatter with equiangular sampling, camera ray r in medium `medium` over
// [0, seg) from o (distance t_base from r.origin). One sample chooses between the
// medium segment (probability p_med) and what lies beyond it:
// - beyond: the throughput times the segment's transmittance / (1 - p_med);
//   returns VOL_PATH_BEYOND (go on to the surface);
// - medium: a light point y is chosen (emitter_sample from o), t equiangular towards
//   y (Kulla and Fajardo 2012), weight T(0, t) σs(t) / (pdf(t) p_med); returns
//   VOL_PATH_SCATTERED with the medium vertex at o + t d in v and its throughput in
//   path. Emitter sampling there (path_shade) uses the same numbers, which pick the
//   same point y of a point, spot or mesh light (the pair (y, t) is sampled jointly);
//   a sphere light or the environment is sampled afresh.
// p_med = 1 - avg transmittance of a homogeneous segment (clamped to [0.05, 0.95]),
// 1/2 for grids, 1 when nothing lies beyond.
int vol_path_equiangular(uint integrator, RayItem r, inout PathState path, uint medium, vec3 o,
                         float seg, inout vec3 throughput, inout MediumRng rng, out PathVertex v) {
    v = path_vertex_surface();
    if (!(seg > 0.0)) return VOL_PATH_BEYOND;
    MediumRecord m = medium_load(medium);
    vec3 T_seg = isinf(seg) ? vec3(0.0) : medium_transmittance(medium, o, r.dir, seg, rng);
    float p_med = isinf(seg) ? 1.0
        : (m.kind == MEDIUM_HOMOGENEOUS ? clamp(1.0 - medium_avg(T_seg), 0.05, 0.95) : 0.5);
    vec4 u = medium_rng_next(rng);
    if (u.x >= p_med) {
        throughput *= T_seg / (1.0 - p_med);
        return VOL_PATH_BEYOND;
    }
    uint depth = PATH_DEPTH;
    vec2 u_light = sample_2d(path.pixel, path.sample_index, rng_dim_bounce(depth, RNG_SLOT_EMITTER));
    EmitterSample es0 = emitter_sample(o, u_light);
    EmitterRecord e = emitter_load(es0.emitter == NONE ? 0u : es0.emitter);
    bool same_point = es0.emitter != NONE
        && (e.kind == EMITTER_POINT || e.kind == EMITTER_SPOT || e.kind == EMITTER_PROJECTOR
            || (e.kind == EMITTER_AREA && e.tri_count > 0u));
    vec3 c = o + es0.wi * min(es0.dist, 1e6);
    Equiangular eq = equiangular_setup(o, r.dir, c, 0.0, seg);
    float t = equiangular_sample(eq, 0.0, seg, u.y);
    float pdf = equiangular_pdf(eq, t);
    if (!(pdf > 0.0) || isinf(pdf)) return VOL_PATH_DEAD;
    vec3 x = o + t * r.dir;
    vec3 sigma_s = vol_path_sigma_s(m, x);
    vec3 Tr = medium_transmittance(medium, o, r.dir, t, rng);
    path.throughput = throughput * Tr * sigma_s / (pdf * p_med);
    path.medium = medium;
    v = PathVertex(medium, x, same_point ? RNG_SLOT_EMITTER : RNG_SLOT_EMITTER2);
    return VOL_PATH_SCATTERED;
}

// The medium stage of ray r with closest hit h, second-nearest hit `second` (intersect
// keeps it: bvh_closest_two) and path state `path`. Returns true
// when path_shade should shade vertex v: a scattering event in a medium, or the
// surface h the ray reaches (or a miss), h.t then its distance from r.origin; the
// path's throughput and medium are updated in `path` (for path_shade to store).
// Returns false when the path ended (absorbed, or stopped by the guards below).
// Integrators that are not volumetric ignore media and only pass through null
// surfaces.
// A thin dielectric (THIN_NULL) is crossed as Mitsuba's volpath crosses its null lobe:
// with probability 1 - R' the ray goes on undeflected, weight specular_transmittance,
// with no path vertex (depth, MIS state and Russian roulette unchanged); otherwise the
// stage ends there with PATH_THIN_REFLECT set, and path_shade takes the reflection
// lobe (probability R', weight specular_reflectance). A thin dielectric that emits
// light always goes to path_shade (its emission is counted there), which samples
// both lobes as an ordinary BSDF.
// A ray that passes a null surface goes on to the second-nearest surface of the same
// traversal without tracing again where it may (bvh_second_goes_on): a ray leaving a
// medium cube crosses its boundary and reaches what lies behind it without a trace.
bool vol_path_traverse(uint integrator, RayItem r, inout HitItem h, HitItem second,
                       inout PathState path, out PathVertex v) {
    v = path_vertex_surface();
    bool vol = integrator_is_volumetric(integrator);
    uint medium = vol ? path.medium : NONE;
    MediumRng rng = medium_rng(path.pixel, path.sample_index, PATH_DEPTH, 0u, frame.seed);
    if (vol) {
        medium_rng_first(rng, sample_2d(path.pixel, path.sample_index, rng_dim_bounce(PATH_DEPTH, RNG_SLOT_MEDIUM)));
    }
    vec3 throughput = path.throughput;
    vec3 o = r.origin;
    float t_base = 0.0; // distance from r.origin to o
    // A real scattering event ends the loop (path_shade shades it).
    bool scattered = false;
    vec3 scatter_p;
    // The surface after h (measured from o), known while have_next.
    Hit next = Hit(second.t, second.u, second.v, second.prim);
    bool have_next = true;
    // The path goes on (else it was absorbed or stopped); equiangular: vol_path_equiangular
    // left its medium vertex in path and v. One return, at the end (medium.glsl says why).
    bool alive = true;
    bool equiangular = false;
    for (uint crossing = 0u;; crossing++) {
        float seg = h.prim == NONE ? r.tmax - t_base : h.t;
        if (medium != NONE && integrator == INTEGRATOR_SINGLE_EQUIANGULAR && PATH_DEPTH == 0u) {
            int e = vol_path_equiangular(integrator, r, path, medium, o, seg, throughput, rng, v);
            equiangular = e == VOL_PATH_SCATTERED;
            alive = e != VOL_PATH_DEAD && (equiangular || any(greaterThan(throughput, vec3(0.0))));
            if (equiangular || !alive) break;
        } else if (medium != NONE) {
            MediumEvent ev = medium_sample(medium, o, r.dir, seg, rng);
            throughput *= ev.weight;
            if (ev.scattered) {
                scattered = true;
                scatter_p = o + ev.t * r.dir;
                break;
            }
            alive = any(greaterThan(throughput, vec3(0.0)));
            if (!alive) break;
        }
        if (h.prim == NONE) break;
        Prim hp = prim_load(instance_prim(h.prim));
        ShapeRecord shape = shape_load(hp.shape);
        bool thin = THIN_NULL && (shape.flags & SHAPE_THIN_DIELECTRIC) != 0u && shape.emitter == NONE;
        // A mask (THIN_NULL too) is crossed as Mitsuba's volpath crosses its null lobe:
        // with probability 1 - opacity, weight 1, no vertex; otherwise the stage ends
        // with PATH_THIN_REFLECT, and path_shade takes the masked BSDF alone.
        // A mask inside another composite: with the probability of its tree's
        // pass-throughs (mask_crossing.glsl).
        uint mask_cross = THIN_NULL && !thin && (shape.flags & SHAPE_NULL_BSDF) == 0u && shape.emitter == NONE
            ? bsdf_mask_crossing(shape.bsdf) : MASK_CROSSING_NONE;
        bool masked = mask_cross != MASK_CROSSING_NONE;
        // A surface with a BSDF ends the stage (path_shade computes its geometry).
        if ((shape.flags & SHAPE_NULL_BSDF) == 0u && !thin && !masked) break;
        Surface s = surface_at_as(h.prim, h.u, h.v, o, r.dir, h.t, THIN_NULL);
        if (masked) {
            // x: the probability of passing, y: its expected weight (below a bump map
            // the bump map's shadowing term, composite.glsl).
            bool root = mask_cross == MASK_CROSSING_ROOT;
            vec2 pass = root ? vec2(1.0) : bsdf_composite_null_pass(shape.bsdf, s, h.prim, vec2(h.u, h.v), r.dir);
            if (medium_rng_next(rng).x < (root ? bsdf_mask_opacity(shape.bsdf, s.uv) : 1.0 - pass.x)) {
                path.flags |= PATH_THIN_REFLECT;
                break;
            }
            if (!root) {
                throughput *= pass.y / pass.x;
                alive = any(greaterThan(throughput, vec3(0.0)));
                if (!alive) break;
            }
        }
        if (thin) {
            BsdfRecord b = bsdf_textured(bsdf_load(shape.bsdf), s.uv);
            if (medium_rng_next(rng).x < fresnel_thin_slab(dot(r.dir, s.ns), b.eta)) {
                path.flags |= PATH_THIN_REFLECT;
                break;
            }
            throughput *= b.transmittance;
            alive = any(greaterThan(throughput, vec3(0.0)));
            if (!alive) break;
        }
        alive = crossing < VOL_PATH_MAX_CROSSINGS;
        if (!alive) break;
        if (vol) medium = medium_after(s.shape, medium, r.dir, s.ng);
        vec3 next_o = surface_spawn_origin(s, dot(r.dir, s.ng) > 0.0 ? s.ng : -s.ng);
        float advance = dot(next_o - o, r.dir);
        t_base += advance;
        o = next_o;
        float remaining = max(r.tmax - t_base, 0.0);
        Hit nh;
        if (have_next && bvh_second_goes_on(hp, advance, remaining, next)) {
            nh = next;
            have_next = false;
        } else if (VOL_PATH_DEFER) {
            vol_path_deferred = true;
            alive = false;
            break;
        } else {
            nh = bvh_closest_two(o, r.dir, 0.0, remaining, next);
            have_next = true;
        }
        h = HitItem(nh.t, nh.u, nh.v, nh.prim);
    }
    if (alive && !equiangular) {
        path.throughput = throughput;
        path.medium = medium;
        if (scattered) {
            v = PathVertex(medium, scatter_p, RNG_SLOT_EMITTER);
        } else if (h.prim != NONE) {
            h.t += t_base;
        }
    }
    return alive;
}

#endif
