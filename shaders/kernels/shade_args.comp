#version 460
#extension GL_GOOGLE_include_directive : require
// shade_args: one thread, between a partitioning `intersect` and `shade`, turns the
// counts of its hits and misses into the indirect dispatch arguments of `shade` (or
// `shade_last`) and `shade_miss` (partition.glsl), folding each part's segment
// tails into its length and back count (queue.glsl).

#include "queue/wavefront.glsl"
#include "queue/queue.glsl"

void main() {
    if (gl_GlobalInvocationID.x != 0u) return;
    uint hits_back, misses_back;
    uint hits = queue_fold(TAIL_PART + PART_HITS, hits_back);
    uint misses = queue_fold(TAIL_PART + PART_MISSES, misses_back);
    uvec3 g = dispatch_groups(hits);
    dispatch_args.hits = uint[3](g.x, g.y, g.z);
    g = dispatch_groups(misses);
    dispatch_args.misses = uint[3](g.x, g.y, g.z);
    queue_lengths_out[2] = uvec4(hits, misses, hits_back, misses_back);
}
