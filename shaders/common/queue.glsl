// Appending work items to the wavefront's queues. Needs wavefront.glsl.
#ifndef QUEUE_GLSL
#define QUEUE_GLSL

// A shadow ray starting in `medium` (NONE: in vacuum): if nothing blocks it within
// tmax, `contribution` times its transmittance joins its path.
void queue_push_shadow_in(uint medium, vec3 origin, uint path, vec3 dir, float tmax, vec3 contribution) {
    uint slot = atomicAdd(counters.shadow_count, 1u);
    shadow_store(slot, ShadowItem(origin, path, dir, tmax, contribution, medium));
}

// A shadow ray: if nothing blocks it within tmax, `contribution` joins its path.
void queue_push_shadow(vec3 origin, uint path, vec3 dir, float tmax, vec3 contribution) {
    queue_push_shadow_in(NONE, origin, path, dir, tmax, contribution);
}

// A ray continuing `path`, for the next bounce (the other ray queue).
void queue_push_ray(vec3 origin, uint path, vec3 dir, float tmax) {
    uint q = 1u - push.queue_in;
    uint slot = atomicAdd(counters.ray_count[q], 1u);
    ray_store(ray_slot(q, slot), RayItem(origin, path, dir, tmax));
}

#endif
