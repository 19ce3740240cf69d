#version 460
#extension GL_GOOGLE_include_directive : require
// first_bounce: generate, intersect, shade and shadow of a batch's first bounce in one
// kernel, for the integrators of path.glsl (and, in scenes with media or null
// surfaces, their medium stage: vol_path.glsl, transmittance.glsl) on CPU devices
// (render::Renderer::new says when). Each thread makes its path's
// camera ray, finds its hit, shades it and traces its shadow ray; where the second
// bounce only ends paths (direct lighting: max_depth 2) it runs that too, and the
// path is done. Otherwise the path's continuation ray goes to ray queue 1, for the
// wavefront's bounces from 1 on.
//
// Why: llvmpipe turns each divergent load and store of the queues into a loop over
// its SIMD lanes, so passing a bounce from kernel to kernel costs stores and loads of
// the ray, the hit, the path and the shadow ray; here they stay in registers. At the
// first bounce every lane has a path, so nothing is lost by not compacting (but for
// camera rays that miss into an environment, which the wavefront shades apart). (Looping
// over all bounces in one kernel costs more than it saves on llvmpipe: a loop keeps
// every value it changes in memory under the lanes' masks, callgrind: 23600
// instructions per SIMD group for one bounce in a loop, 15100 without; and a group
// runs as many bounces as its longest path.)
// The same functions and sample numbers as the wavefront's kernels in the same order:
// the same image up to float contraction. In closed scenes without media
// (SCENE_SECOND_FUSED) it shades bounce 1 too, as every lane still has a path there.
// Writes: paths[p] for path p of the batch, ray queue 1 (with SCENE_SECOND_FUSED ray
// queue 0 and the shadow queue), its segment's count of traced rays (queue_count_rays).

#include "generated/spec_constants.glsl"
#include "queue/wavefront.glsl"
#include "scene/scene_bindings.glsl"
// Instances (shaders/accel/instance.glsl): the hit names' shift, 0 without any, and
// their transform records; set before anything includes instance.glsl.
SPEC(SCENE_INSTANCES);
SPEC(SCENE_INSTANCE_SLOTS);
#define BVH_INSTANCES SCENE_INSTANCES
#define BVH_INSTANCE_SLOTS SCENE_INSTANCE_SLOTS
#include "queue/queue.glsl"
// The sampler kind (SAMPLER_*): the other kinds compile away.
SPEC(SCENE_SAMPLER_KIND);
#define SAMPLER_KIND SCENE_SAMPLER_KIND
#include "film/film.glsl"
#include "sensor/camera.glsl"

// Bounce 1 runs here too, in full (closed scenes without media, where every lane
// still has a path: render::plan::Schedule): its shadow rays go to the shadow queue
// and the rays it continues to ray queue 0 (push.queue_in is 1), for the shadow
// kernel and the wavefront's bounce 2.
SPEC(SCENE_SECOND_FUSED);

// path.glsl leaves a vertex's results in this thread (its sink; the wavefront's is
// path_queues.glsl): the path's state, and its shadow ray and next ray if the vertex
// made them.
#define PATH_SINK
uint fb_depth;
#define PATH_DEPTH fb_depth
PathState fb_path;
bool fb_shadowed;
ShadowItem fb_shadow;
bool fb_continued;
RayItem fb_ray;

void path_keep_radiance(uint i, PathState p) { fb_path.radiance = p.radiance; }
void path_keep_bounce(uint i, PathState p) {
    vec3 radiance = fb_path.radiance;
    fb_path = p;
    fb_path.radiance = radiance;
}
void path_keep_flags(uint i, PathState p) {
    fb_path.bsdf_pdf = p.bsdf_pdf;
    fb_path.flags = p.flags;
    fb_path.eta_scale = p.eta_scale;
    fb_path.medium = p.medium;
}
void path_push_shadow(uint medium, vec3 origin, uint path, vec3 dir, float tmax, vec3 contribution) {
    // Traced in this kernel, but bounce 1's with SCENE_SECOND_FUSED, which main pushes
    // to the shadow kernel (it traces only the lanes that have one).
    fb_shadowed = true;
    fb_shadow = ShadowItem(origin, path, dir, tmax, contribution, medium);
}
void path_push_ray(vec3 origin, uint path, vec3 dir, float tmax) {
    fb_continued = true;
    fb_ray = RayItem(origin, path, dir, tmax);
}

// The scene's features, with shade.comp's constant ids (the host gives both the same
// constants; see there).
SPEC(SCENE_SURFACE_FEATURES);
#define SURFACE_FEATURES SCENE_SURFACE_FEATURES
SPEC(SCENE_TEXTURES);
#define TEXTURE_KINDS SCENE_TEXTURES
SPEC(SCENE_EMITTER_KINDS);
#define EMITTER_KINDS SCENE_EMITTER_KINDS
#define EMITTER_STRATA (SCENE_SAMPLER_KIND != SAMPLER_INDEPENDENT)
#include "emitter/emitter.glsl"
// An irradiancemeter draws its rays' origins on its shape (emitter.glsl).
SPEC(SCENE_SENSOR_SHAPE);
#define SENSOR_ON_SHAPE SCENE_SENSOR_SHAPE
// A batch sensor's children side by side (camera_path.glsl; 0: one camera).
SPEC(SCENE_SENSOR_BATCH);
#define SENSOR_BATCH SCENE_SENSOR_BATCH
#include "integrator/camera_path.glsl"
SPEC(SCENE_BSDF_KINDS);
#define BSDF_KINDS SCENE_BSDF_KINDS
#include "bsdf/bsdf.glsl"
#include "bsdf/bsdf_textured.glsl"
SPEC(SCENE_PRIM_KINDS);
#define BVH_PRIM_KINDS SCENE_PRIM_KINDS
SPEC(SCENE_BVH_DEPTH);
#define BVH_STACK_DEPTH SCENE_BVH_DEPTH
SPEC(SCENE_FLAT_PRIMS);
SPEC(SCENE_FLAT_KINDS);
#define BVH_FLAT_PRIMS SCENE_FLAT_PRIMS
#define BVH_FLAT_KINDS SCENE_FLAT_KINDS
#include "accel/bvh.glsl"
// Media or null surfaces (shade's and shadow's constant 4): the camera ray keeps its
// second-nearest hit (intersect's SCENE_SECOND_HITS), the medium stage runs before
// path_shade (as in shade.comp) and the shadow ray is attenuated by what it crosses
// (as in shadow.comp). Without them this code compiles away. (Before path.glsl, which
// shades medium vertices where medium.glsl came first.)
SPEC(SCENE_HAS_MEDIA);
#define MEDIA_ENABLED SCENE_HAS_MEDIA
SPEC(SCENE_MEDIUM_FEATURES);
#define MEDIUM_FEATURES SCENE_MEDIUM_FEATURES
SPEC(SCENE_THIN_NULL);
#define THIN_NULL SCENE_THIN_NULL
#include "medium/medium.glsl"
SPEC(SCENE_MIS_POWER);
#define MIS_POWER SCENE_MIS_POWER
// The first bounce ends the paths (max_depth 1: only the emission camera rays find).
SPEC(SCENE_FIRST_ENDS);
#define SHADE_LAST SCENE_FIRST_ENDS
#include "integrator/path.glsl"
// The second bounce, where it runs here, meets the emitters alone (path_emitted.glsl)
// in scenes with few emitter primitives: how many, and their kinds (0: it traces).
SPEC(SCENE_EMITTER_PRIMS);
#define EMITTER_PRIMS SCENE_EMITTER_PRIMS
SPEC(SCENE_EMITTER_PRIM_KINDS);
#define EMITTER_PRIM_KINDS SCENE_EMITTER_PRIM_KINDS
#include "integrator/path_emitted.glsl"
#include "integrator/vol_path.glsl"
#include "medium/transmittance.glsl"

SPEC(INTEGRATOR);
SPEC(SCENE_FILM_ALPHA);
// The second bounce ends the paths (max_depth 2) and meets the emitters alone
// (EMITTER_PRIMS > 0): it runs here too.
SPEC(SCENE_SECOND_ENDS);

// The path's shadow ray from its vertex just shaded, if it made one: traced, and its
// contribution added where nothing blocks it.
void first_bounce_shadow(inout uint rays) {
    if (!fb_shadowed) return;
    rays += 1u;
    vec3 T = shadow_transmittance(fb_shadow, fb_path.pixel, fb_path.sample_index);
    if (any(greaterThan(T, vec3(0.0)))) fb_path.radiance += fb_shadow.contribution * T;
}

// Path p of the batch, its first bounce (or two); returns the rays it traced.
uint first_bounce_path(uint p) {
    // The path's state and camera ray, as generate makes them.
    RayItem r;
    camera_path_start(p, fb_path, r);

    // Bounce 0: intersect, the medium stage, shade and shadow (main reset the sink).
    Hit hit;
    Hit second = Hit(r.tmax, 0.0, 0.0, HIT_NONE);
    if (SCENE_HAS_MEDIA) {
        hit = bvh_closest_two(r.origin, r.dir, 0.0, r.tmax, second);
    } else {
        hit = bvh_closest_coherent(r.origin, r.dir, 0.0, r.tmax);
    }
    HitItem h = HitItem(hit.t, hit.u, hit.v, hit.prim);
    PathVertex v = path_vertex_surface();
    uint rays = 1u;
    // The path's state as the medium stage leaves it (shade.comp's `path`); a path it
    // ends (absorbed) keeps the state it had, as the wavefront stores nothing then.
    PathState path = fb_path;
    if (!SCENE_HAS_MEDIA
        || vol_path_traverse(INTEGRATOR, r, h, HitItem(second.t, second.u, second.v, second.prim), path, v)) {
        if (SCENE_FILM_ALPHA) path_mark_covered(p, path, h, v);
        path_shade(INTEGRATOR, r, h, path, v);
        first_bounce_shadow(rays);
    }
    if (SCENE_SECOND_ENDS) {
        // Bounce 1, which ends the paths: the emitters its rays meet, through a shadow
        // ray (shade_last with path_emitted.glsl). A ray counts as traced, as the
        // wavefront counts it.
        if (fb_continued) {
            fb_depth = 1u;
            fb_shadowed = false;
            fb_continued = false;
            path_shade_emitted(INTEGRATOR, fb_ray, fb_path);
            rays += 1u;
            first_bounce_shadow(rays);
        }
    } else if (SCENE_SECOND_FUSED) {
        // Bounce 1 as the wavefront's intersect and shade run it (no media), its ray,
        // hit and path kept in registers; its shadow ray and bounce 2's ray for the
        // wavefront.
        if (fb_continued) {
            RayItem r1 = fb_ray;
            fb_depth = 1u;
            fb_shadowed = false;
            fb_continued = false;
            Hit hit1 = bvh_closest(r1.origin, r1.dir, 0.0, r1.tmax);
            rays += 1u;
            path_shade(INTEGRATOR, r1, HitItem(hit1.t, hit1.u, hit1.v, hit1.prim), fb_path,
                       path_vertex_surface());
        }
    }
    // A ray left in fb_continued goes on in the wavefront (bounce 1's, or with
    // SCENE_SECOND_FUSED bounce 2's; past a budget of one bounce queue_args counts its
    // path as cut): main pushes it.
    path_store(p, fb_path);
    return rays;
}

void main() {
    uint p = thread_index();
    // No early return: every invocation pushes its rays (none past the batch) and counts
    // them, one atomic per SIMD group and counter (queue_push_ray_all,
    // queue_count_rays; per lane, they and subgroupElect cost the HG media cube's
    // first_bounce 6-8% at 16 lanes).
    fb_depth = 0u;
    fb_shadowed = false;
    fb_continued = false;
    uint rays = p < push.path_count ? first_bounce_path(p) : 0u;
    if (SCENE_SECOND_FUSED) queue_push_shadow_all(fb_depth == 1u && fb_shadowed, fb_shadow);
    queue_push_ray_all(fb_continued, fb_ray.origin, p, fb_ray.dir, fb_ray.tmax);
    queue_count_rays(rays);
}
