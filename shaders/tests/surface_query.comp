#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: the closest hit of each queried ray and the surface there (surface.glsl),
// so tests/shape_hits_vs_mitsuba.rs can compare positions, normals, uvs and tangent
// frames with Mitsuba's surface interactions.
//
// Four vec4 per ray in: (origin, 0), (direction, 0), unused, unused. Four out:
// (p, t), (ng, prim or -1 as a float), (ns, u), (ss, v).

#include "scene/scene_bindings.glsl"
// The primitives the traversal tests in turn (accel::FlatPrims::constants of the
// tree: the scene's few quadrics apart from it), as in the renderer's kernels.
layout(constant_id = 0) const uint FLAT_PRIMS = 0u;
layout(constant_id = 1) const uint FLAT_KINDS = 0u;
#define BVH_FLAT_PRIMS FLAT_PRIMS
#define BVH_FLAT_KINDS FLAT_KINDS
#include "accel/bvh.glsl"
#include "shape/surface.glsl"

layout(local_size_x = 64) in;

layout(std430, set = 1, binding = 0) readonly buffer QueryBuffer { vec4 queries[]; };
layout(std430, set = 1, binding = 1) writeonly buffer OutBuffer { vec4 results[]; };

layout(push_constant) uniform PushBlock { uint count; } pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (4u * i >= pc.count) return;
    vec3 o = queries[4u * i].xyz;
    vec3 d = queries[4u * i + 1u].xyz;
    Hit h = bvh_closest(o, d, 0.0, uintBitsToFloat(0x7f800000u));
    if (h.prim == HIT_NONE) {
        results[4u * i] = vec4(0.0, 0.0, 0.0, -1.0);
        results[4u * i + 1u] = vec4(0.0, 0.0, 0.0, -1.0);
        return;
    }
    Surface s = surface_at(h.prim, h.u, h.v, o, d, h.t);
    results[4u * i] = vec4(s.p, h.t);
    results[4u * i + 1u] = vec4(s.ng, float(h.prim));
    results[4u * i + 2u] = vec4(s.ns, s.uv.x);
    results[4u * i + 3u] = vec4(s.ss, s.uv.y);
}
