#version 460
#extension GL_GOOGLE_include_directive : require
// shade_args: one thread, between a partitioning `intersect` and `shade`, turns the
// counts of its hits and misses into the indirect dispatch arguments of `shade` (or
// `shade_last`) and `shade_miss` (partition.glsl).

#include "wavefront.glsl"

void main() {
    if (gl_GlobalInvocationID.x != 0u) return;
    uvec3 g = dispatch_groups(counters.hit_count);
    dispatch_args.hits = uint[3](g.x, g.y, g.z);
    g = dispatch_groups(counters.miss_count);
    dispatch_args.misses = uint[3](g.x, g.y, g.z);
}
