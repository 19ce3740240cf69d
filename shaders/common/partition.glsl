// The partition of a bounce's rays into those that found a surface and those that
// left the scene: intersect makes it (partition_push), shade_args turns its counts
// into dispatches, shade and shade_miss read one part each (partition_hit,
// partition_miss). Lanes whose ray missed cost shade's whole code on llvmpipe, which
// runs every branch for every SIMD lane, though only the environment shades them:
// partitioned, the hits fill shade's SIMD groups and the misses run in a kernel with
// only the miss code. It pays where many rays miss and the environment lights them
// (src/render/mod.rs: Partition).
//
// The queue indices of the hits fill shade_ray_words from the front, those of the
// misses from the back (counters.hit_count and miss_count long). Needs wavefront.glsl.
#ifndef PARTITION_GLSL
#define PARTITION_GLSL

// Appends ray i to its part: the hits if `hit`, else the misses. An atomic per lane, as the
// queues' pushes: on llvmpipe (Mesa 22.3) a workgroup's shared counters with
// barriers, and subgroup ballots with one atomic per SIMD group, cost intersect as
// much or more (the normal-map scene, 256^2: intersect 163 -> 243 ms with atomics
// per lane, 303 with barriers, 242 with ballots; fastest of 6 runs each).
void partition_push(uint i, bool hit) {
    if (hit) {
        shade_ray_words[atomicAdd(counters.hit_count, 1u)] = i;
    } else {
        shade_ray_words[push.capacity - 1u - atomicAdd(counters.miss_count, 1u)] = i;
    }
}

// Queue index of hit k, of miss k.
uint partition_hit(uint k) { return imageLoad(shade_ray_texels, int(k)).x; }
uint partition_miss(uint k) { return imageLoad(shade_ray_texels, int(push.capacity - 1u - k)).x; }

#endif
