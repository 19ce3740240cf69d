#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel for tests/media_sampling_chi2.rs: phase_sample, phase_eval and phase_pdf of
// Henyey-Greenstein with asymmetry g for a fixed wo.
// mode 0 (sample): out[2i] = (wi, pdf returned by phase_sample),
//   out[2i+1] = (phase_eval(wo, wi), phase_pdf(wo, wi), 0, 0).
// mode 1 (evaluate): out[i] = (phase_pdf(wo, dirs[i].xyz), phase_eval(wo, dirs[i].xyz), 0, 0).

#include "medium/phase.glsl"
#include "sampling/rng.glsl"

layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly buffer DirBuffer { vec4 dirs[]; };
layout(std430, set = 0, binding = 1) writeonly buffer OutBuffer { vec4 outs[]; };

layout(push_constant) uniform PushBlock {
    vec4 wo;
    float g;
    uint mode;
    uint count;
    uint seed;
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (i >= pc.count) return;
    vec3 wo = pc.wo.xyz;
    if (pc.mode == 0u) {
        uvec4 h = rng_pcg4d(uvec4(i, pc.seed, 0x85ebca6bu, 29u));
        PhaseSample s = phase_sample(pc.g, wo, vec2(rng_to_float(h.x), rng_to_float(h.y)));
        outs[2u * i] = vec4(s.wi, s.pdf);
        outs[2u * i + 1u] = vec4(phase_eval(pc.g, wo, s.wi), phase_pdf(pc.g, wo, s.wi), 0.0, 0.0);
    } else {
        vec3 wi = dirs[i].xyz;
        outs[i] = vec4(phase_pdf(pc.g, wo, wi), phase_eval(pc.g, wo, wi), 0.0, 0.0);
    }
}
