// The partition of a bounce's rays into those that found a surface and those that
// left the scene: intersect makes it (partition_push), shade_args turns its counts
// into dispatches, shade and shade_miss read one part each (partition_hit,
// partition_miss). Lanes whose ray missed cost shade's whole code on llvmpipe, which
// runs every branch for every SIMD lane, though only the environment shades them:
// partitioned, the hits fill shade's SIMD groups and the misses run in a kernel with
// only the miss code. It pays where many rays miss and the environment lights them
// (src/render/mod.rs: Partition).
//
// Part p (PART_HITS, PART_MISSES) holds the queue indices of its rays in
// shade_ray_words[p capacity, (p + 1) capacity), a queue filled from both ends as
// queue.glsl's (queue_part_count(p) long, queue_part_back(p) of them at the back).
// Needs wavefront.glsl.
#ifndef PARTITION_GLSL
#define PARTITION_GLSL

#include "queue/queue.glsl"

// Appends ray i to its part: the hits if `hit`, else the misses. An atomic per lane, as the
// queues' pushes: on llvmpipe (Mesa 22.3) a workgroup's shared counters with
// barriers, and subgroup ballots with one atomic per SIMD group, cost intersect as
// much or more (the normal-map scene, 256^2: intersect 163 -> 243 ms with atomics
// per lane, 303 with barriers, 242 with ballots; fastest of 6 runs each). One atomic
// and one store, each at a per-lane address, not one of each per part: llvmpipe runs
// both sides of a branch, and a masked-off atomic or store still costs its loop over
// the lanes.
void partition_push(uint i, bool hit) {
    uint p = hit ? PART_HITS : PART_MISSES;
    shade_ray_words[p * push.capacity + queue_append(TAIL_PART + p)] = i;
}

// Queue index of ray k of part p.
uint partition_ray(uint p, uint k) {
    uint pos = queue_position(k, queue_part_count(p), queue_part_back(p));
    return imageLoad(shade_ray_texels, int(p * push.capacity + pos)).x;
}
uint partition_hit(uint k) { return partition_ray(PART_HITS, k); }
uint partition_miss(uint k) { return partition_ray(PART_MISSES, k); }

#endif
