#version 460
#extension GL_GOOGLE_include_directive : require
// ptracer_fold: after the last light path of a sample index, adds each crop pixel's
// splats (64-bit fixed point, integer sums: integrator/ptracer.glsl) to the film sums
// as one sample of weight 1, and clears them for the next sample index. One thread per
// crop pixel; the film's float sums are then a left fold over sample indices, as
// film_gather makes them for camera samples.
// Reads and writes: splats, the film's sums.

#include "generated/spec_constants.glsl"
#include "queue/wavefront.glsl"
#include "scene/scene_bindings.glsl"
#include "photon/bindings.glsl"
#include "film/film.glsl"

// The value of a 64-bit two's complement fixed-point sum.
float fixed_value(uint lo, uint hi) {
    if (hi >= 0x80000000u) {
        lo = ~lo + 1u;
        hi = ~hi + (lo == 0u ? 1u : 0u);
        return -(float(hi) * 4294967296.0 + float(lo)) * (1.0 / 16777216.0);
    }
    return (float(hi) * 4294967296.0 + float(lo)) * (1.0 / 16777216.0);
}

void main() {
    uint i = thread_index();
    if (i >= film.crop_width * film.crop_height) return;
    uint w = 6u * i;
    vec3 v = vec3(fixed_value(splat_words[w], splat_words[w + 1u]),
                  fixed_value(splat_words[w + 2u], splat_words[w + 3u]),
                  fixed_value(splat_words[w + 4u], splat_words[w + 5u]));
    for (uint k = 0u; k < 6u; k++) splat_words[w + k] = 0u;
    film_sums[i] += vec4(v, 1.0);
}
