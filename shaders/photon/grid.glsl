// The photon hash grid (Teschner et al. 2003, "Optimized Spatial Hashing for
// Collision Detection of Deformable Objects"): space is cut into cubes of side
// photon_params.cell_size, each hashed to one of table_mask + 1 buckets. Buckets are
// built on the GPU by a counting sort (photon_grid_count, photon_grid_scan,
// photon_grid_place): afterwards bucket b holds grid photons cells[b] .. cells[b + 1].
// The cell side is at least twice the largest gather radius (src/render/photon/grid.rs),
// so a gather visits the 1 or 2 cells per axis that the cube around its sphere meets,
// at most 8. Needs bindings.glsl and rng.glsl.
#ifndef PHOTON_GRID_GLSL
#define PHOTON_GRID_GLSL

#include "sampling/rng.glsl"

// Most buckets a gather visits.
#define GRID_MAX_BUCKETS 8

ivec3 grid_cell(vec3 p) { return ivec3(floor(p * photon_params.inv_cell_size)); }

// The bucket of a cell: a pcg4d hash of its coordinates.
uint grid_bucket(ivec3 c) {
    return rng_pcg4d(uvec4(uvec3(c), 0x9e3779b9u)).x & photon_params.table_mask;
}

// The cells lo .. hi (per axis) that hold every photon a gather of radius r around x
// can accept. They are those of the cube x ± r (1 + 1e-5), found with the very
// operations grid_cell applies to a photon, which round monotonically: a photon that
// photon_in_radius accepts lies within r (1 + 1e-6) of x however its squared distance
// rounded, so inside that cube, so in those cells. The host makes the side at least
// 2 r (1 + 1e-4): the cube then meets at most 2 cells per axis.
void grid_cell_range(vec3 x, float r, out ivec3 lo, out ivec3 hi) {
    float reach = r * (1.0 + 1e-5);
    lo = grid_cell(x - vec3(reach));
    hi = min(grid_cell(x + vec3(reach)), lo + ivec3(1));
}

// The buckets of the cells around x (grid_cell_range), each once, in buckets[0 .. n);
// returns n. A bucket two cells hash to is visited once: its photons are counted once.
uint grid_buckets_near(vec3 x, float r, out uint buckets[GRID_MAX_BUCKETS]) {
    ivec3 lo, hi;
    grid_cell_range(x, r, lo, hi);
    uint n = 0u;
    for (int cz = lo.z; cz <= hi.z; cz++) {
        for (int cy = lo.y; cy <= hi.y; cy++) {
            for (int cx = lo.x; cx <= hi.x; cx++) {
                uint b = grid_bucket(ivec3(cx, cy, cz));
                bool seen = false;
                for (uint j = 0u; j < n; j++) seen = seen || buckets[j] == b;
                if (!seen) {
                    buckets[n] = b;
                    n++;
                }
            }
        }
    }
    return n;
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
