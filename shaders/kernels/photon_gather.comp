#version 460
#extension GL_GOOGLE_include_directive : require
// photon_gather: the photon mapper's density estimate at each camera path's visible
// point, Σ f(wo, wi_p) Φ_p over the photons within photon_params.radius, added to the
// path's radiance times its throughput and photon_params.gather_scale (1 / (π r² N),
// N the photon paths emitted, times the number of photon passes; see
// src/render/photon/photonmapper.rs).
// Reads: visible points (by path slot), grid, paths. Writes: paths' radiance.

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
    uint p = thread_index();
    if (p >= push.path_count || vp_bsdf(p) == NONE) return;
    VisiblePoint v = vp_load(p);
    PhotonGather g = photon_gather(v, photon_params.radius);
    if (g.count == 0u) return;
    PathState path = path_load(p);
    path.radiance += v.beta * g.sum * photon_params.gather_scale;
    path_store_radiance(p, path);
}
