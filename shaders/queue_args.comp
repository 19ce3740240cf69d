#version 460
#extension GL_GOOGLE_include_directive : require
// queue_args: one thread, between `shade` and `shadow` of a bounce, turns the queue
// lengths into indirect dispatch arguments and counts the rays traced: the shadow
// queue `shade` filled (its length moves to shadow_traced, for the `shadow` kernel)
// and the ray queue it filled, for the next bounce's `intersect` and `shade`. It
// empties the shadow queue and the ray queue this bounce read, which the next
// bounce's `shade` appends to. One dispatch per bounce: on lavapipe each dispatch
// costs some 100 microseconds however little it does.

#include "wavefront.glsl"

// Workgroups for n items on a 2D grid of at most 65535 x 65535 groups.
uvec3 groups_for(uint n) {
    uint groups = (n + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    uint x = min(groups, 65535u);
    uint y = x == 0u ? 1u : (groups + x - 1u) / x;
    return uvec3(x, y, 1u);
}

void main() {
    if (gl_GlobalInvocationID.x != 0u) return;
    uint q = push.queue_in;
    uint shadows = counters.shadow_count;
    uvec3 g = groups_for(shadows);
    dispatch_args.shadows = uint[3](g.x, g.y, g.z);
    counters.shadow_traced = shadows;
    counters.shadow_count = 0u;

    uint next = counters.ray_count[1u - q];
    g = groups_for(next);
    dispatch_args.rays = uint[3](g.x, g.y, g.z);
    counters.rays_traced += counters.ray_count[q] + shadows;
    counters.ray_count[q] = 0u;
}
