#version 460
#extension GL_GOOGLE_include_directive : require
// ptracer_bounce: where a light path meets a surface (path depth push.depth + 1, as
// Mitsuba counts it) below max_depth, it connects the surface to the camera and splats
// β f |cos| / (d² cos³θc A) (an irradiancemeter: β f |cos| cos θx / d²;
// integrator/ptracer.glsl), with Mitsuba's adjoint
// shading-normal correction (Veach 1997, p. 155) and light-leak test; then, if the next
// vertex can still be connected, it scatters by BSDF sampling (adjoint refraction) with
// Mitsuba's Russian roulette (from depth rr_depth on: survival min(max β η², 0.95)).
// Reads: ray queue `queue_in`, hits, light paths. Writes: splats, light paths, next
// ray queue.

#include "generated/spec_constants.glsl"
#include "queue/wavefront.glsl"
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
SPEC(SCENE_BSDF_KINDS);
#define BSDF_KINDS SCENE_BSDF_KINDS
SPEC(SCENE_PRIM_KINDS);
#define BVH_PRIM_KINDS SCENE_PRIM_KINDS
SPEC(SCENE_BVH_DEPTH);
#define BVH_STACK_DEPTH SCENE_BVH_DEPTH
SPEC(SCENE_FLAT_PRIMS);
SPEC(SCENE_FLAT_KINDS);
SPEC(PTRACER_THIN_LENS);
SPEC(SCENE_SENSOR_SHAPE);
#define PTRACER_SENSOR_SHAPE SCENE_SENSOR_SHAPE
// An irradiancemeter's points are drawn as an area emitter's (emitter.glsl).
SPEC(SCENE_EMITTER_KINDS);
#define EMITTER_KINDS SCENE_EMITTER_KINDS
#define BVH_FLAT_PRIMS SCENE_FLAT_PRIMS
#define BVH_FLAT_KINDS SCENE_FLAT_KINDS
#include "accel/bvh.glsl"
#include "shape/surface.glsl"
#include "texture/texture.glsl"
#include "bsdf/bsdf.glsl"
#include "bsdf/bsdf_textured.glsl"
#include "emitter/emitter.glsl"
#include "queue/queue.glsl"
#include "photon/bindings.glsl"
#include "photon/record.glsl"
#include "photon/random.glsl"
#include "photon/scatter.glsl"
#include "film/film.glsl"
// The film's reconstruction filter (a FILTER_* value), which splats go through.
SPEC(FILM_FILTER);
#include "film/filter.glsl"
#include "integrator/ptracer.glsl"

#define PTRACER_INFINITY uintBitsToFloat(0x7f800000u)

void main() {
    uint i = thread_index();
    if (i >= queue_ray_count(push.queue_in)) return;
    HitItem h = hit_load(i);
    if (h.prim == NONE) return;
    RayItem r = ray_load(ray_slot(push.queue_in, i));
    PhotonPath ph = photon_path_load(r.path);
    ScatterSurface x = scatter_surface(r, h);
    // Mitsuba's depth of this vertex is push.depth + 1; the emitter launched the path
    // only if depth 1 < max_depth.
    vec3 wl = -r.dir;
    float wl_ng = dot(x.s.ng, wl);
    float wl_s = dot(x.s.ns, wl);
    if (push.depth + 1u < frame.max_depth) {
        vec2 u_lens = PTRACER_SENSOR_SAMPLED
            ? ptracer_sensor_rng(ph.index, photon_params.iteration, PTRACER_RNG_DIM_SENSOR + 1u + push.depth)
            : vec2(0.0);
        CameraLink c = ptracer_camera(x.s.p, u_lens);
        if (c.ok) {
            float wc_ng = dot(x.s.ng, c.dir);
            float wc_s = dot(x.s.ns, c.dir);
            // Light leaks through shading normals: both directions on the same side of
            // the geometric and the shading normal.
            if (wl_ng * wl_s > 0.0 && wc_ng * wc_s > 0.0) {
                // Importance transport: the adjoint BSDF from the light's side to the
                // camera's is the BSDF with the camera as viewer (wo) and the light as
                // wi (Veach 1997, sec. 3.7), with the cosine towards the camera.
                vec3 f = bsdf_eval(x.bsdf, surface_to_local(x.s, c.dir),
                                   surface_to_local(x.s, wl), x.s.uv);
                // bsdf_eval's cosine is the light side's: turn it to the camera's.
                f *= abs(wc_s / wl_s);
                if (x.mapped) f *= normal_map_weight(x.nm, c.dir);
                float correction = abs((wl_s * wc_ng) / (wc_s * wl_ng));
                vec3 value = ph.power * f * (correction * c.importance);
                if (any(greaterThan(value, vec3(0.0))) && ptracer_camera_visible(x.s, c)) {
                    ptracer_splat(c.film_pos, value);
                }
            }
        }
    }
    // The next vertex (depth push.depth + 2) is connected only below max_depth.
    if (!(push.depth + 2u < frame.max_depth)) return;

    vec4 u = photon_rng(ph.index, photon_params.iteration, PHOTON_RNG_DIM_BOUNCE + push.depth);
    float eta_scale = ph.start_power;
    ScatterSample ss = scatter_sample(x, wl, u.xyz, true, eta_scale);
    if (ss.flags == 0u) return;
    float wo_ng = dot(x.s.ng, ss.wi);
    float wo_s = dot(x.s.ns, ss.wi);
    if (!(wl_ng * wl_s > 0.0 && wo_ng * wo_s > 0.0)) return;
    float correction = abs((wl_s * wo_ng) / (wo_s * wl_ng));
    vec3 power = ph.power * ss.weight * correction;
    if (!any(greaterThan(power, vec3(0.0)))) return;
    if (push.depth + 2u > frame.rr_depth) {
        float q = min(max(power.x, max(power.y, power.z)) * eta_scale, 0.95);
        if (!(u.w < q)) return;
        power /= q;
    }
    ph.power = power;
    ph.start_power = eta_scale;
    photon_path_store(r.path, ph);
    queue_push_ray(scatter_origin(x, ss.wi), r.path, ss.wi, PTRACER_INFINITY);
}
