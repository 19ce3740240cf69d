#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: the density of grid medium `medium` at the queried grid-local points
// (medium.glsl medium_grid_density, every layout compiled in), so tests/media_grids.rs can
// compare it with trilinear interpolation on the CPU.

#include "scene/scene_bindings.glsl"

layout(local_size_x = 64) in;

layout(std430, set = 1, binding = 0) readonly buffer QueryBuffer { vec4 queries[]; };
layout(std430, set = 1, binding = 1) writeonly buffer OutBuffer { vec4 results[]; };

layout(push_constant) uniform PushBlock {
    uint count;
    uint medium;
} pc;

#include "medium/medium.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    results[i] = vec4(medium_grid_density(medium_load(pc.medium), queries[i].xyz), 0.0);
}
