#version 460
#extension GL_GOOGLE_include_directive : require
// photon_grid_scan: inclusive prefix sum of the bucket counts cells[0 .. n), n =
// push.path_count a multiple of SCAN_BLOCK, in three stages (a specialization constant):
//   0: each workgroup scans one block of SCAN_BLOCK counts in place (a serial scan of
//      8 per thread, then one of the 128 thread totals in shared memory) and writes
//      the block's total to scan_sums[block];
//   1: one workgroup scans the block totals in place, SCAN_BLOCK at a time, and sets
//      cells[n] to the sum of all counts;
//   2: each block but the first adds the total of the blocks before it.
// Reads and writes: cells, scan_sums.

#include "generated/spec_constants.glsl"
#include "queue/wavefront.glsl"
#include "photon/bindings.glsl"

SPEC(SCAN_STAGE);
#define SCAN_PER_THREAD 8u
#define SCAN_BLOCK (WORKGROUP_SIZE * SCAN_PER_THREAD)

shared uint scan_shared[WORKGROUP_SIZE];

// Inclusive scan of v over the workgroup's threads, in shared memory
// (Hillis and Steele 1986).
uint scan_workgroup(uint v) {
    uint t = gl_LocalInvocationID.x;
    scan_shared[t] = v;
    barrier();
    for (uint d = 1u; d < WORKGROUP_SIZE; d <<= 1u) {
        uint add = t >= d ? scan_shared[t - d] : 0u;
        barrier();
        scan_shared[t] += add;
        barrier();
    }
    return scan_shared[t];
}

// Scans SCAN_BLOCK values of `values` from `base` in place (one workgroup); returns
// the block's total in every thread.
#define SCAN_BLOCK_IN_PLACE(values, base, total)                                \
    {                                                                            \
        uint first = (base) + gl_LocalInvocationID.x * SCAN_PER_THREAD;         \
        uint run[SCAN_PER_THREAD];                                              \
        uint sum = 0u;                                                          \
        for (uint k = 0u; k < SCAN_PER_THREAD; k++) {                           \
            sum += values[first + k];                                           \
            run[k] = sum;                                                       \
        }                                                                       \
        uint inclusive = scan_workgroup(sum);                                   \
        uint before = inclusive - sum;                                          \
        for (uint k = 0u; k < SCAN_PER_THREAD; k++) values[first + k] = run[k] + before; \
        total = scan_shared[WORKGROUP_SIZE - 1u];                               \
        barrier();                                                              \
    }

void main() {
    uint block = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint n = push.path_count;
    uint blocks = n / SCAN_BLOCK;
    if (SCAN_STAGE == 0u) {
        if (block >= blocks) return;
        uint total;
        SCAN_BLOCK_IN_PLACE(cells, block * SCAN_BLOCK, total);
        if (gl_LocalInvocationID.x == 0u) scan_sums[block] = total;
    } else if (SCAN_STAGE == 1u) {
        if (block != 0u) return;
        // Block totals, padded to whole blocks with zeros by the host.
        uint carry = 0u;
        for (uint base = 0u; base < blocks; base += SCAN_BLOCK) {
            uint total;
            SCAN_BLOCK_IN_PLACE(scan_sums, base, total);
            uint first = base + gl_LocalInvocationID.x * SCAN_PER_THREAD;
            for (uint k = 0u; k < SCAN_PER_THREAD; k++) scan_sums[first + k] += carry;
            carry += total;
            barrier();
        }
        if (gl_LocalInvocationID.x == 0u) cells[n] = carry;
    } else {
        if (block == 0u || block >= blocks) return;
        uint add = scan_sums[block - 1u];
        uint first = block * SCAN_BLOCK + gl_LocalInvocationID.x * SCAN_PER_THREAD;
        for (uint k = 0u; k < SCAN_PER_THREAD; k++) cells[first + k] += add;
    }
}
