#version 460
#extension GL_GOOGLE_include_directive : require
// accumulate: adds each finished path's radiance to its pixel. Thread t owns pixel
// (pixel_base + t) % pixels and sums paths t, t + pixels, ... of the batch, so no two
// threads write one pixel. NaN or infinite samples are dropped and counted.
// Reads: paths. Writes: film (rgb sum, sample count), counters.discarded.

#include "wavefront.glsl"

void main() {
    uint t = thread_index();
    uint pixels = frame.width * frame.height;
    if (t >= min(push.path_count, pixels)) return;
    vec3 sum = vec3(0.0);
    float n = 0.0;
    uint dropped = 0u;
    for (uint p = t; p < push.path_count; p += pixels) {
        vec3 L = path_load(p).radiance;
        if (any(isnan(L)) || any(isinf(L))) {
            dropped += 1u;
        } else {
            sum += L;
            n += 1.0;
        }
    }
    uint pixel = path_load(t).pixel;
    film[pixel] += vec4(sum, n);
    if (dropped != 0u) atomicAdd(counters.discarded, dropped);
}
