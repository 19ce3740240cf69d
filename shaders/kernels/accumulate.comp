#version 460
#extension GL_GOOGLE_include_directive : require
// accumulate: puts each finished path's sample (value, position in its pixel, flags)
// into its film slot, for film_gather. NaN or infinite samples are kept out (flagged
// invalid) and counted.
// Reads: paths. Writes: the film's sample ring, counters.discarded.

#include "generated/spec_constants.glsl"
#include "queue/wavefront.glsl"
// The sampler kind (SAMPLER_*), which draws the samples' positions in their pixels.
SPEC(SCENE_SAMPLER_KIND);
#define SAMPLER_KIND SCENE_SAMPLER_KIND
#include "film/film.glsl"

void main() {
    uint p = thread_index();
    if (p >= push.path_count) return;
    PathState path = path_load(p);
    vec3 L = path.radiance;
    bool valid = !(any(isnan(L)) || any(isinf(L)));
    if (!valid) atomicAdd(counters.discarded, 1u);
    uint flags = (valid ? FILM_SAMPLE_VALID : 0u)
        | ((path.flags & PATH_COVERED) != 0u ? FILM_SAMPLE_COVERED : 0u);
    film_store_sample(film_slot(p), valid ? L : vec3(0.0),
                      film_sample_cells(path.pixel, path.sample_index), flags);
}
