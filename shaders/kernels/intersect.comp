#version 460
#extension GL_GOOGLE_include_directive : require
// intersect: closest hit through the BVH for every ray of the input queue.
// Reads: ray queue `queue_in`. Writes: hits[i] for ray i.

#include "queue/wavefront.glsl"
#include "scene/scene_bindings.glsl"
#include "queue/partition.glsl"

// The quadric kinds of the scene (SURFACE_FEATURE_* bits): the traversal compiles the
// tests of the others out.
layout(constant_id = 0) const uint SCENE_PRIM_KINDS = 0xffffffffu;
#define BVH_PRIM_KINDS SCENE_PRIM_KINDS
// Entries of the traversal stack: the scene BVH's deepest leaf (bvh.glsl).
layout(constant_id = 1) const int SCENE_BVH_DEPTH = 32;
#define BVH_STACK_DEPTH SCENE_BVH_DEPTH
// A scene of a few primitives: how many and their kinds; the traversal tests each
// in turn (bvh.glsl: bvh_trace_flat; 0: traverse the BVH).
layout(constant_id = 3) const uint SCENE_FLAT_PRIMS = 0u;
layout(constant_id = 4) const uint SCENE_FLAT_KINDS = 0u;
#define BVH_FLAT_PRIMS SCENE_FLAT_PRIMS
#define BVH_FLAT_KINDS SCENE_FLAT_KINDS
#include "accel/bvh.glsl"
// Whether the rays are partitioned into hits and misses for shade (partition.glsl);
// else the kernels that follow read every ray's hit.
layout(constant_id = 2) const bool SCENE_PARTITION = false;
// Rays may cross null surfaces: the second-nearest hit is kept too, for shade to go on
// through the nearest without tracing again (vol_path.glsl).
layout(constant_id = 5) const bool SCENE_SECOND_HITS = false;

void main() {
    uint i = thread_index();
    if (i >= queue_ray_count(push.queue_in)) return;
    RayItem r = ray_load(ray_slot(push.queue_in, i));
    Hit h;
    if (SCENE_SECOND_HITS) {
        Hit second;
        h = bvh_closest_two(r.origin, r.dir, 0.0, r.tmax, second);
        hit_second_store(i, HitItem(second.t, second.u, second.v, second.prim));
    } else {
        h = bvh_closest(r.origin, r.dir, 0.0, r.tmax);
    }
    hit_store(i, HitItem(h.t, h.u, h.v, h.prim));
    if (SCENE_PARTITION) partition_push(i, h.prim != HIT_NONE);
}
