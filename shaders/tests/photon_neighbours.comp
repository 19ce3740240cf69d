#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: the photons of the hash grid (descriptor set 2) within radius w of each
// query point xyz, found as the gathers find them (grid.glsl), listed by their `path`
// field: results[q * 256] = how many, then up to 255 of them.
// Reads: set 3 binding 0 (queries), the grid. Writes: set 3 binding 1.

#include "queue/wavefront.glsl"
#include "photon/bindings.glsl"
#include "photon/record.glsl"
#include "photon/grid.glsl"

layout(std430, set = 3, binding = 0) readonly buffer Queries { vec4 queries[]; };
layout(std430, set = 3, binding = 1) writeonly buffer Results { uint results[]; };

#define MAX_FOUND 255u

void main() {
    uint q = thread_index();
    if (q >= push.path_count) return;
    vec4 query = queries[q];
    float r2 = query.w * query.w;
    uint found = 0u;
    uint buckets[GRID_MAX_BUCKETS];
    uint n = grid_buckets_near(query.xyz, query.w, buckets);
    for (uint k = 0u; k < n; k++) {
        uvec2 range = grid_bucket_range(buckets[k]);
        for (uint j = range.x; j < range.y; j++) {
            Photon p = grid_photon_load(j);
            if (!photon_in_radius(p, query.xyz, r2)) continue;
            if (found < MAX_FOUND) results[q * (MAX_FOUND + 1u) + 1u + found] = p.path;
            found++;
        }
    }
    results[q * (MAX_FOUND + 1u)] = found;
}
