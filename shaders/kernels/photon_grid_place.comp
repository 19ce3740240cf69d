#version 460
#extension GL_GOOGLE_include_directive : require
// photon_grid_place: the last step of the counting sort: after photon_grid_scan,
// cells[b] is one past the last slot of bucket b; each photon takes the slot below it
// (an atomic decrement), so that afterwards cells[b] is the first photon of bucket b.
// Reads: photons. Writes: grid photons, cells.

#include "queue/wavefront.glsl"
#include "photon/bindings.glsl"
#include "photon/record.glsl"
#include "photon/grid.glsl"

void main() {
    uint i = thread_index();
    if (i >= push.path_count) return;
    Photon p = photon_load(i);
    if (p.path >= photon_params.path_limit) return;
    uint slot = atomicAdd(cells[grid_bucket(grid_cell(p.position))], 0xffffffffu) - 1u;
    grid_photon_store(slot, p);
}
