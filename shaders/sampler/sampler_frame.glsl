// The render's sampler (Frame fields) for the wavefront kernels: sample_1d / sample_2d
// of a path's pixel and sample index. Needs wavefront.glsl (for `frame`).
#ifndef SAMPLER_FRAME_GLSL
#define SAMPLER_FRAME_GLSL

#include "sampler/sampler.glsl"

Sampler sampler_frame() {
    return Sampler(frame.sampler_kind, frame.sample_count, frame.sampler_res_x, frame.sampler_res_y,
                   frame.sampler_flags, frame.seed, frame.sampler_width, frame.sampler_height);
}

float sample_1d(uint pixel, uint sample_index, uint dim) {
    return sampler_1d(sampler_frame(), pixel, sample_index, dim);
}

vec2 sample_2d(uint pixel, uint sample_index, uint dim) {
    return sampler_2d(sampler_frame(), pixel, sample_index, dim);
}

#endif
