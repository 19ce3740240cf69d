#version 460
#extension GL_GOOGLE_include_directive : require
// photon_grid_count: the first step of the counting sort that builds the hash grid:
// each of the push.path_count photons adds one to its bucket (photons of paths at or
// past photon_params.path_limit stay out).
// Reads: photons. Writes: cells (counts; the host zeroes them first).

#include "queue/wavefront.glsl"
#include "photon/bindings.glsl"
#include "photon/record.glsl"
#include "photon/grid.glsl"

void main() {
    uint i = thread_index();
    if (i >= push.path_count) return;
    Photon p = photon_load(i);
    if (p.path >= photon_params.path_limit) return;
    atomicAdd(cells[grid_bucket(grid_cell(p.position))], 1u);
}
