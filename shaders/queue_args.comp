#version 460
#extension GL_GOOGLE_include_directive : require
// queue_args: one thread turns a queue length into indirect dispatch arguments and
// counts the rays traced. MODE 0 (before `intersect`): the ray queue `queue_in`;
// also empties the other ray queue and the shadow queue for this bounce.
// MODE 1 (before `shadow`): the shadow queue.

#include "wavefront.glsl"

layout(constant_id = 0) const uint MODE = 0u;

// Workgroups for n items on a 2D grid of at most 65535 x 65535 groups.
uvec3 groups_for(uint n) {
    uint groups = (n + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    uint x = min(groups, 65535u);
    uint y = x == 0u ? 1u : (groups + x - 1u) / x;
    return uvec3(x, y, 1u);
}

void main() {
    if (gl_GlobalInvocationID.x != 0u) return;
    if (MODE == 0u) {
        uint n = counters.ray_count[push.queue_in];
        uvec3 g = groups_for(n);
        dispatch_args.rays[0] = g.x;
        dispatch_args.rays[1] = g.y;
        dispatch_args.rays[2] = g.z;
        counters.ray_count[1u - push.queue_in] = 0u;
        counters.shadow_count = 0u;
        counters.rays_traced += n;
    } else {
        uint n = counters.shadow_count;
        uvec3 g = groups_for(n);
        dispatch_args.shadows[0] = g.x;
        dispatch_args.shadows[1] = g.y;
        dispatch_args.shadows[2] = g.z;
        counters.rays_traced += n;
    }
}
