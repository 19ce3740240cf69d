#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: bsdf_eval and bsdf_pdf of the scene's BSDF record `id` with its textured
// parameters looked up at a uv by bsdf_textured (bsdf_textured.glsl, as the path
// kernels look them up at a hit), so tests/pplastic_vs_mitsuba.rs can compare a
// textured parameter, its lookup and the model with Mitsuba's eval and pdf at once.
// Item i reads queries[3i] = (u, v, -, -), queries[3i + 1] = (wo, -) and
// queries[3i + 2] = (wi, -), and writes results[i] = (f |cos θi|, pdf) and
// results[count + i] = (the record's eta there, -, -, -).

#include "scene/scene_bindings.glsl"

layout(local_size_x = 64) in;

layout(std430, set = 1, binding = 0) readonly buffer QueryBuffer { vec4 queries[]; };
layout(std430, set = 1, binding = 1) writeonly buffer OutBuffer { vec4 results[]; };

layout(push_constant) uniform PushBlock {
    uint count;
    uint id;
    uint pad;
} pc;

#include "texture/texture.glsl"
#include "bsdf/bsdf.glsl"
#include "bsdf/bsdf_textured.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    vec2 uv = queries[3u * i].xy;
    vec3 wo = queries[3u * i + 1u].xyz, wi = queries[3u * i + 2u].xyz;
    BsdfRecord b = bsdf_textured(bsdf_load(pc.id), uv);
    results[i] = vec4(bsdf_eval(b, wo, wi, uv), bsdf_pdf(b, wo, wi, uv));
    results[pc.count + i] = vec4(b.eta, 0.0, 0.0, 0.0);
}
