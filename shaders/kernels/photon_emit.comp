#version 460
#extension GL_GOOGLE_include_directive : require
// photon_emit: the first ray of photon paths push.pixel_base .. + path_count of stream
// photon_params.iteration, one per path slot.
// Writes: photon paths (path-state buffer), ray queue 0 (appended; the host empties it
// and folds it with queue_args).

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
#include "emitter/emitter.glsl"
// Choose the emitter uniformly (the photonmapper, as Nori) instead of by power.
SPEC(UNIFORM_EMITTER_CHOICE);
#include "photon/bindings.glsl"
#include "photon/record.glsl"
#include "photon/random.glsl"
#include "photon/emit.glsl"

void main() {
    uint p = thread_index();
    if (p >= push.path_count) return;
    uint index = push.pixel_base + p;
    uint it = photon_params.iteration;
    PhotonEmission em = photon_emit_sample(UNIFORM_EMITTER_CHOICE,
                                           photon_rng(index, it, PHOTON_RNG_DIM_EMIT),
                                           photon_rng(index, it, PHOTON_RNG_DIM_EMIT + 1u));
    float start = max(em.power.x, max(em.power.y, em.power.z));
    photon_path_store(p, PhotonPath(em.power, index, start, 0u, 0u, 0u));
    if (start > 0.0 && !isinf(start) && !isnan(start)) {
        ray_store(ray_slot_at(0u, queue_append(TAIL_RAYS)), RayItem(em.origin, p, em.dir, EMITTER_INFINITY));
    }
}
