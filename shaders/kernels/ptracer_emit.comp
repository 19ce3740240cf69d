#version 460
#extension GL_GOOGLE_include_directive : require
// ptracer_emit: the start of light paths push.pixel_base .. + path_count of sample index
// photon_params.iteration (integrator/ptracer.glsl), one per path slot. Each first
// connects a point on an emitter chosen uniformly to the camera (Mitsuba's
// sample_visible_emitters: area emitters only, not with hide_emitters or max_depth
// 0), then samples the path's first ray as the photon mappers emit (photon/emit.glsl,
// emitter chosen uniformly as Mitsuba's Scene::sample_emitter_ray).
// Writes: splats, light paths (path-state buffer, PhotonPath with start_power holding
// the η² Russian roulette divides out), ray queue 0 (appended; the host folds it with
// queue_args).

#include "generated/spec_constants.glsl"
#include "queue/wavefront.glsl"
#include "queue/queue.glsl"
#include "scene/scene_bindings.glsl"
// Instances (shaders/accel/instance.glsl): the hit names' shift, 0 without any.
SPEC(SCENE_INSTANCES);
SPEC(SCENE_INSTANCE_SLOTS);
#define BVH_INSTANCES SCENE_INSTANCES
#define BVH_INSTANCE_SLOTS SCENE_INSTANCE_SLOTS
SPEC(SCENE_SURFACE_FEATURES);
#define SURFACE_FEATURES SCENE_SURFACE_FEATURES
SPEC(SCENE_TEXTURES);
#define TEXTURE_KINDS SCENE_TEXTURES
SPEC(SCENE_EMITTER_KINDS);
#define EMITTER_KINDS SCENE_EMITTER_KINDS
SPEC(SCENE_PRIM_KINDS);
#define BVH_PRIM_KINDS SCENE_PRIM_KINDS
SPEC(SCENE_BVH_DEPTH);
#define BVH_STACK_DEPTH SCENE_BVH_DEPTH
SPEC(SCENE_FLAT_PRIMS);
SPEC(SCENE_FLAT_KINDS);
SPEC(PTRACER_THIN_LENS);
SPEC(SCENE_SENSOR_SHAPE);
#define PTRACER_SENSOR_SHAPE SCENE_SENSOR_SHAPE
#define BVH_FLAT_PRIMS SCENE_FLAT_PRIMS
#define BVH_FLAT_KINDS SCENE_FLAT_KINDS
#include "accel/bvh.glsl"
#include "emitter/emitter.glsl"
#include "photon/bindings.glsl"
#include "photon/record.glsl"
#include "numeric/convert.glsl"
#include "photon/random.glsl"
#include "photon/emit.glsl"
#include "film/film.glsl"
// The film's reconstruction filter (a FILTER_* value), which splats go through.
SPEC(FILM_FILTER);
#include "film/filter.glsl"
#include "integrator/ptracer.glsl"

// The environment seen by the camera along a direction d sampled as the emitter
// samples it (Mitsuba samples it from the sensor's position): its radiance along d
// times the importance of d, 1 / (cos³θc A) (an irradiancemeter's: cos θx at a point x
// of its shape), over the density of d and of the choice (uniform, 1 / n), where
// nothing blocks the ray from the camera.
void connect_visible_environment(EmitterRecord e, uint n, vec2 u, vec2 u_lens) {
    vec3 d;
    float pdf;
    if (EMITTER_HAS(EMITTER_ENVMAP) && e.kind == EMITTER_ENVMAP) {
        if (!TEXTURE_USES(TEXTURE_FEATURE_ENVMAP)) return;
        d = envmap_sample(e, u, pdf);
    } else {
        d = warp_uniform_sphere(u);
        pdf = warp_uniform_sphere_pdf(d);
    }
    if (!(pdf > 0.0)) return;
    if (PTRACER_SENSOR_SHAPE) {
        Surface x;
        float w = irradiancemeter_direction_importance(d, u_lens, x);
        vec3 value = emitter_env_radiance(e, d) * (float(n) * w / pdf);
        if (!any(greaterThan(value, vec3(0.0)))) return;
        if (bvh_any(surface_spawn_origin(x, x.ng), d, 0.0, EMITTER_INFINITY)) return;
        ptracer_splat(u_lens * vec2(frame.width, frame.height), value);
        return;
    }
    vec3 eye = frame.camera_to_world[3].xyz;
    // A thin lens sees the environment along d from a point of its aperture.
    if (PTRACER_THIN_LENS) eye = (frame.camera_to_world * vec4(ptracer_lens_point(u_lens), 1.0)).xyz;
    // A point far along d stands for the environment: the camera link's importance
    // is then 1 / (d² cos³θc A) for that distance, d² = 1 here.
    CameraLink c = ptracer_camera(eye + d * frame.near_clip * 2.0 + d, u_lens);
    vec3 local = inverse(mat3(frame.camera_to_world)) * d;
    if (!c.ok || !(local.z > 0.0)) return;
    float cos_c = local.z / length(local);
    float area = 4.0 * frame.tan_half_fov.x * frame.tan_half_fov.y;
    vec3 value = emitter_env_radiance(e, d) * (float(n) / (pdf * cos_c * cos_c * cos_c * area));
    if (!any(greaterThan(value, vec3(0.0)))) return;
    if (bvh_any(eye, d, 0.0, EMITTER_INFINITY)) return;
    ptracer_splat(c.film_pos, value);
}

// A point on an area emitter seen by the camera: its radiance towards the camera
// times cos θ over the density of choosing the point (uniform emitter choice, 1 / area).
void connect_visible_emitter(uint index, uint it) {
    vec4 u = photon_rng(index, it, PTRACER_RNG_DIM_VISIBLE);
    vec2 u_lens = PTRACER_SENSOR_SAMPLED ? ptracer_sensor_rng(index, it, PTRACER_RNG_DIM_SENSOR) : vec2(0.0);
    uint n = frame.emitter_count;
    uint i = min(floor_to_uint(u.x * float(n)), n - 1u);
    EmitterRecord e = emitter_load(i);
    if ((EMITTER_HAS(EMITTER_CONSTANT) && e.kind == EMITTER_CONSTANT)
        || (EMITTER_HAS(EMITTER_ENVMAP) && e.kind == EMITTER_ENVMAP)) {
        connect_visible_environment(e, n, u.yz, u_lens);
        return;
    }
    if (!EMITTER_HAS_ANY(EMITTER_AREA_BITS) || e.kind != EMITTER_AREA) return;
    Surface ls = emitter_area_point(e, u.yz);
    CameraLink c = ptracer_camera(ls.p, u_lens);
    if (!c.ok) return;
    // One-sided: Mitsuba clamps the cosine in the point's frame.
    float cos_y = dot(ls.ns, c.dir);
    if (!(cos_y > 0.0)) return;
    vec3 L = emitter_area_radiance(e, ls.ns, -c.dir, ls.uv);
    vec3 value = L * (cos_y * e.area * float(n) * c.importance);
    if (!any(greaterThan(value, vec3(0.0)))) return;
    if (!ptracer_camera_visible(ls, c)) return;
    ptracer_splat(c.film_pos, value);
}

void main() {
    uint p = thread_index();
    if (p >= push.path_count) return;
    uint index = push.pixel_base + p;
    uint it = photon_params.iteration;
    if (frame.max_depth != 0u && frame.hide_emitters == 0u && frame.emitter_count > 0u) {
        connect_visible_emitter(index, it);
    }
    PhotonEmission em = photon_emit_sample(true,
                                           photon_rng(index, it, PHOTON_RNG_DIM_EMIT),
                                           photon_rng(index, it, PHOTON_RNG_DIM_EMIT + 1u));
    float start = max(em.power.x, max(em.power.y, em.power.z));
    photon_path_store(p, PhotonPath(em.power, index, 1.0, 0u, 0u, 0u));
    // The first hit is path depth 1: connected only below max_depth.
    if (frame.max_depth > 1u && start > 0.0 && !isinf(start) && !isnan(start)) {
        ray_store(ray_slot_at(0u, queue_append(TAIL_RAYS)), RayItem(em.origin, p, em.dir, EMITTER_INFINITY));
    }
}
