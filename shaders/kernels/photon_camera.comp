#version 460
#extension GL_GOOGLE_include_directive : require
// photon_camera: one vertex of the photon mapper's camera paths (Nori's photonmapper):
// the emission the ray finds (times photon_params.emission_scale), then at a delta BSDF
// (mirror, dielectric) the next ray by BSDF sampling with Russian roulette, and at any
// other surface the path's visible point, where photon_gather ends it.
// Reads: ray queue `queue_in`, hits, paths. Writes: paths, visible points (by path
// slot), next ray queue.

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
SPEC(SCENE_EMITTER_KINDS);
#define EMITTER_KINDS SCENE_EMITTER_KINDS
#include "emitter/emitter.glsl"
SPEC(SCENE_BSDF_KINDS);
#define BSDF_KINDS SCENE_BSDF_KINDS
#include "bsdf/bsdf.glsl"
#include "bsdf/bsdf_textured.glsl"
#include "queue/queue.glsl"
// The sampler kind (SAMPLER_*): the other kinds compile away.
SPEC(SCENE_SAMPLER_KIND);
#define SAMPLER_KIND SCENE_SAMPLER_KIND
#include "sampler/sampler_frame.glsl"
#include "photon/bindings.glsl"
#include "photon/record.glsl"
#include "photon/scatter.glsl"
#include "photon/visible_point.glsl"

void main() {
    uint i = thread_index();
    if (i >= queue_ray_count(push.queue_in)) return;
    RayItem r = ray_load(ray_slot(push.queue_in, i));
    HitItem h = hit_load(i);
    PathState path = path_load(r.path);
    float emission = photon_params.emission_scale;

    if (h.prim == NONE) {
        if ((EMITTER_HAS(EMITTER_CONSTANT) || EMITTER_HAS(EMITTER_ENVMAP)) && frame.env_emitter != NONE
            && emission > 0.0) {
            path.radiance += path.throughput * emitter_env_radiance(emitter_load(frame.env_emitter), r.dir) * emission;
            path_store_radiance(r.path, path);
        }
        return;
    }
    ScatterSurface x = scatter_surface(r, h);
    if (x.emitter != NONE && emission > 0.0) {
        vec3 Le = emitter_area_radiance(emitter_load(x.emitter), x.s.ng, r.dir, x.s.uv);
        path.radiance += path.throughput * Le * emission;
        path_store_radiance(r.path, path);
    }
    if (!bsdf_is_delta(x.bsdf)) {
        vp_store(r.path, visible_point_at(x, -r.dir, path.throughput));
        return;
    }
    // The lobe, direction and Russian-roulette dimensions of the path tracers
    // (path.glsl).
    vec3 u = vec3(sample_1d(path.pixel, path.sample_index, rng_dim_bounce(push.depth, RNG_SLOT_LOBE)),
                  sample_2d(path.pixel, path.sample_index, rng_dim_bounce(push.depth, RNG_SLOT_BSDF)));
    ScatterSample ss = scatter_sample(x, -r.dir, u, false, path.eta_scale);
    vec3 throughput = path.throughput * ss.weight;
    if (!any(greaterThan(throughput, vec3(0.0)))) return;
    // Russian roulette as the path tracers play it (path.glsl).
    if (push.depth + 1u >= frame.rr_depth) {
        vec3 rr = throughput * path.eta_scale;
        float q = min(max(rr.x, max(rr.y, rr.z)), 0.99);
        if (sample_1d(path.pixel, path.sample_index, rng_dim_bounce(push.depth, RNG_SLOT_RR)) >= q) return;
        throughput /= q;
    }
    path.throughput = throughput;
    path.flags = PATH_DELTA;
    path_store_bounce(r.path, path);
    queue_push_ray(scatter_origin(x, ss.wi), r.path, ss.wi, EMITTER_INFINITY);
}
