// Deferred items: work a fast kernel leaves to a full twin. In scenes with null
// surfaces (media boundaries), a ray that passes more surfaces than its traversal
// found (vol_path.glsl) and a shadow ray likewise (transmittance.glsl) must trace
// again. On llvmpipe (Mesa 22.3), which runs every branch of a kernel for all its SIMD
// lanes and every loop at least once per entry, a traversal inside the crossing loop
// costs every SIMD group a pass through it at every crossing, whether a lane traces or
// not (callgrind, media/cube.xml 128^2 16 spp --wavefront, those traversals left out: a
// wrong image, shade -34%, shadow -27%). So shade and shadow come in two forms: the
// fast one has no traversal in its crossing loop and leaves each item that needs one
// to the full one, which a second dispatch runs over the deferred items alone:
// - shade's rays untouched: shade_deferred runs them from the start, with the same
//   numbers as if the fast kernel had run the full code;
// - the rest of each shadow ray from where it stopped, written over its slot of the
//   shadow queue, with the random numbers its tracking drew (transmittance.glsl):
//   shadow_deferred goes on from there.
// The same image either way, but for the rounding of a deferred shadow ray's product
// of transmittances.
//
// List k (DEFERRED_RAYS: queue indices of shade's rays; DEFERRED_SHADOWS: shadow queue
// slots) is shade_ray_words[k capacity + j], Counters.deferred[k] long, and a deferred
// shadow ray's draws are at [2 capacity + j]. A scene with media never partitions its
// rays, whose parts use those words otherwise (partition.glsl). The pushing lanes size
// the full kernel's dispatch themselves (atomicMax on its indirect arguments), which
// saves a one-thread dispatch between the two (some 50-100 us each on lavapipe);
// queue_args empties both lists and their arguments for the next bounce, adding their
// lengths to Counters.deferred_total.
// Needs wavefront.glsl.
#ifndef DEFERRAL_GLSL
#define DEFERRAL_GLSL

// The dispatch (x, y) that covers items 0..n (as dispatch_groups, which a growing n
// only makes larger in each component).
uvec2 deferral_groups(uint n) {
    uint groups = (n + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    return uvec2(min(groups, 65535u), (groups + 65534u) / 65535u);
}

// Raises list k's full kernel's dispatch to cover its items 0..n.
void deferral_raise(uint k, uint n) {
    uvec2 g = deferral_groups(n);
    if (k == DEFERRED_RAYS) {
        atomicMax(dispatch_args.deferred_rays[0], g.x);
        atomicMax(dispatch_args.deferred_rays[1], g.y);
    } else {
        atomicMax(dispatch_args.deferred_shadows[0], g.x);
        atomicMax(dispatch_args.deferred_shadows[1], g.y);
    }
}

// Leaves queue item `index` (a ray's, or a shadow ray's) to list k's full kernel;
// returns its position in the list.
uint deferral_push(uint k, uint index) {
    uint j = atomicAdd(counters.deferred[k], 1u);
    shade_ray_words[k * push.capacity + j] = index;
    // Only the first item of each workgroup's worth raises the dispatch (the args are
    // the groups that cover the largest position, which that item's covers too): an
    // atomic per WORKGROUP_SIZE items instead of per item, on counters both cores share.
    if (j % WORKGROUP_SIZE == 0u) deferral_raise(k, j + 1u);
    return j;
}

#if SUBGROUP_ATOMICS
// deferral_push where `want`, called by every invocation of the dispatch (in uniform
// flow): one atomic per SIMD group that defers anything, from lane 0, on the counter
// both cores share, instead of llvmpipe's locked add per lane (as queue_append_all).
// Lane 0 raises the dispatch where the group's items need more workgroups than those
// before them. Returns the item's position where `want`.
uint deferral_push_all(uint k, bool want, uint index) {
    uint one = want ? 1u : 0u;
    uint n = subgroupAdd(one);
    uint j = 0u;
    if (n > 0u) {
        uint before = subgroupExclusiveAdd(one);
        uint base = 0u;
        if (gl_SubgroupInvocationID == 0u) base = atomicAdd(counters.deferred[k], n);
        base = subgroupBroadcast(base, 0u);
        j = base + before;
        if (want) shade_ray_words[k * push.capacity + j] = index;
        if (gl_SubgroupInvocationID == 0u
            && (base + n + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE > (base + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE) {
            deferral_raise(k, base + n);
        }
    }
    return j;
}
#endif

// deferral_push where `want`, from every invocation of the dispatch: a SIMD group at a
// time where subgroup operations allow it.
void deferral_push_where(uint k, bool want, uint index) {
#if SUBGROUP_ATOMICS
    deferral_push_all(k, want, index);
#else
    if (want) deferral_push(k, index);
#endif
}

// Leaves the rest of a shadow ray (written to shadow queue slot `slot`) to the full
// shadow kernel, with the number of random numbers its tracking drew
// (transmittance.glsl).
void deferral_push_shadow(uint slot, uint draws) {
    uint j = deferral_push(DEFERRED_SHADOWS, slot);
    shade_ray_words[2u * push.capacity + j] = draws;
}

// deferral_push_shadow where `want`, from every invocation of the dispatch (as
// deferral_push_where).
void deferral_push_shadow_where(bool want, uint slot, uint draws) {
#if SUBGROUP_ATOMICS
    uint j = deferral_push_all(DEFERRED_SHADOWS, want, slot);
    if (want) shade_ray_words[2u * push.capacity + j] = draws;
#else
    if (want) deferral_push_shadow(slot, draws);
#endif
}

// The random numbers deferred shadow ray j drew before it was deferred.
uint deferral_draws(uint j) { return imageLoad(shade_ray_texels, int(2u * push.capacity + j)).x; }

// How many items list k holds (read by its full kernel, after the fast one).
uint deferral_count(uint k) { return counters.deferred[k]; }

// Item j of list k: a ray's queue index, or a shadow ray's slot.
uint deferral_item(uint k, uint j) {
    return imageLoad(shade_ray_texels, int(k * push.capacity + j)).x;
}

// Empties both lists (queue_args, after the full shade and before the fast shadow).
void deferral_reset() {
    counters.deferred_total += counters.deferred[DEFERRED_RAYS] + counters.deferred[DEFERRED_SHADOWS];
    counters.deferred[DEFERRED_RAYS] = 0u;
    counters.deferred[DEFERRED_SHADOWS] = 0u;
    dispatch_args.deferred_rays = uint[3](0u, 1u, 1u);
    dispatch_args.deferred_shadows = uint[3](0u, 1u, 1u);
}

#endif
