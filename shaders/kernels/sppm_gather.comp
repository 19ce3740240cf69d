#version 460
#extension GL_GOOGLE_include_directive : require
// sppm_gather: at each pixel's visible point, the photons of the grid within the
// pixel's radius add β Σ f(wo, wi_p) Φ_p to its Φ and their count to its M (pbrt-v4's
// SPPM; one thread per pixel, so no atomics). An iteration whose photons took several
// passes gathers once per pass; sppm_update then applies them.
// Reads: visible points (by pixel), grid. Writes: SPPM pixels (phi, m).

#include "generated/spec_constants.glsl"
#include "queue/wavefront.glsl"
#include "scene/scene_bindings.glsl"
// Instances (shaders/accel/instance.glsl): the hit names' shift, 0 without any.
SPEC(SCENE_INSTANCES);
SPEC(SCENE_INSTANCE_SLOTS);
#define BVH_INSTANCES SCENE_INSTANCES
#define BVH_INSTANCE_SLOTS SCENE_INSTANCE_SLOTS
SPEC(SCENE_TEXTURES);
#define TEXTURE_KINDS SCENE_TEXTURES
SPEC(SCENE_BSDF_KINDS);
#define BSDF_KINDS SCENE_BSDF_KINDS
#include "shape/surface.glsl"
#include "texture/texture.glsl"
#include "bsdf/bsdf.glsl"
#include "bsdf/bsdf_textured.glsl"
#include "sampling/frame.glsl"
#include "bsdf/normal_map.glsl"
#include "photon/bindings.glsl"
#include "photon/record.glsl"
#include "photon/grid.glsl"
#include "photon/density.glsl"

void main() {
    uint q = thread_index();
    if (q >= push.path_count || vp_bsdf(q) == NONE) return;
    VisiblePoint v = vp_load(q);
    PhotonGather g = photon_gather(v, sppm_pixels[q].radius);
    if (g.count == 0u) return;
    sppm_pixels[q].phi += v.beta * g.sum;
    sppm_pixels[q].m += g.count;
}
