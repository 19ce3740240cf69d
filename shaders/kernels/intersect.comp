#version 460
#extension GL_GOOGLE_include_directive : require
// intersect: closest hit through the BVH for every ray of the input queue.
// Reads: ray queue `queue_in`. Writes: hits[i] for ray i.

#include "generated/spec_constants.glsl"
#include "queue/wavefront.glsl"
#include "scene/scene_bindings.glsl"
// Instances (shaders/accel/instance.glsl): the hit names' shift, 0 without any, and
// their transform records; set before anything includes instance.glsl.
SPEC(SCENE_INSTANCES);
SPEC(SCENE_INSTANCE_SLOTS);
#define BVH_INSTANCES SCENE_INSTANCES
#define BVH_INSTANCE_SLOTS SCENE_INSTANCE_SLOTS
#include "queue/partition.glsl"

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
// Whether the rays are partitioned into hits and misses for shade (partition.glsl);
// else the kernels that follow read every ray's hit.
SPEC(SCENE_PARTITION);
// Rays may cross null surfaces: the second-nearest hit is kept too, for shade to go on
// through the nearest without tracing again (vol_path.glsl).
SPEC(SCENE_SECOND_HITS);

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
