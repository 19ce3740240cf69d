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

void path_push_shadow(uint medium, vec3 origin, uint path, vec3 dir, float tmax, vec3 contribution) {
    queue_push_shadow_in(medium, origin, path, dir, tmax, contribution);
}

void path_push_ray(vec3 origin, uint path, vec3 dir, float tmax) {
    queue_push_ray(origin, path, dir, tmax);
}

#endif
