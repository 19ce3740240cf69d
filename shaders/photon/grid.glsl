// The photon hash grid (Teschner et al. 2003, "Optimized Spatial Hashing for
// Collision Detection of Deformable Objects"): space is cut into cubes of side
// photon_params.cell_size, each hashed to one of table_mask + 1 buckets. Buckets are
// built on the GPU by a counting sort (photon_grid_count, photon_grid_scan,
// photon_grid_place): afterwards bucket b holds grid photons cells[b] .. cells[b + 1].
// The cell side is at least twice the largest gather radius (src/render/photon/grid.rs
// adds a margin for rounding), so a sphere of radius r around x lies in the 2 x 2 x 2
// cells from grid_first_cell(x). Needs bindings.glsl and rng.glsl.
#ifndef PHOTON_GRID_GLSL
#define PHOTON_GRID_GLSL

#include "rng.glsl"

ivec3 grid_cell(vec3 p) { return ivec3(floor(p * photon_params.inv_cell_size)); }

// The lower corner of the 2 x 2 x 2 cells around x: the cell of x - (side / 2).
ivec3 grid_first_cell(vec3 x) { return ivec3(floor(x * photon_params.inv_cell_size - 0.5)); }

// The bucket of a cell: a pcg4d hash of its coordinates.
uint grid_bucket(ivec3 c) {
    return rng_pcg4d(uvec4(uvec3(c), 0x9e3779b9u)).x & photon_params.table_mask;
}

// The buckets of the 2 x 2 x 2 cells around x, each once: a bucket that an earlier cell
// of the eight hashed to as well is NONE (its photons are visited once).
void grid_buckets_around(vec3 x, out uint buckets[8]) {
    ivec3 c0 = grid_first_cell(x);
    for (int k = 0; k < 8; k++) {
        uint b = grid_bucket(c0 + ivec3(k & 1, (k >> 1) & 1, k >> 2));
        for (int j = 0; j < k; j++) {
            if (buckets[j] == b) b = NONE;
        }
        buckets[k] = b;
    }
}

// Whether photon p lies within sqrt(r2) of x (the sphere's surface included).
bool photon_in_radius(Photon p, vec3 x, float r2) {
    vec3 d = p.position - x;
    return dot(d, d) <= r2;
}

// Grid photons of bucket b: [first, end).
uvec2 grid_bucket_range(uint b) {
    return uvec2(imageLoad(cell_words, int(b)).x, imageLoad(cell_words, int(b + 1u)).x);
}

#endif
