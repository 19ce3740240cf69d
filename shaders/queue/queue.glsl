// Appending work items to the wavefront's queues. Needs wavefront.glsl.
//
// A queue fills from both ends: the first half of the producing dispatch's workgroups
// appends at the front, the second half at the back, each counting its items in its
// own tail (Counters.tails, a segment per 128 bytes). lavapipe (Mesa 22.3,
// lp_cs_tpool.c) hands each of its two threads one contiguous half of a dispatch's
// workgroups, so each thread appends to a counter on a cache line of its own; with one
// counter, the two cores' atomics pulled its line back and forth for every SIMD group
// (the normal-map scene scaled 1.64x from one thread to two in intersect and 1.75x in
// shade, against 1.97x in generate, which appends nothing). queue_args and shade_args
// fold the tails into the lengths and back counts the consumers read
// (queue_position in wavefront.glsl). The order of items within a queue carries no
// meaning: every result is written to its path.
#ifndef QUEUE_GLSL
#define QUEUE_GLSL

// The segment of the current workgroup: 0 for the first half of the dispatch's
// workgroups, 1 for the rest (lavapipe gives each of two threads groups / 2 of them,
// rounded down, and then the odd one to whichever is free).
uint queue_segment() {
    uint groups = gl_NumWorkGroups.x * gl_NumWorkGroups.y;
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    return group >= groups / 2u ? 1u : 0u;
}

// A new position in a queue whose segment tails are at word `tail` of each segment.
uint queue_append(uint tail) {
    uint s = queue_segment();
    uint k = atomicAdd(counters.tails[s * COUNTER_TAIL_STRIDE + tail], 1u);
    return s == 0u ? k : push.capacity - 1u - k;
}

// Between dispatches, in one thread: the length of the queue whose segment tails are
// word `tail` of each segment, and (back) how many of its items lie at its back end.
// Empties the tails for the queue's next filling.
uint queue_fold(uint tail, out uint back) {
    uint front = counters.tails[tail];
    back = counters.tails[COUNTER_TAIL_STRIDE + tail];
    counters.tails[tail] = 0u;
    counters.tails[COUNTER_TAIL_STRIDE + tail] = 0u;
    return front + back;
}

// Adds `rays`, the rays this invocation traced, to its segment's count (word
// TAIL_RAYS_TRACED), which queue_args adds to counters.rays_traced: each core adds to
// a line of its own. With SUBGROUP_ATOMICS one atomic per SIMD group, from its lane
// 0: every invocation of the dispatch must call it. (first_bounce's count was one
// counter both cores added to, after subgroupElect, which llvmpipe runs as a loop over
// the lanes: 6% of first_bounce's time in the HG media cube; perf, attributed to
// kernels by lavapipe's timestamps.)
void queue_count_rays(uint rays) {
    uint tail = queue_segment() * COUNTER_TAIL_STRIDE + TAIL_RAYS_TRACED;
#if SUBGROUP_ATOMICS
    uint group_rays = subgroupAdd(rays);
    if (gl_SubgroupInvocationID == 0u) atomicAdd(counters.tails[tail], group_rays);
#else
    if (rays > 0u) atomicAdd(counters.tails[tail], rays);
#endif
}

// A shadow ray starting in `medium` (NONE: in vacuum): if nothing blocks it within
// tmax, `contribution` times its transmittance joins its path.
void queue_push_shadow_in(uint medium, vec3 origin, uint path, vec3 dir, float tmax, vec3 contribution) {
    shadow_store(queue_append(TAIL_SHADOWS), ShadowItem(origin, path, dir, tmax, contribution, medium));
}

// A shadow ray: if nothing blocks it within tmax, `contribution` joins its path.
void queue_push_shadow(vec3 origin, uint path, vec3 dir, float tmax, vec3 contribution) {
    queue_push_shadow_in(NONE, origin, path, dir, tmax, contribution);
}

// A ray continuing `path`, for the next bounce (the other ray queue).
void queue_push_ray(vec3 origin, uint path, vec3 dir, float tmax) {
    uint q = 1u - push.queue_in;
    ray_store(ray_slot_at(q, queue_append(TAIL_RAYS + q)), RayItem(origin, path, dir, tmax));
}

#if SUBGROUP_ATOMICS
// queue_append where `want`, called by every invocation of the dispatch (in uniform
// flow): the SIMD group takes its positions with one atomic from lane 0 and a prefix
// sum, instead of llvmpipe's locked add per lane. The same order of positions as
// lane-by-lane atomics. (Aggregated in divergent branches with subgroupElect instead,
// which llvmpipe runs as a loop over the lanes, shade took 7% longer:
// docs/performance.md.) Returns the position where `want`.
uint queue_append_all(uint tail, bool want) {
    uint s = queue_segment();
    uint one = want ? 1u : 0u;
    uint n = subgroupAdd(one);
    uint before = subgroupExclusiveAdd(one);
    uint base = 0u;
    if (gl_SubgroupInvocationID == 0u && n > 0u) {
        base = atomicAdd(counters.tails[s * COUNTER_TAIL_STRIDE + tail], n);
    }
    uint k = subgroupBroadcast(base, 0u) + before;
    return s == 0u ? k : push.capacity - 1u - k;
}
#endif

// queue_push_ray where `want`, and queue_push_shadow_in where `want` for shadow ray s,
// called by every invocation of the dispatch (first_bounce, shade with
// PATH_QUEUES_GROUPED): one atomic per SIMD group with SUBGROUP_ATOMICS
// (queue_append_all; the HG media cube's first_bounce at 16 lanes -1 to -6%).
void queue_push_ray_all(bool want, vec3 origin, uint path, vec3 dir, float tmax) {
#if SUBGROUP_ATOMICS
    uint q = 1u - push.queue_in;
    uint k = queue_append_all(TAIL_RAYS + q, want);
    if (want) ray_store(ray_slot_at(q, k), RayItem(origin, path, dir, tmax));
#else
    if (want) queue_push_ray(origin, path, dir, tmax);
#endif
}

void queue_push_shadow_all(bool want, ShadowItem s) {
#if SUBGROUP_ATOMICS
    uint k = queue_append_all(TAIL_SHADOWS, want);
    if (want) shadow_store(k, s);
#else
    if (want) shadow_store(queue_append(TAIL_SHADOWS), s);
#endif
}

#endif
