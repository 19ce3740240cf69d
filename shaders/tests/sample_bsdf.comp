#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel for tests/chi2.rs and tests/furnace.rs: runs bsdf_sample, bsdf_eval and
// bsdf_pdf of one BsdfRecord for a fixed wo.
// mode 0 (sample): item i draws u from a hash of (i, seed) and writes
//   out[3i] = (wi, pdf), out[3i+1] = (weight, flags as float bits),
//   out[3i+2] = (bsdf_eval(wo, wi), bsdf_pdf(wo, wi)).
// mode 1 (evaluate): out[i] = (bsdf_eval(wo, dirs[i].xyz), bsdf_pdf(wo, dirs[i].xyz)).
// A blend node as records[0] (src/scene/bsdf/composite.rs, children records[1] and
// records[2], weight w) is the mixture (1 − w) child 0 + w child 1 of mixture.glsl,
// sampled as path.glsl samples it: child 1 where u.x < w, u.x rescaled for it.
// Models with tables (measured) read them from dirs[tables] on, four words a vec4.

layout(std430, set = 0, binding = 1) readonly buffer DirBuffer { vec4 dirs[]; };
layout(push_constant) uniform PushBlock {
    vec4 wo;
    uint mode;
    uint count;
    uint seed;
    uint tables;
} pc;

#define BSDF_TABLE_WORD_DEFINED
uint bsdf_table_word(uint k) {
    return floatBitsToUint(dirs[pc.tables + (k >> 2u)][k & 3u]);
}

#include "bsdf/bsdf.glsl"
#include "bsdf/mixture.glsl"
#include "sampling/rng.glsl"

layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly buffer RecordBuffer { BsdfRecord records[]; };
layout(std430, set = 0, binding = 2) writeonly buffer OutBuffer { vec4 outs[]; };

// (f |cos θi|, pdf) of the record, or of the blend.
vec4 probe_eval(vec3 wo, vec3 wi) {
    BsdfRecord b = records[0];
    if (b.kind != BSDF_COMPOSITE) return vec4(bsdf_eval(b, wo, wi, vec2(0.0)), bsdf_pdf(b, wo, wi, vec2(0.0)));
    float w = b.eta;
    BsdfRecord b0 = records[b.tex_specular], b1 = records[b.tex_transmittance];
    return (1.0 - w) * vec4(bsdf_eval(b0, wo, wi, vec2(0.0)), bsdf_pdf(b0, wo, wi, vec2(0.0)))
        + w * vec4(bsdf_eval(b1, wo, wi, vec2(0.0)), bsdf_pdf(b1, wo, wi, vec2(0.0)));
}

BsdfSample probe_sample(vec3 wo, vec3 u) {
    BsdfRecord b = records[0];
    if (b.kind != BSDF_COMPOSITE) return bsdf_sample(b, wo, u, vec2(0.0));
    float w = b.eta;
    bool second = u.x < w;
    float wj = second ? w : 1.0 - w;
    u.x = min(second ? u.x / w : (u.x - w) / (1.0 - w), 0.99999994);
    BsdfRecord bj = records[second ? b.tex_transmittance : b.tex_specular];
    BsdfRecord bk = records[second ? b.tex_specular : b.tex_transmittance];
    BsdfSample s = bsdf_sample(bj, wo, u, vec2(0.0));
    vec4 others = (1.0 - wj) * vec4(bsdf_eval(bk, wo, s.wi, vec2(0.0)), bsdf_pdf(bk, wo, s.wi, vec2(0.0)));
    return bsdf_mixture_sample(s, wj, others);
}

void main() {
    uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (i >= pc.count) return;
    vec3 wo = pc.wo.xyz;
    if (pc.mode == 0u) {
        uvec4 h = rng_pcg4d(uvec4(i, pc.seed, 0x9e3779b9u, 17u));
        vec3 u = vec3(rng_to_float(h.x), rng_to_float(h.y), rng_to_float(h.z));
        BsdfSample s = probe_sample(wo, u);
        outs[3u * i] = vec4(s.wi, s.pdf);
        outs[3u * i + 1u] = vec4(s.weight, uintBitsToFloat(s.flags));
        outs[3u * i + 2u] = probe_eval(wo, s.wi);
    } else {
        outs[i] = probe_eval(wo, dirs[i].xyz);
    }
}
