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

#include "integrator/integrator.glsl"
#include "sampling/frame.glsl"
#include "sampler/sampler_frame.glsl"
#include "queue/queue.glsl"
#include "queue/path_queues.glsl"
#include "bsdf/bsdf_textured.glsl"
#include "bsdf/normal_map.glsl"
#include "bsdf/composite.glsl"
#include "bsdf/mask_crossing.glsl"
#ifdef MEDIUM_GLSL
#include "medium/phase.glsl"
#endif

// MIS weight of a strategy with density a against one with density b (Veach 1997,
// sec. 9.2): the balance heuristic a / (a + b), or with MIS_POWER (a bool constant
// defined before including this file) the power heuristic a² / (a² + b²).
#ifndef MIS_POWER
#define MIS_POWER false
#endif
// SHADE_LAST (a bool constant defined before including this file: the `shade_last`
// kernel of shade.comp): every vertex shaded is the last one its path can reach
// (depth + 2 > max_depth), whose only light is the emission its ray found. Its
// BSDF, emitter sampling and continuation then compile away: llvmpipe would run
// their code for every lane though each lane returns before them.
#ifndef SHADE_LAST
#define SHADE_LAST false
#endif
// THIN_NULL (a bool constant likewise, vol_path.glsl): thin dielectrics and masks are
// null crossings of the medium stage.
#ifndef THIN_NULL
#define THIN_NULL false
#endif
// SHADE_RAYS (a uint constant likewise): the rays the kernel shades. SHADE_RAYS_ALL,
// every ray of the bounce's queue; SHADE_RAYS_HITS, those intersect found a surface
// for; SHADE_RAYS_MISSES, those that left the scene (partition.glsl).
// Partitioned, the other kind's code compiles away.
#define SHADE_RAYS_ALL 0u
#define SHADE_RAYS_HITS 1u
#define SHADE_RAYS_MISSES 2u
#ifndef SHADE_RAYS
#define SHADE_RAYS SHADE_RAYS_ALL
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

// The light that ray r of `path` finds at surface point s (at distance t) of emitter
// `emitter` (its record `light`, its texture's value `texel`), as the path adds it:
// through the path's throughput and, with `weigh`, the MIS weight of BSDF sampling
// against emitter sampling of that point.
vec3 path_emission_found(PathState path, RayItem r, float t, Surface s, uint emitter,
                         EmitterRecord light, vec3 texel, bool weigh) {
    vec3 Le = emitter_area_radiance_texel(light, s.ng, r.dir, texel);
    float w = weigh ? mis_weight(path.bsdf_pdf, emitter_pdf_hit(emitter, r.origin, r.dir, t, s.ng, s.uv)) : 1.0;
    return path.throughput * Le * w;
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

// What a path's ray reached, for path_shade: the surface of its hit (or nothing, on a
// miss), or, with medium != NONE, a real scattering event at p in that medium (the
// medium stage, vol_path.glsl). Emitter sampling there uses the numbers of bounce
// slot light_dim (RNG_SLOT_EMITTER, as at surfaces, unless equiangular sampling
// chose the light point with them and wants fresh ones: RNG_SLOT_EMITTER2).
struct PathVertex {
    uint medium;
    vec3 p;
    uint light_dim;
};

PathVertex path_vertex_surface() {
    return PathVertex(NONE, vec3(0.0), RNG_SLOT_EMITTER);
}

// For a film with alpha: marks path i covered (PATH_COVERED, in `path` and stored),
// as Mitsuba's integrators set `valid_ray`, once its camera ray (past null surfaces)
// found a surface with a BSDF or scattered in a medium; with max_depth 1, only when
// it sees an emitter. (generate marks every path covered where Mitsuba's path and
// volpath count a visible environment.) Called by shade at depth 0 with the medium
// stage's outcome.
void path_mark_covered(uint i, inout PathState path, HitItem h, PathVertex v) {
    bool covered = v.medium != NONE || h.prim != NONE;
    if (frame.max_depth <= 1u && v.medium == NONE && h.prim != NONE) {
        covered = frame.hide_emitters == 0u && shape_load(prim_load(instance_prim(h.prim)).shape).emitter != NONE;
    }
    if (!covered || (path.flags & PATH_COVERED) != 0u) return;
    path.flags |= PATH_COVERED;
    PathState stored = path;
    stored.flags &= ~PATH_THIN_REFLECT;
    path_keep_flags(i, stored);
}

// Shades path vertex v, reached by ray r (path vertex number PATH_DEPTH + 1) with hit
// h; `path` is the state of r's path (path_load(r.path), as the medium stage may have
// left it: a path state written in this dispatch is passed on, never read back
// through the texel view). At a surface: emission, emitter sampling against the BSDF
// and BSDF sampling; in a medium: emitter sampling against the phase function and
// phase sampling. Both kinds of vertex share one emitter-sampling step and one
// continuation step, each with its shadow or ray push: llvmpipe runs a branch's code
// whatever its lanes decide, so separate steps would cost every lane both.
// `max_depth` bounds the path's length in segments (frame.max_depth in path_shade; the
// photon mappers' camera paths end sooner, shaders/kernels/sppm_shade.comp).
void path_shade_to(uint integrator, RayItem r, HitItem h, PathState path, PathVertex v, uint max_depth) {
    bool single = integrator_is_single_scatter(integrator);
    bool ems = integrator_samples_emitters(integrator);
    bool mats = integrator != INTEGRATOR_DIRECT_EMS;
    bool mis = integrator_uses_mis(integrator);
    bool path_tracer = integrator == INTEGRATOR_PATH_MATS || integrator == INTEGRATOR_PATH_MIS
        || integrator_is_volumetric(integrator);

    uint depth = PATH_DEPTH;
    bool in_medium = false;
#ifdef MEDIUM_GLSL
    in_medium = MEDIA_ENABLED && v.medium != NONE;
    float g = 0.0;
    if (in_medium) {
        MediumRecord m = medium_load(v.medium);
        g = m.g;
        // Emitter sampling in a medium: vol_path_mis and single_scatter, where the
        // medium asks for it; a medium vertex of single_scatter ends its path.
        ems = (integrator == INTEGRATOR_VOL_PATH_MIS || single)
            && (m.flags & MEDIUM_SAMPLE_EMITTERS) != 0u;
        mats = !single;
    }
#endif
    // Emission found by this ray counts for camera rays (unless hidden) and for rays
    // that BSDF sampling chose; with MIS it is weighted against emitter sampling,
    // except after a delta lobe, which emitter sampling cannot reproduce.
    bool count_emission = depth == 0u ? frame.hide_emitters == 0u : mats;
    bool weigh = depth > 0u && mis && (path.flags & PATH_DELTA) == 0u;

    // A ray that left the scene sees the environment. Where the integrator samples
    // emitters in a scene with an environment map, its lookup (radiance and density
    // along r.dir) is the one of emitter sampling below, made for the sampled direction
    // at surface vertices (emitter_sample_env): llvmpipe runs both sides of a branch,
    // so two lookups would cost every lane both. The numbers are the same.
    bool miss = SHADE_RAYS == SHADE_RAYS_MISSES
        || (SHADE_RAYS == SHADE_RAYS_ALL && !in_medium && h.prim == NONE);
    bool env_seen = miss && (EMITTER_HAS(EMITTER_CONSTANT) || EMITTER_HAS(EMITTER_ENVMAP))
        && count_emission && frame.env_emitter != NONE;
    bool env_merged = EMITTER_HAS(EMITTER_ENVMAP) && integrator_samples_emitters(integrator)
        && !SHADE_LAST;
    if (miss) {
        if (env_seen && !env_merged) {
            float w = weigh ? mis_weight(path.bsdf_pdf, emitter_pdf_env(r.dir)) : 1.0;
            path.radiance += path.throughput * emitter_env_radiance(emitter_load(frame.env_emitter), r.dir) * w;
            path_keep_radiance(r.path, path);
        }
        if (!env_seen || !env_merged) return;
    }

    Surface s;
    BsdfRecord bsdf;
    // The lobe number of BSDF sampling; a composite's resolution takes its share first.
    float u_lobe = 0.0;
    bool mapped = false;
    NormalMapFrame nm;
    vec3 wo;
    // A composite BSDF's leaves (composite.glsl): bsdf is the one the lobe number
    // chose, and the others (each in its frame from s_base, the surface before any bump
    // map) join its eval and pdf as Mitsuba's blendbsdf mixes its two. count > 1 only
    // where a blend or mask mixes.
    CompositeMix leaves;
    leaves.count = 0u;
    Surface s_base;
    // Where the medium stage did not pass a tree with pass-throughs (probability
    // 1 − x), the vertex samples its solid part divided by 1 − x; MIS weighs by the
    // tree's own pdf, 1 − x times that (Mitsuba 3.9.1's mask::pdf, the opacity times
    // the nested pdf; blendbsdf's pdf, the weighted sum): the two differ in mean
    // where shadow rays and BSDF sampling see different surfaces (a bump map over a
    // mask: mask_crossing.glsl).
    float mis_scale = 1.0;
    if (miss) {
        s.p = r.origin;
    } else if (in_medium) {
        s.p = v.p;
        wo = -r.dir; // world frame, as the phase function takes it
    } else {
        s = surface_at(h.prim, h.u, h.v, r.origin, r.dir, h.t);
        ShapeRecord shape = shape_load(s.shape);
        bool emits = count_emission && shape.emitter != NONE;
        EmitterRecord light;
        uint emission_texture = 0u;
        if (emits) {
            light = emitter_load(shape.emitter);
            emission_texture = light.texture;
        }
        // Every texture of the point in one pass (the BSDF's parameters, its normal
        // map, the emitter's radiance): bsdf_textured_point says why.
        SurfaceTexels texels = SurfaceTexels(vec3(0.0), vec3(0.0));
        if (SHADE_LAST) {
            if (TEXTURE_USES(TEXTURE_FEATURE_AREA) && emission_texture != 0u) {
                texels.emission = texture_eval(emission_texture, s.uv);
            }
        } else {
            uint bsdf_index = shape.bsdf;
            uint bsdf_flags = 0u;
            if (BSDF_HAS(BSDF_COMPOSITE)) {
                // A composite BSDF resolves to its leaves here (composite.glsl).
                u_lobe = sample_1d(path.pixel, path.sample_index, rng_dim_bounce(depth, RNG_SLOT_LOBE));
                s_base = s;
                // The medium stage chose a mask's BSDF over its pass-through
                // (mask_crossing.glsl): the mask's child 1 alone.
                // A tree with a mask inside: the tree without its pass-throughs.
                uint mask_cross = THIN_NULL && (path.flags & PATH_THIN_REFLECT) != 0u
                    ? bsdf_mask_crossing(bsdf_index) : MASK_CROSSING_NONE;
                if (mask_cross == MASK_CROSSING_ROOT) {
                    mis_scale = bsdf_mask_opacity(bsdf_index, s.uv);
                    bsdf_index = bsdf_load(bsdf_index).tex_transmittance;
                }
                if (mask_cross != MASK_CROSSING_NONE) {
                    // Done with: its lobe number is not forced as a thin dielectric's.
                    path.flags &= ~PATH_THIN_REFLECT;
                }
                leaves = bsdf_composite_mix(bsdf_index, s, h.prim, vec2(h.u, h.v), -r.dir, u_lobe);
                if (mask_cross == MASK_CROSSING_TREE) {
                    // Where a blend's side was picked (more leaves than listed), the
                    // listed leaves are one draw of a random mixture whose mean is the
                    // tree: their solid weight over the whole tree's, 1 − the
                    // pass-through probability vol_path_traverse took, scales the
                    // vertex, so that its mean is the tree's solid part (renormalizing
                    // by the draw's own solid weight would not be).
                    float solid = leaves.sampled ? bsdf_composite_solid_weight(leaves) : 1.0;
                    leaves = bsdf_composite_solid(leaves, u_lobe);
                    mis_scale = 1.0 - bsdf_composite_null_pass(bsdf_index, s, h.prim, vec2(h.u, h.v), r.dir).x;
                    if (leaves.sampled) path.throughput *= mis_scale > 0.0 ? solid / mis_scale : 0.0;
                }
                CompositeBranch leaf = leaves.leaf[leaves.chosen];
                bsdf_index = leaf.index;
                bsdf_flags = leaf.flags;
                u_lobe = leaves.u;
                // A bump map's frame weighs light as a normal map's (Mitsuba 3.9).
                mapped = leaf.bumped;
                nm = leaf.nm;
                if (leaf.bumped) {
                    s.ns = leaf.nm.n;
                    s.ss = leaf.ss;
                }
            }
            bsdf = bsdf_textured_point(bsdf_load(bsdf_index), s.uv, true, emission_texture, texels);
            bsdf.flags |= bsdf_flags;
        }
        if (emits) {
            path.radiance += path_emission_found(path, r, h.t, s, shape.emitter, light, texels.emission, weigh);
            path_keep_radiance(r.path, path);
        }
        // A normal map (normal_map.glsl) replaces the shading normal and weighs the
        // light of each direction wi by normal_map_weight: 0 on different sides of the
        // old and the new normal, else its shadowing term. A twosided record mirrors
        // the old normal towards the viewer there, so the nested model is one-sided,
        // as in Mitsuba's twosided around a normalmap.
        if (SHADE_LAST) return;
        if (TEXTURE_USES(TEXTURE_FEATURE_NORMALMAP) && bsdf.normal_map != 0u) {
            mapped = true;
            nm = normal_map_frame_texel(bsdf, s, -r.dir, texels.normal);
            s.ns = nm.n;
            // Mitsuba's perturbed frame keeps the old tangent, made orthogonal to n.
            s.ss = surface_tangent(s.ss, s.ns);
            bsdf.flags &= ~BSDF_TWOSIDED;
        }
        // BSDFs work in the shading frame (ss, ns × ss, ns): Mitsuba's sh_frame, whose
        // tangent orients anisotropic roughness.
        wo = surface_to_local(s, -r.dir);
        bool ems_any = ems;
        ems = ems && !bsdf_is_delta(bsdf);
        // A mixture samples emitters unless every leaf is delta.
        if (BSDF_HAS(BSDF_COMPOSITE) && leaves.count > 1u) ems = ems_any && !leaves.all_delta;
    }

    // A longer path must fit in max_depth segments (this vertex ends segment depth+1).
    if (!miss && (SHADE_LAST || depth + 2u > max_depth)) return;

    if (ems || (env_merged && miss)) {
        vec2 u = sample_2d(path.pixel, path.sample_index, rng_dim_bounce(depth, v.light_dim));
        EmitterSample es = emitter_sample_env(s.p, u, env_merged && miss, r.dir);
        if (env_merged && miss) {
            // The environment seen along r.dir (env_merged).
            float w = weigh ? mis_weight(path.bsdf_pdf, es.pdf) : 1.0;
            path.radiance += path.throughput * es.Le * w;
            path_keep_radiance(r.path, path);
            return;
        }
        if (es.pdf > 0.0 && any(greaterThan(es.Le, vec3(0.0)))) {
            vec3 f;
            float pdf;
            vec3 origin;
            float tmax;
            uint medium;
#ifdef MEDIUM_GLSL
            if (in_medium) {
                float ph = phase_eval(g, wo, es.wi);
                f = vec3(ph);
                pdf = ph;
                origin = s.p;
                tmax = isinf(es.dist) ? es.dist : es.dist * (1.0 - 1e-4);
                medium = v.medium;
            } else
#endif
            {
                vec3 wi = surface_to_local(s, es.wi);
                float m = mapped ? normal_map_weight(nm, es.wi) : 1.0;
                f = m > 0.0 ? m * bsdf_eval(bsdf, wo, wi, s.uv) : vec3(0.0);
                pdf = bsdf_pdf(bsdf, wo, wi, s.uv);
                if (BSDF_HAS(BSDF_COMPOSITE) && leaves.count > 1u) {
                    float wj = leaves.leaf[leaves.chosen].weight;
                    vec4 others = bsdf_composite_others(leaves, s_base, -r.dir, es.wi);
                    f = wj * f + others.rgb;
                    pdf = wj * pdf + others.a;
                }
                origin = surface_spawn_origin(s, dot(es.wi, s.ng) > 0.0 ? s.ng : -s.ng);
                // Stop short of the light's own surface by Mitsuba's ShadowEpsilon
                // (~1e-3 of the distance): at 1e-4 a shadow ray from the offset origin
                // to the rim of a large, near sphere light met the sphere itself first
                // (4% of its light lost: tests/sphere_light_closed_form.rs).
                tmax = emitter_shadow_tmax(es, s.p, origin);
                medium = path_medium_after(integrator, s.shape, path.medium, es.wi, s.ng);
            }
            if (any(greaterThan(f, vec3(0.0)))) {
                // single_scatter's in-scattering is emitter sampling alone.
                float w = (mis && !es.delta && !(single && in_medium)) ? mis_weight(es.pdf, mis_scale * pdf) : 1.0;
                path_push_shadow(medium, origin, r.path, es.wi, tmax, path.throughput * f * es.Le * (w / es.pdf));
            }
        }
    }

    if (mats) {
        // BSDF sampling: a 1-D lobe choice and a 2-D direction (Mitsuba's sample1,
        // sample2); Russian roulette has its own dimension.
        vec3 u = vec3(BSDF_HAS(BSDF_COMPOSITE) ? u_lobe
                                               : sample_1d(path.pixel, path.sample_index, rng_dim_bounce(depth, RNG_SLOT_LOBE)),
                      sample_2d(path.pixel, path.sample_index, rng_dim_bounce(depth, RNG_SLOT_BSDF)));
        vec3 wi;
        vec3 weight;
        float pdf;
        uint flags;
        vec3 origin;
        uint medium;
#ifdef MEDIUM_GLSL
        if (in_medium) {
            // The phase function is sampled exactly: its weight is 1.
            PhaseSample ps = phase_sample(g, wo, u.yz);
            wi = ps.wi;
            weight = vec3(1.0);
            pdf = ps.pdf;
            // Without emitter sampling here, emitters the next ray finds count in full.
            flags = ems ? 0u : PATH_DELTA;
            origin = s.p;
            medium = v.medium;
        } else
#endif
        {
            // The medium stage already chose a thin dielectric's reflection
            // (probability R', vol_path_traverse): u.x = 0 selects that lobe, weight
            // f/P = specular.
            if ((path.flags & PATH_THIN_REFLECT) != 0u) u.x = 0.0;
            BsdfSample bs = bsdf_sample(bsdf, wo, u, s.uv);
            wi = surface_to_world(s, bs.wi);
            weight = bs.weight * (mapped ? normal_map_weight(nm, wi) : 1.0);
            pdf = bs.pdf;
            if (BSDF_HAS(BSDF_COMPOSITE) && leaves.count > 1u && bs.flags != 0u && (bs.flags & BSDF_FLAG_DELTA) == 0u) {
                // A smooth sample of a mixture: f / pdf of the whole mixture.
                vec4 others = bsdf_composite_others(leaves, s_base, -r.dir, wi);
                BsdfSample mixed = bsdf_mixture_sample(BsdfSample(wi, weight, bs.pdf, bs.flags),
                                                       leaves.leaf[leaves.chosen].weight, others);
                weight = mixed.weight;
                pdf = mixed.pdf;
            }
            flags = (bs.flags & BSDF_FLAG_DELTA) != 0u ? PATH_DELTA : 0u;
            // Refraction scaled the radiance by (η_i/η_t)² (dielectrics, rough or
            // smooth; not a thin dielectric's undeflected transmission).
            if ((bs.flags & (BSDF_FLAG_TRANSMISSION | BSDF_FLAG_NULL)) == BSDF_FLAG_TRANSMISSION) {
                path.eta_scale *= wo.z > 0.0 ? bsdf.eta * bsdf.eta : 1.0 / (bsdf.eta * bsdf.eta);
            }
            origin = surface_spawn_origin(s, dot(wi, s.ng) > 0.0 ? s.ng : -s.ng);
            medium = path_medium_after(integrator, s.shape, path.medium, wi, s.ng);
        }
        vec3 throughput = path.throughput * weight;
        if (!any(greaterThan(throughput, vec3(0.0)))) return;
        // Russian roulette: survive with probability min(max throughput, 0.99), the
        // throughput taken without the refractions' radiance scaling.
        if (path_tracer && depth + 1u >= frame.rr_depth) {
            vec3 rr = throughput * path.eta_scale;
            float q = min(max(rr.x, max(rr.y, rr.z)), 0.99);
            if (sample_1d(path.pixel, path.sample_index, rng_dim_bounce(depth, RNG_SLOT_RR)) >= q) return;
            throughput /= q;
        }
        path.throughput = throughput;
        path.bsdf_pdf = mis_scale * pdf;
        path.flags = flags | (path.flags & PATH_COVERED);
        path.medium = medium;
        path_keep_bounce(r.path, path); // the radiance word is stored where it changed
        path_push_ray(origin, r.path, wi, EMITTER_INFINITY);
    }
}

void path_shade(uint integrator, RayItem r, HitItem h, PathState path, PathVertex v) {
    path_shade_to(integrator, r, h, path, v, frame.max_depth);
}

#endif
