#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel for `wavetrace warptest directionalarea` (render::emitter_probe): the
// light rays of a directionalarea emitter as the photon and particle tracers draw them
// (emitter_directionalarea_ray), against its own density emitter_directionalarea_pdf.
// mode 0: per sample two vec4, (point on the shape, pdf there), (direction, weight.r);
// mode 1: out[i].x = emitter_directionalarea_pdf at points[i] (world space, on the
// shape); mode 2: a deliberately wrong density for testing the test (wavetrace
// warptest mismatched_directionalarea): a mesh's triangle chosen uniformly instead of
// by area, 1 / (triangles x that triangle's area) at points[i].

#include "scene/scene_bindings.glsl"

layout(local_size_x = 64) in;

layout(std430, set = 1, binding = 0) readonly buffer FrameBuffer { Frame frame; };
layout(std430, set = 1, binding = 1) writeonly buffer OutBuffer { vec4 outs[]; };
layout(std430, set = 1, binding = 2) readonly buffer PointBuffer { vec4 points[]; };

layout(push_constant) uniform PushBlock {
    uint count;
    uint seed;
    uint mode;
    uint emitter;
} pc;

layout(constant_id = 0) const uint FLAT_PRIMS = 0u;
layout(constant_id = 1) const uint FLAT_KINDS = 0u;
#define BVH_FLAT_PRIMS FLAT_PRIMS
#define BVH_FLAT_KINDS FLAT_KINDS
#include "accel/bvh.glsl"
#include "sampling/rng.glsl"
#include "emitter/emitter.glsl"
#include "emitter/directionalarea.glsl"

// The wrong density of mode 2 at x: that of the triangle holding x, chosen uniformly.
float uniform_triangle_choice_pdf(EmitterRecord e, vec3 x) {
    for (uint t = 0u; t < e.tri_count; t++) {
        Prim p = prim_load(alias_load(e.tri_first + t).prim);
        vec3 n = cross(p.p1 - p.p0, p.p2 - p.p0);
        float b1 = dot(cross(x - p.p0, p.p2 - p.p0), n);
        float b2 = dot(cross(p.p1 - p.p0, x - p.p0), n);
        float nn = dot(n, n);
        if (b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= nn) return 2.0 / (float(e.tri_count) * sqrt(nn));
    }
    return 0.0;
}

void main() {
    uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (i >= pc.count) return;
    EmitterRecord e = emitter_load(pc.emitter);
    if (pc.mode == 0u) {
        DirectionalAreaRay r = emitter_directionalarea_ray(e, rng_4d(i, 0u, 7u, pc.seed).xy);
        outs[2u * i] = vec4(r.point, emitter_directionalarea_pdf(e));
        outs[2u * i + 1u] = vec4(r.dir, r.weight.r);
    } else if (pc.mode == 1u) {
        outs[i] = vec4(emitter_directionalarea_pdf(e), 0.0, 0.0, 0.0);
    } else {
        outs[i] = vec4(uniform_triangle_choice_pdf(e, points[i].xyz), 0.0, 0.0, 0.0);
    }
}
