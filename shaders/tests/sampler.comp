#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel for tests/samplers.rs: the samplers of shaders/sampler/ evaluated for a
// block of pixels, samples and dimensions. Thread t computes dimension
// dim_base + t % dims of sample sample_base + (t / dims) % samples of pixel
// pixel_base + t / (dims * samples) and writes it to out[t]: (u, v) of a 2-D draw
// (mode 0) or (u, 0) of a 1-D one (mode 1).

// The kind under test, as the renderer's kernels specialize it.
layout(constant_id = 0) const uint TEST_SAMPLER_KIND = 0u;
#define SAMPLER_KIND TEST_SAMPLER_KIND
#include "sampler/sampler.glsl"

layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) writeonly buffer OutBuffer { vec2 outs[]; };

layout(push_constant) uniform PushBlock {
    Sampler s;
    uint pixel_base;
    uint sample_base;
    uint dim_base;
    uint samples;
    uint dims;
    uint total;
    uint mode;
} pc;

void main() {
    uint t = gl_GlobalInvocationID.x;
    if (t >= pc.total) return;
    uint dim = pc.dim_base + t % pc.dims;
    uint rest = t / pc.dims;
    uint sample_index = pc.sample_base + rest % pc.samples;
    uint pixel = pc.pixel_base + rest / pc.samples;
    if (pc.mode == 1u) {
        outs[t] = vec2(sampler_1d(pc.s, pixel, sample_index, dim), 0.0);
    } else {
        outs[t] = sampler_2d(pc.s, pixel, sample_index, dim);
    }
}
