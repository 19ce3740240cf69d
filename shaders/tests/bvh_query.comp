#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: closest-hit (both traversals), any-hit and two-hit queries for a list of
// rays, so tests/bvh.rs can compare the GLSL traversal with the CPU brute force.

#include "scene/scene_bindings.glsl"
// The traversal stack is specialized to the tree's depth, as in the renderer's kernels.
layout(constant_id = 0) const int BVH_DEPTH = 32;
#define BVH_STACK_DEPTH BVH_DEPTH
// The primitives tested in turn (bvh_trace_flat) and their kinds (accel::FlatPrims):
// every one, or those apart from the tree; 0: the tree alone.
layout(constant_id = 1) const uint FLAT_PRIMS = 0u;
layout(constant_id = 2) const uint FLAT_KINDS = 0u;
#define BVH_FLAT_PRIMS FLAT_PRIMS
#define BVH_FLAT_KINDS FLAT_KINDS
#include "accel/bvh.glsl"

layout(local_size_x = 64) in;

struct QueryRay {
    vec3 origin;
    float tmin;
    vec3 dir;
    float tmax;
};

layout(std430, set = 1, binding = 0) readonly buffer QueryBuffer { QueryRay queries[]; };
layout(std430, set = 1, binding = 1) writeonly buffer ClosestBuffer { HitItem closest[]; };
layout(std430, set = 1, binding = 2) writeonly buffer AnyBuffer { uint any_hit[]; };
layout(std430, set = 1, binding = 3) writeonly buffer SecondBuffer { HitItem second_hit[]; };

layout(push_constant) uniform PushBlock { uint count; } pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    QueryRay q = queries[i];
    Hit h = bvh_closest(q.origin, q.dir, q.tmin, q.tmax);
    // The traversal for coherent rays (division-free triangle tests first) finds the
    // same hit, bit for bit; else the answer is marked (tests/bvh.rs rejects it).
    Hit c = bvh_closest_coherent(q.origin, q.dir, q.tmin, q.tmax);
    bool same = floatBitsToUint(vec3(c.t, c.u, c.v)) == floatBitsToUint(vec3(h.t, h.u, h.v));
    closest[i] = HitItem(h.t, h.u, h.v, same && c.prim == h.prim ? h.prim : 0xfffffffdu);
    any_hit[i] = bvh_any(q.origin, q.dir, q.tmin, q.tmax) ? 1u : 0u;
    Hit second;
    Hit first = bvh_closest_two(q.origin, q.dir, q.tmin, q.tmax, second);
    // The two-hit traversal's closest hit is the closest hit's distance (ties aside).
    if (first.t != h.t) second.prim = 0xfffffffeu;
    second_hit[i] = HitItem(second.t, second.u, second.v, second.prim);
}
