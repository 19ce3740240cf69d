#version 460
#extension GL_GOOGLE_include_directive : require
// shadow: any-hit occlusion test for every shadow ray; an unblocked ray adds its
// contribution to its path. In scenes with media or null surfaces (SCENE_HAS_MEDIA)
// the ray passes null surfaces and is attenuated by the media it crosses
// (transmittance.glsl). A path has at most one shadow ray per bounce, so the write
// to its radiance does not race.
// Reads: shadow queue. Writes: paths[].radiance.

#include "generated/spec_constants.glsl"
#include "queue/wavefront.glsl"
#include "scene/scene_bindings.glsl"
// Instances (shaders/accel/instance.glsl): the hit names' shift, 0 without any, and
// their transform records; set before anything includes instance.glsl.
SPEC(SCENE_INSTANCES);
SPEC(SCENE_INSTANCE_SLOTS);
#define BVH_INSTANCES SCENE_INSTANCES
#define BVH_INSTANCE_SLOTS SCENE_INSTANCE_SLOTS
// The primitive and vertex features of the scene (SURFACE_FEATURE_* bits): hit geometry
// compiles the others away (surface.glsl).
SPEC(SCENE_SURFACE_FEATURES);
#define SURFACE_FEATURES SCENE_SURFACE_FEATURES
// Texture kinds and features the scene uses: textured thin dielectrics attenuate
// shadow rays by their textured transmittance.
SPEC(SCENE_TEXTURES);
#define TEXTURE_KINDS SCENE_TEXTURES
#include "texture/texture.glsl"
// BSDF kinds of the scene: masks pass shadow rays (mask_crossing.glsl) only where it
// has composites.
SPEC(SCENE_BSDF_KINDS);
#define BSDF_KINDS SCENE_BSDF_KINDS
#include "bsdf/bsdf.glsl"
#include "bsdf/bsdf_textured.glsl"

// The quadric kinds of the scene (SURFACE_FEATURE_* bits): the traversal compiles the
// tests of the others out.
SPEC(SCENE_PRIM_KINDS);
#define BVH_PRIM_KINDS SCENE_PRIM_KINDS
// Entries of the traversal stack: the scene BVH's deepest leaf (bvh.glsl).
SPEC(SCENE_BVH_DEPTH);
#define BVH_STACK_DEPTH SCENE_BVH_DEPTH
// A scene of a few primitives: how many and their kinds; the traversal tests each
// in turn (bvh.glsl: bvh_trace_flat; 0: traverse the BVH).
SPEC(SCENE_FLAT_PRIMS);
SPEC(SCENE_FLAT_KINDS);
#define BVH_FLAT_PRIMS SCENE_FLAT_PRIMS
#define BVH_FLAT_KINDS SCENE_FLAT_KINDS
#include "accel/bvh.glsl"
// Media or null surfaces in the scene; without them the code below compiles away.
SPEC(SCENE_HAS_MEDIA);
#include "shape/surface.glsl"
#define MEDIA_ENABLED SCENE_HAS_MEDIA
// The medium kinds and grid layouts in the scene (MEDIUM_FEATURE_* bits); the code of
// the others compiles away (without grids, only the homogeneous code is compiled).
SPEC(SCENE_MEDIUM_FEATURES);
#define MEDIUM_FEATURES SCENE_MEDIUM_FEATURES
// Thin dielectrics pass shadow rays (volumetric integrators in scenes with them).
SPEC(SCENE_THIN_NULL);
#define THIN_NULL SCENE_THIN_NULL
// Deferral (deferral.glsl; scenes with null surfaces): 0 none; SHADOW_FAST, one
// traversal per ray, leaving the rest of the rays that need more to the full kernel
// (transmittance.glsl); SHADOW_DEFERRED, the full kernel over those rests alone.
#define SHADOW_FAST 1u
#define SHADOW_DEFERRED 2u
SPEC(SCENE_DEFERRAL);
#define TRANSMITTANCE_DEFER (SCENE_DEFERRAL == SHADOW_FAST)
#include "medium/transmittance.glsl"
#include "queue/deferral.glsl"
// This is the full kernel over the deferred rests.
#define SHADOW_OF_DEFERRED (SCENE_DEFERRAL == SHADOW_DEFERRED)

// Traces shadow ray i of the queue (or of the deferred list); returns whether it left
// the rest of the ray to the full kernel, with its slot and draws.
bool shadow_item(uint i, out uint slot, out uint draws) {
    slot = SHADOW_OF_DEFERRED ? deferral_item(DEFERRED_SHADOWS, i) : shadow_slot(i);
    draws = 0u;
    ShadowItem s = shadow_load(slot);
    PathState p = path_load(s.path);
    vec3 T = shadow_transmittance_from(s, p.pixel, p.sample_index, SHADOW_OF_DEFERRED ? deferral_draws(i) : 0u);
    bool defer = TRANSMITTANCE_DEFER && transmittance_deferred;
    if (defer) {
        // The rest of the ray, in its slot, for the full kernel.
        shadow_store(slot, transmittance_rest);
        draws = transmittance_rest_draws;
    }
    if (any(greaterThan(T, vec3(0.0)))) {
        p.radiance += s.contribution * T;
        path_store_radiance(s.path, p);
    }
    return defer;
}

void main() {
    uint i = thread_index();
    uint n = SHADOW_OF_DEFERRED ? deferral_count(DEFERRED_SHADOWS) : queue_shadow_count();
    // No early return where the fast kernel defers: the deferred rays go to their list a
    // SIMD group at a time (deferral_push_shadow_where), every invocation at the end.
    uint slot = 0u;
    uint draws = 0u;
    bool defer = i < n && shadow_item(i, slot, draws);
    if (TRANSMITTANCE_DEFER) deferral_push_shadow_where(defer, slot, draws);
}
