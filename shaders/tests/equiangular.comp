#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel for tests/media_sampling_chi2.rs: equiangular distance sampling on
// [a, b] of the ray (o, d) towards c.
// mode 0 (sample): out[i] = (t, pdf at t, 0, 0); mode 1: out[i].x = pdf(ts[i].x).

#include "medium/equiangular.glsl"
#include "sampling/rng.glsl"

layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly buffer InBuffer { vec4 ts[]; };
layout(std430, set = 0, binding = 1) writeonly buffer OutBuffer { vec4 outs[]; };

layout(push_constant) uniform PushBlock {
    vec4 o;     // xyz origin, w: a
    vec4 d;     // xyz unit direction, w: b
    vec4 c;     // xyz the point sampled towards
    uint mode;
    uint count;
    uint seed;
    uint pad;
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (i >= pc.count) return;
    Equiangular e = equiangular_setup(pc.o.xyz, pc.d.xyz, pc.c.xyz, pc.o.w, pc.d.w);
    if (pc.mode == 0u) {
        uvec4 h = rng_pcg4d(uvec4(i, pc.seed, 0x27d4eb2fu, 41u));
        float t = equiangular_sample(e, pc.o.w, pc.d.w, rng_to_float(h.x));
        outs[i] = vec4(t, equiangular_pdf(e, t), 0.0, 0.0);
    } else {
        outs[i] = vec4(equiangular_pdf(e, ts[i].x), 0.0, 0.0, 0.0);
    }
}
