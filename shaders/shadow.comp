#version 460
#extension GL_GOOGLE_include_directive : require
// shadow: any-hit occlusion test for every shadow ray; an unblocked ray adds its
// contribution to its path. A path has at most one shadow ray per bounce, so the
// write to its radiance does not race.
// Reads: shadow queue. Writes: paths[].radiance.

#include "wavefront.glsl"
#include "scene_bindings.glsl"

// Scenes without spheres compile the sphere test out of the traversal.
layout(constant_id = 0) const bool SCENE_HAS_SPHERES = true;
#define BVH_HAS_SPHERES SCENE_HAS_SPHERES
#include "bvh.glsl"

void main() {
    uint i = thread_index();
    if (i >= counters.shadow_count) return;
    ShadowItem s = shadow_load(i);
    if (!bvh_any(s.origin, s.dir, 0.0, s.tmax)) {
        PathState p = path_load(s.path);
        p.radiance += s.contribution;
        path_store_radiance(s.path, p);
    }
}
