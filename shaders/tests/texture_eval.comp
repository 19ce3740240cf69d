#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: looks up texture `id` at the queried uvs (mode 0), or environment map
// emitter `id` along the queried directions (mode 1), so
// tests/texture_lookups_gpu_vs_cpu.rs can compare texture.glsl and envmap.glsl with
// their CPU references.

#include "scene/scene_bindings.glsl"

layout(local_size_x = 64) in;

// Queries: uv in xy (mode 0) or a direction in xyz (mode 1).
layout(std430, set = 1, binding = 0) readonly buffer QueryBuffer { vec4 queries[]; };
layout(std430, set = 1, binding = 1) writeonly buffer OutBuffer { vec4 results[]; };

layout(push_constant) uniform PushBlock {
    uint count;
    uint id;
    uint mode;
} pc;

#include "texture/texture.glsl"
#include "emitter/envmap.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    vec4 q = queries[i];
    vec3 v = pc.mode == 0u ? texture_eval(pc.id, q.xy) : envmap_eval(emitter_load(pc.id), normalize(q.xyz));
    results[i] = vec4(v, 0.0);
}
