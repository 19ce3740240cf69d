// Where path.glsl's vertices leave their results in the wavefront kernels (shade,
// sppm_shade): the words of the path state that changed go to paths[], shadow rays and
// continuation rays to their queues. first_bounce.comp defines PATH_SINK before
// including path.glsl and keeps them in registers instead.
// Needs wavefront.glsl and queue.glsl.
#ifndef PATH_SINK
#define PATH_SINK

// The bounce of the vertices shaded (0: found by camera rays).
#define PATH_DEPTH push.depth

void path_keep_radiance(uint i, PathState p) { path_store_radiance(i, p); }
void path_keep_bounce(uint i, PathState p) { path_store_bounce(i, p); }
void path_keep_flags(uint i, PathState p) { path_store_flags(i, p); }

// PATH_QUEUES_GROUPED (defined before including path.glsl: shade): the vertex's shadow
// ray and continuation ray wait in these until path_queues_flush, which every
// invocation of the dispatch calls at its end, pushes them a SIMD group at a time
// (queue_push_ray_all). Elsewhere each goes to its queue at once.
#ifndef PATH_QUEUES_GROUPED
#define PATH_QUEUES_GROUPED false
#endif
bool pq_shadowed = false;
ShadowItem pq_shadow;
bool pq_continued = false;
RayItem pq_ray;

void path_push_shadow(uint medium, vec3 origin, uint path, vec3 dir, float tmax, vec3 contribution) {
    if (PATH_QUEUES_GROUPED) {
        pq_shadowed = true;
        pq_shadow = ShadowItem(origin, path, dir, tmax, contribution, medium);
    } else {
        queue_push_shadow_in(medium, origin, path, dir, tmax, contribution);
    }
}

void path_push_ray(vec3 origin, uint path, vec3 dir, float tmax) {
    if (PATH_QUEUES_GROUPED) {
        pq_continued = true;
        pq_ray = RayItem(origin, path, dir, tmax);
    } else {
        queue_push_ray(origin, path, dir, tmax);
    }
}

void path_queues_flush() {
    if (PATH_QUEUES_GROUPED) {
        queue_push_shadow_all(pq_shadowed, pq_shadow);
        queue_push_ray_all(pq_continued, pq_ray.origin, pq_ray.path, pq_ray.dir, pq_ray.tmax);
    }
}

#endif
