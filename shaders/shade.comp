#version 460
#extension GL_GOOGLE_include_directive : require
// shade: turns each hit (or miss) into radiance, shadow rays and continuation rays,
// as the integrator chosen by specialization constant INTEGRATOR says.
// Reads: ray queue `queue_in`, hits. Writes: paths[], shadow queue, next ray queue.

#include "wavefront.glsl"
#include "scene_bindings.glsl"
// Texture kinds and features the scene uses (TEXTURE_* kind bits, TEXTURE_FEATURE_*).
layout(constant_id = 2) const uint SCENE_TEXTURES = 0xffffffffu;
#define TEXTURE_KINDS SCENE_TEXTURES
#include "emitter.glsl"

// The BSDF kinds the scene uses (a bit per BSDF_* kind): the others compile away.
layout(constant_id = 1) const uint SCENE_BSDF_KINDS = 0xffffffffu;
#define BSDF_KINDS SCENE_BSDF_KINDS
#include "bsdf.glsl"
#include "bsdf_textured.glsl"
#include "first_hit.glsl"
#include "path.glsl"

layout(constant_id = 0) const uint INTEGRATOR = INTEGRATOR_AO;

void main() {
    uint i = thread_index();
    if (i >= counters.ray_count[push.queue_in]) return;
    RayItem r = rays[ray_slot(push.queue_in, i)];
    HitItem h = hits[i];
    if (INTEGRATOR >= INTEGRATOR_DIRECT_EMS) {
        path_shade(INTEGRATOR, r, h);
    } else {
        first_hit_shade(INTEGRATOR, r, h);
    }
}
