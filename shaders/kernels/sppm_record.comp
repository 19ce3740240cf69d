#version 460
#extension GL_GOOGLE_include_directive : require
// sppm_record: adds the light each finished SPPM camera path found directly (emission
// and emitter sampling) to its pixel's Ld; one path per pixel in a batch, so no two
// threads write a pixel. NaN or infinite values are dropped and counted.
// Reads: paths. Writes: SPPM pixels (of the tile from photon_params.first_pixel),
// counters.discarded.

#include "queue/wavefront.glsl"
#include "photon/bindings.glsl"

void main() {
    uint p = thread_index();
    if (p >= push.path_count) return;
    PathState path = path_load(p);
    vec3 L = path.radiance;
    if (any(isnan(L)) || any(isinf(L))) {
        atomicAdd(counters.discarded, 1u);
        return;
    }
    sppm_pixels[path.pixel - photon_params.first_pixel].ld += L;
}
