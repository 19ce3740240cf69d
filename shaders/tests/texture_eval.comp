#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: looks up texture `id` at the queried uvs (mode 0), environment map
// emitter `id` along the queried directions (mode 1), or texture `id` at the surface
// point of BVH primitive x (its bits) and barycentrics (y, z) (mode 2: mesh
// attributes, through surface_at), so
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
#include "shape/surface.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    vec4 q = queries[i];
    vec3 v;
    if (pc.mode == 2u) {
        Surface s = surface_at(floatBitsToUint(q.x), q.y, q.z, vec3(0.0), vec3(0.0), 0.0);
        v = texture_eval(pc.id, s.uv);
    } else {
        v = pc.mode == 0u ? texture_eval(pc.id, q.xy) : envmap_eval(emitter_load(pc.id), normalize(q.xyz));
    }
    results[i] = vec4(v, 0.0);
}
