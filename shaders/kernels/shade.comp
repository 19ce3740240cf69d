#version 460
#extension GL_GOOGLE_include_directive : require
// shade: turns each hit (or miss) into radiance, shadow rays and continuation rays,
// as the integrator chosen by specialization constant INTEGRATOR says. In scenes with
// media or null surfaces (SCENE_HAS_MEDIA), path integrators first run the medium
// stage (vol_path.glsl): free-flight sampling and null-surface crossings.
// Reads: ray queue `queue_in`, hits. Writes: paths[], shadow queue, next ray queue.

#include "generated/spec_constants.glsl"
#include "queue/wavefront.glsl"
#include "scene/scene_bindings.glsl"
// Instances (shaders/accel/instance.glsl): the hit names' shift, 0 without any, and
// their transform records; set before anything includes instance.glsl.
SPEC(SCENE_INSTANCES);
SPEC(SCENE_INSTANCE_SLOTS);
#define BVH_INSTANCES SCENE_INSTANCES
#define BVH_INSTANCE_SLOTS SCENE_INSTANCE_SLOTS
#include "queue/partition.glsl"
// The sampler kind (SAMPLER_*): the other kinds compile away.
SPEC(SCENE_SAMPLER_KIND);
#define SAMPLER_KIND SCENE_SAMPLER_KIND
// The primitive and vertex features of the scene (SURFACE_FEATURE_* bits): hit geometry
// compiles the others away (surface.glsl).
SPEC(SCENE_SURFACE_FEATURES);
#define SURFACE_FEATURES SCENE_SURFACE_FEATURES
// Texture kinds and features the scene uses (TEXTURE_* kind bits, TEXTURE_FEATURE_*).
SPEC(SCENE_TEXTURES);
#define TEXTURE_KINDS SCENE_TEXTURES
// The emitter kinds the scene has (a bit per EMITTER_* kind, EMITTER_KIND_BIT_SPHERE_AREA
// for area lights on spheres): the others compile away.
SPEC(SCENE_EMITTER_KINDS);
#define EMITTER_KINDS SCENE_EMITTER_KINDS
// Only stratifying samplers stratify the emitter choice (emitter.glsl).
#define EMITTER_STRATA (SCENE_SAMPLER_KIND != SAMPLER_INDEPENDENT)
#include "emitter/emitter.glsl"

// The BSDF kinds the scene uses (a bit per BSDF_* kind): the others compile away.
SPEC(SCENE_BSDF_KINDS);
#define BSDF_KINDS SCENE_BSDF_KINDS
#include "bsdf/bsdf.glsl"
#include "bsdf/bsdf_textured.glsl"
#include "integrator/first_hit.glsl"
// A vertex's shadow ray and next ray go to their queues at the end of the kernel, a SIMD
// group at a time (path_queues.glsl), where subgroup operations allow it.
#define PATH_QUEUES_GROUPED (SUBGROUP_ATOMICS == 1)

// Media or null surfaces in the scene; without them the medium stage compiles away.
SPEC(SCENE_HAS_MEDIA);
// The quadric kinds of the scene (SURFACE_FEATURE_* bits; bvh.glsl).
SPEC(SCENE_PRIM_KINDS);
#define BVH_PRIM_KINDS SCENE_PRIM_KINDS
// Entries of the traversal stack: the scene BVH's deepest leaf (bvh.glsl).
SPEC(SCENE_BVH_DEPTH);
#define BVH_STACK_DEPTH SCENE_BVH_DEPTH
// A scene of a few primitives: how many and their kinds; the traversal tests each
// in turn (bvh.glsl: bvh_trace_flat; 0: traverse the BVH).
SPEC(SCENE_FLAT_PRIMS);
SPEC(SCENE_FLAT_KINDS);
#define BVH_FLAT_PRIMS SCENE_FLAT_PRIMS
#define BVH_FLAT_KINDS SCENE_FLAT_KINDS
#include "accel/bvh.glsl"
#define MEDIA_ENABLED SCENE_HAS_MEDIA
// The medium kinds and grid layouts in the scene (MEDIUM_FEATURE_* bits); the code of
// the others compiles away (without grids, only the homogeneous code is compiled).
SPEC(SCENE_MEDIUM_FEATURES);
#define MEDIUM_FEATURES SCENE_MEDIUM_FEATURES
// Thin dielectrics are null crossings (volumetric integrators in scenes with them).
SPEC(SCENE_THIN_NULL);
#define THIN_NULL SCENE_THIN_NULL
#include "medium/medium.glsl"
// MIS weights by the power heuristic instead of the balance heuristic.
SPEC(SCENE_MIS_POWER);
#define MIS_POWER SCENE_MIS_POWER
// The kernel of the bounces whose vertices end their paths (depth + 2 > max_depth):
// only the emission rays find (path.glsl).
SPEC(SCENE_SHADE_LAST);
#define SHADE_LAST SCENE_SHADE_LAST
// The rays it shades (constant 15; SHADE_RAYS_* in path.glsl): the bounce's queue, or
// one part of intersect's partition of it (path integrators in scenes without media).
SPEC(SCENE_SHADE_RAYS);
#define SHADE_RAYS SCENE_SHADE_RAYS
#include "integrator/path.glsl"
// Deferral (deferral.glsl; scenes with null surfaces): 0 none; SHADE_FAST, the medium
// stage never traces and leaves the rays that need it to the full kernel;
// SHADE_DEFERRED, the full kernel over those rays alone.
#define SHADE_FAST 1u
#define SHADE_DEFERRED 2u
SPEC(SCENE_DEFERRAL);
#define VOL_PATH_DEFER (SCENE_DEFERRAL == SHADE_FAST)
#include "integrator/vol_path.glsl"
#include "queue/deferral.glsl"
// shade_last in scenes with few emitter primitives and no media: how many there are
// (frame.emitter_prims); its rays then meet the emitters alone (path_emitted.glsl)
// and need no intersect before.
SPEC(SCENE_EMITTER_PRIMS);
#define EMITTER_PRIMS SCENE_EMITTER_PRIMS
// Their kinds (a bit per PRIM_* kind).
SPEC(SCENE_EMITTER_PRIM_KINDS);
#define EMITTER_PRIM_KINDS SCENE_EMITTER_PRIM_KINDS
#include "integrator/path_emitted.glsl"

SPEC(INTEGRATOR);
// The film keeps an alpha channel: camera paths record whether they cover their pixel.
SPEC(SCENE_FILM_ALPHA);

// The queue index of the ray this invocation leaves to shade_deferred, or NONE.
uint shade_deferred_item = NONE;

// Shades item i of the bounce's rays (one return, at the end: medium.glsl says why).
void shade_item(uint i) {
    if (SHADE_RAYS == SHADE_RAYS_HITS) i = partition_hit(i);
    if (SHADE_RAYS == SHADE_RAYS_MISSES) i = partition_miss(i);
    if (SCENE_DEFERRAL == SHADE_DEFERRED) i = deferral_item(DEFERRED_RAYS, i);
    RayItem r = ray_load(ray_slot(push.queue_in, i));
    if (SHADE_LAST && EMITTER_PRIMS > 0u && !integrator_is_first_hit(INTEGRATOR)) {
        path_shade_emitted(INTEGRATOR, r, path_load(r.path));
    } else {
        HitItem h = SHADE_RAYS == SHADE_RAYS_MISSES ? HitItem(r.tmax, 0.0, 0.0, NONE) : hit_load(i);
        if (!integrator_is_first_hit(INTEGRATOR)) {
            PathState path = path_load(r.path);
            PathVertex v = path_vertex_surface();
            if (!SCENE_HAS_MEDIA || vol_path_traverse(INTEGRATOR, r, h, hit_second_load(i), path, v)) {
                if (SCENE_FILM_ALPHA && push.depth == 0u) path_mark_covered(r.path, path, h, v);
                path_shade(INTEGRATOR, r, h, path, v);
            } else if (VOL_PATH_DEFER && vol_path_deferred) {
                shade_deferred_item = i;
            }
        } else {
            // Mitsuba's first-hit integrators: a camera ray covers its pixel where it hits.
            if (SCENE_FILM_ALPHA && push.depth == 0u && h.prim != NONE) {
                PathState path = path_load(r.path);
                path.flags |= PATH_COVERED;
                path_store_flags(r.path, path);
            }
            first_hit_shade(INTEGRATOR, r, h);
        }
    }
}

void main() {
    uint i = thread_index();
    uint n = SHADE_RAYS == SHADE_RAYS_HITS ? queue_part_count(PART_HITS)
        : SHADE_RAYS == SHADE_RAYS_MISSES ? queue_part_count(PART_MISSES)
        : SCENE_DEFERRAL == SHADE_DEFERRED ? deferral_count(DEFERRED_RAYS)
        : queue_ray_count(push.queue_in);
    // No early return: the vertices' rays go to their queues (PATH_QUEUES_GROUPED) and
    // the deferred rays to their list a SIMD group at a time, every invocation pushing,
    // or not, at the end.
    if (i < n) shade_item(i);
    path_queues_flush();
    if (VOL_PATH_DEFER) deferral_push_where(DEFERRED_RAYS, shade_deferred_item != NONE, shade_deferred_item);
}
