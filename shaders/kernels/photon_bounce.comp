#version 460
#extension GL_GOOGLE_include_directive : require
// photon_bounce: where a photon path meets a surface whose BSDF is not a delta, it
// stores a photon (from its first surface on with photon_params.store_first, else from
// its second); then it scatters by BSDF sampling (adjoint refraction) with Russian
// roulette and continues in the next ray queue, up to photon_params.max_bounces
// surfaces.
// Reads: ray queue `queue_in`, hits, photon paths. Writes: photons (appended past
// photon_counters.stored; only counted beyond photon_params.capacity), photon paths,
// next ray queue.

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
#include "shape/surface.glsl"
#include "texture/texture.glsl"
#include "bsdf/bsdf.glsl"
#include "bsdf/bsdf_textured.glsl"
#include "queue/queue.glsl"
#include "photon/bindings.glsl"
#include "photon/record.glsl"
#include "photon/random.glsl"
#include "photon/scatter.glsl"

#define PHOTON_INFINITY uintBitsToFloat(0x7f800000u)

void main() {
    uint i = thread_index();
    if (i >= queue_ray_count(push.queue_in)) return;
    HitItem h = hit_load(i);
    if (h.prim == NONE) return;
    RayItem r = ray_load(ray_slot(push.queue_in, i));
    PhotonPath ph = photon_path_load(r.path);
    ScatterSurface x = scatter_surface(r, h);

    if (!bsdf_is_delta(x.bsdf) && (push.depth > 0u || photon_params.store_first != 0u)) {
        uint slot = atomicAdd(photon_counters.stored, 1u);
        if (slot < photon_params.capacity) {
            photon_store(slot, Photon(x.s.p, ph.index, ph.power, photon_dir_encode(-r.dir)));
        }
        ph.stored += 1u;
        photon_path_store(r.path, ph);
    }
    if (push.depth + 1u >= photon_params.max_bounces) return;

    vec4 u = photon_rng(ph.index, photon_params.iteration, PHOTON_RNG_DIM_BOUNCE + push.depth);
    float eta_scale = 1.0;
    ScatterSample ss = scatter_sample(x, -r.dir, u.xyz, true, eta_scale);
    vec3 power = ph.power * ss.weight;
    // Russian roulette: survive with probability min(max channel of power / its
    // largest channel at emission, 0.99), so that surviving photons keep about their
    // emitted power (pbrt-v4's SPPM keeps it exactly, without the 0.99 that ends paths
    // in a white closed room).
    float q = min(max(power.x, max(power.y, power.z)) / ph.start_power, 0.99);
    if (!(q > 0.0) || u.w >= q) return;
    ph.power = power / q;
    photon_path_store(r.path, ph);
    queue_push_ray(scatter_origin(x, ss.wi), r.path, ss.wi, PHOTON_INFINITY);
}
