#version 460
#extension GL_GOOGLE_include_directive : require
// queue_args: one thread, between `shade` and `shadow` of a bounce, turns the queue
// lengths into indirect dispatch arguments, empties the lists of deferred items
// (deferral.glsl) and counts the rays traced (first_bounce's count, queue_count_rays,
// and the queues' rays): the shadow queue `shade` filled (for the `shadow` kernel)
// and the ray queue it filled, for the next bounce's `intersect` and `shade`. It
// empties the shadow queue and the ray queue this bounce read, which the next
// bounce's `shade` appends to. The queues' lengths are their segments' tails added up
// (queue.glsl). One dispatch per bounce: on lavapipe each dispatch costs some 100
// microseconds however little it does.

#include "queue/wavefront.glsl"
#include "queue/queue.glsl"
#include "queue/deferral.glsl"

void main() {
    if (gl_GlobalInvocationID.x != 0u) return;
    uint q = push.queue_in;
    uint shadow_back;
    uint shadows = queue_fold(TAIL_SHADOWS, shadow_back);
    uvec3 g = dispatch_groups(shadows);
    dispatch_args.shadows = uint[3](g.x, g.y, g.z);

    uint ray_back;
    uint next = queue_fold(TAIL_RAYS + 1u - q, ray_back);
    g = dispatch_groups(next);
    dispatch_args.rays = uint[3](g.x, g.y, g.z);
    uint fused_back;
    uint fused = queue_fold(TAIL_RAYS_TRACED, fused_back);
    counters.rays_traced += counters.ray_count[q] + shadows + fused;
    counters.ray_count[q] = 0u;
    counters.ray_count[1u - q] = next;
    queue_lengths_out[0] = q == 0u ? uvec4(0u, next, 0u, ray_back) : uvec4(next, 0u, ray_back, 0u);
    queue_lengths_out[1] = uvec4(shadows, shadow_back, 0u, 0u);
    // The rays shade deferred are shaded, and the shadow rays are still to come.
    deferral_reset();
}
