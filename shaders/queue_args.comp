#version 460
#extension GL_GOOGLE_include_directive : require
// queue_args: one thread, between `shade` and `shadow` of a bounce, turns the queue
// lengths into indirect dispatch arguments and counts the rays traced: the shadow
// queue `shade` filled (its length moves to shadow_traced, for the `shadow` kernel)
// and the ray queue it filled, for the next bounce's `intersect` and `shade`. It
// empties the shadow queue and the ray queue this bounce read, which the next
// bounce's `shade` appends to, and the partition intersect made of it. One dispatch per bounce: on lavapipe each dispatch
// costs some 100 microseconds however little it does.

#include "wavefront.glsl"

void main() {
    if (gl_GlobalInvocationID.x != 0u) return;
    uint q = push.queue_in;
    uint shadows = counters.shadow_count;
    uvec3 g = dispatch_groups(shadows);
    dispatch_args.shadows = uint[3](g.x, g.y, g.z);
    counters.shadow_traced = shadows;
    counters.shadow_count = 0u;

    uint next = counters.ray_count[1u - q];
    g = dispatch_groups(next);
    dispatch_args.rays = uint[3](g.x, g.y, g.z);
    counters.rays_traced += counters.ray_count[q] + shadows;
    counters.ray_count[q] = 0u;
    counters.hit_count = 0u;
    counters.miss_count = 0u;
}
