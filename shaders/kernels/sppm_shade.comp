#version 460
#extension GL_GOOGLE_include_directive : require
// sppm_shade: one vertex of SPPM's camera paths (pbrt-v4's SPPMIntegrator): the
// vertex of a path tracer with emitter and BSDF sampling under the power heuristic
// (path.glsl, path_mis), which adds the light found directly to the path, and, at the
// first surface sppm_visible_point_here accepts, the pixel's visible point for this
// iteration. The ray after the visible point only adds the emission it finds (its MIS
// share), then the path ends.
// Reads: ray queue `queue_in`, hits, paths, visible points. Writes: paths, shadow
// queue, next ray queue, visible points (by pixel of the tile).

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
#define MIS_POWER true
#include "integrator/path.glsl"
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
    uint vp = path.pixel - photon_params.first_pixel;
    bool has_vp = vp_bsdf(vp) != NONE;
    path_shade_to(INTEGRATOR_PATH_MIS, r, h, path, path_vertex_surface(),
                  has_vp ? push.depth + 1u : frame.max_depth);
    if (has_vp || h.prim == NONE || push.depth + 2u > frame.max_depth) return;
    // A composite resolves as path_shade_to resolved it (the vertex's lobe number).
    ScatterSurface x = scatter_surface_u(r, h, sample_1d(path.pixel, path.sample_index, rng_dim_bounce(push.depth, RNG_SLOT_LOBE)));
    if (sppm_visible_point_here(x.bsdf, push.depth + 2u == frame.max_depth)) {
        vp_store(vp, visible_point_at(x, -r.dir, path.throughput));
    }
}
