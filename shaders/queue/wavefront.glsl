// Descriptor set 1: the wavefront's queues and path states, and the push constants.
// Bindings are mirrored in src/render/wavefront.rs.
#ifndef WAVEFRONT_GLSL
#define WAVEFRONT_GLSL

#extension GL_KHR_shader_subgroup_basic : require
#ifdef SCENE_STORAGE
// Sums over a subgroup, to make one atomic per SIMD group of a counter every lane adds
// to (first_bounce's ray count). The SCENE_STORAGE variants run on llvmpipe from Mesa
// 26 alone (gpu::device::scene_storage_faster), which supports subgroup arithmetic.
// (Queue appends, whose counters each core has its own of, stay an atomic per lane:
// with a subgroup prefix sum instead, shade took 7% longer on the Cornell box.)
#define SUBGROUP_ATOMICS 1
#extension GL_KHR_shader_subgroup_arithmetic : require
// subgroupBroadcast (queue_push_ray_all).
#extension GL_KHR_shader_subgroup_ballot : require
#else
#define SUBGROUP_ATOMICS 0
#endif
#include "generated/spec_constants.glsl"
#include "scene/layout.glsl"

#define WORKGROUP_SIZE 128
layout(local_size_x = WORKGROUP_SIZE) in;

// The frame's parameters: a uniform block (std140 lays Frame out as std430 does; see
// layout.glsl). After them, the queue lengths that the kernels consuming a queue read
// (queue_ray_count and the like below): llvmpipe loads a uniform block once per SIMD
// group, where it loads from the storage buffer of the counters lane by lane. One
// block, because lavapipe 22.3 crashes running a set with a second uniform buffer.
// The frame is read as frames[push.frame_index], an index that is always 0 but not a
// constant (the `frame` macro below): lavapipe 22.3 "inlines uniforms", i.e. where an
// `if` tests only values loaded from a uniform block at constant offsets, it copies
// the shader, puts the values in, optimizes it again and looks its machine code up in
// the disk cache, at every dispatch whose uniforms or descriptor sets were bound anew
// (all of ours), and keeps doing so for a kernel whose code the values halve.
// first_bounce (its depth a constant, so `depth + 1 >= frame.max_depth` and the like
// test the frame alone) paid 11-16 ms a dispatch for it, whatever its size: a 16x16
// Veach render took 16.7 ms in it, 0.4 ms with the frame indexed. An offset from a
// push constant is still uniform, so llvmpipe still loads each value once per SIMD
// group.
layout(std140, set = 1, binding = 0) uniform FrameBuffer { Frame frames[1]; uvec4 queue_lengths[3]; };
// Path states and queues are written through 16-byte words, one store per word, and
// read through texel views of the same buffers (bindings 7-10, imageLoad): llvmpipe
// turns each divergent storage-buffer access into a loop over the SIMD lanes, an image
// load into one inline gather (see BindingKind::Texels in src/gpu/kernel.rs). Use the
// *_load and *_store functions below, never the arrays.
//
// A divergent store costs llvmpipe (Mesa 22.3) a loop over the SIMD lanes per
// component: the WAVEFRONT_INT64 variant of each kernel (build.rs; devices with
// shaderInt64) stores a word as two 64-bit components instead of four 32-bit ones
// (callgrind, veach direct: shade -9%, generate -16% instructions). Store a word
// through wavefront_word.
#ifdef WAVEFRONT_INT64
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#define WAVEFRONT_WORD u64vec2
WAVEFRONT_WORD wavefront_word(uvec4 w) { return u64vec2(packUint2x32(w.xy), packUint2x32(w.zw)); }
uvec4 wavefront_texel(WAVEFRONT_WORD w) { return uvec4(unpackUint2x32(w.x), unpackUint2x32(w.y)); }
#else
#define WAVEFRONT_WORD uvec4
WAVEFRONT_WORD wavefront_word(uvec4 w) { return w; }
uvec4 wavefront_texel(WAVEFRONT_WORD w) { return w; }
#endif
// The queues' records are written here and read through the texel views at bindings
// 7-10, or, in the SCENE_STORAGE variants of kernels that also read the scene (for
// drivers whose storage-buffer loads beat their image loads: gpu::SceneAccess), read
// here too.
#ifdef SCENE_STORAGE
#define WAVEFRONT_ACCESS
#else
#define WAVEFRONT_ACCESS writeonly
#endif
layout(std430, set = 1, binding = 1) WAVEFRONT_ACCESS buffer PathBuffer { WAVEFRONT_WORD path_words[]; };
layout(std430, set = 1, binding = 2) WAVEFRONT_ACCESS buffer RayBuffer { WAVEFRONT_WORD ray_words[]; };
layout(std430, set = 1, binding = 3) WAVEFRONT_ACCESS buffer HitBuffer { WAVEFRONT_WORD hit_words[]; };
layout(std430, set = 1, binding = 4) WAVEFRONT_ACCESS buffer ShadowBuffer { WAVEFRONT_WORD shadow_words[]; };
layout(std430, set = 1, binding = 5) buffer CounterBuffer { Counters counters; };
layout(std430, set = 1, binding = 6) buffer DispatchBuffer { DispatchArgs dispatch_args; };
layout(set = 1, binding = 7, rgba32ui) uniform readonly uimageBuffer path_texels;
layout(set = 1, binding = 8, rgba32ui) uniform readonly uimageBuffer ray_texels;
layout(set = 1, binding = 9, rgba32ui) uniform readonly uimageBuffer hit_texels;
layout(set = 1, binding = 10, rgba32ui) uniform readonly uimageBuffer shadow_texels;
// A bounce's rays partitioned by intersect for shade (partition.glsl): written as a
// storage buffer, read through a word view.
layout(std430, set = 1, binding = 11) writeonly buffer ShadeRayBuffer { uint shade_ray_words[]; };
layout(set = 1, binding = 12, r32ui) uniform readonly uimageBuffer shade_ray_texels;
// The frame's buffer as storage, for queue_args and shade_args to publish the queue
// lengths they fold (queue.glsl) after the frame: [0] ray queue q's length at q, how
// many of its items lie at its back end at 2 + q; [1] the shadow queue's length and
// back count; [2] the partition's parts' (the host sets them at a batch's start:
// render::wavefront::Wavefront::reset_queues).
layout(std430, set = 1, binding = 13) writeonly buffer QueueLengthBuffer { Frame frame_unused; uvec4 queue_lengths_out[3]; };
uint queue_ray_count(uint q) { return q == 0u ? queue_lengths[0].x : queue_lengths[0].y; }
uint queue_ray_back(uint q) { return q == 0u ? queue_lengths[0].z : queue_lengths[0].w; }
uint queue_shadow_count() { return queue_lengths[1].x; }
uint queue_shadow_back() { return queue_lengths[1].y; }
uint queue_part_count(uint p) { return p == 0u ? queue_lengths[2].x : queue_lengths[2].y; }
uint queue_part_back(uint p) { return p == 0u ? queue_lengths[2].z : queue_lengths[2].w; }

layout(push_constant) uniform PushBlock { Push push; };
#define frame frames[push.frame_index]

SPEC(SUBGROUPS_IN_ORDER);

// Linear thread index over a 2D grid of workgroups (queues can exceed 65535 groups).
// Where the device runs a workgroup's invocations in order, subgroup after subgroup
// (SUBGROUPS_IN_ORDER: llvmpipe, whose subgroup is one SIMD vector), the invocation's
// place in its workgroup is its subgroup's number times the subgroup size plus its
// lane, which llvmpipe has at hand; gl_LocalInvocationID there costs every vector of
// every kernel one integer division per lane (16 `divl` at 512 bits: llvmpipe
// derives it from the linear index with the workgroup's size, a run-time value).
uint thread_index() {
    uint local = SUBGROUPS_IN_ORDER ? gl_SubgroupID * gl_SubgroupSize + gl_SubgroupInvocationID
                                    : gl_LocalInvocationID.x;
    return (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * WORKGROUP_SIZE + local;
}

// Position of item i in a queue of n items of which `back` lie at its back end
// (queue.glsl): the front's items first, then the back's from the last slot down.
uint queue_position(uint i, uint n, uint back) {
    uint front = n - back;
    return i < front ? i : push.capacity - 1u - (i - front);
}

// Index of position pos of ray queue q in the ray buffer.
uint ray_slot_at(uint q, uint pos) { return q * push.capacity + pos; }

// Index of item i of ray queue q in the ray buffer.
uint ray_slot(uint q, uint i) {
    return ray_slot_at(q, queue_position(i, queue_ray_count(q), queue_ray_back(q)));
}

// Index of item i of the shadow queue the shadow kernel traces.
uint shadow_slot(uint i) { return queue_position(i, queue_shadow_count(), queue_shadow_back()); }

// Workgroups for n items on a 2D grid of at most 65535 x 65535 groups (the indirect
// dispatch arguments of a queue).
uvec3 dispatch_groups(uint n) {
    uint groups = (n + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    uint x = min(groups, 65535u);
    uint y = x == 0u ? 1u : (groups + x - 1u) / x;
    return uvec3(x, y, 1u);
}

// The queues' records: loads through the texel views (the storage buffers in
// SCENE_STORAGE variants), stores through the word buffers, each a texel of the record
// at a time (generated: generated/records.glsl).
#ifdef SCENE_STORAGE
uvec4 path_texel(uint k) { return wavefront_texel(path_words[k]); }
uvec4 ray_texel(uint k) { return wavefront_texel(ray_words[k]); }
uvec4 hit_texel(uint k) { return wavefront_texel(hit_words[k]); }
uvec4 shadow_texel(uint k) { return wavefront_texel(shadow_words[k]); }
#else
uvec4 path_texel(uint k) { return imageLoad(path_texels, int(k)); }
uvec4 ray_texel(uint k) { return imageLoad(ray_texels, int(k)); }
uvec4 hit_texel(uint k) { return imageLoad(hit_texels, int(k)); }
uvec4 shadow_texel(uint k) { return imageLoad(shadow_texels, int(k)); }
#endif
void path_word_store(uint k, uvec4 w) { path_words[k] = wavefront_word(w); }
void ray_word_store(uint k, uvec4 w) { ray_words[k] = wavefront_word(w); }
void hit_word_store(uint k, uvec4 w) { hit_words[k] = wavefront_word(w); }
void shadow_word_store(uint k, uvec4 w) { shadow_words[k] = wavefront_word(w); }
// Path states lie split: texel k of path i at k * capacity + i, so that the shadow
// kernel's read and write of a path's radiance touch a dense array of radiances, not
// the cache lines of whole states (Cornell box at 16 lanes, 256^2 64 spp: shadow 135 ->
// 87 ms; the media cube's shadow 83 -> 76 ms; shade and first_bounce, which read and
// write every texel, unchanged).
PathState_LOAD_SPLIT(path_load, path_texel, push.capacity)
PathState_STORE_SPLIT(path_store, path_word_store, push.capacity)
RayItem_LOAD(ray_load, ray_texel)
RayItem_STORE(ray_store, ray_word_store)
HitItem_LOAD(hit_load, hit_texel)
HitItem_STORE(hit_store, hit_word_store)
ShadowItem_LOAD(shadow_load, shadow_texel)
ShadowItem_STORE(shadow_store, shadow_word_store)

// Every word of path i but the radiance one: what a bounce changes when the radiance
// was stored already (path_store_radiance) or did not change.
void path_store_bounce(uint i, PathState p) {
    path_word_store(i, PathState_WORD0(p));
    path_word_store(2u * push.capacity + i, PathState_WORD2(p));
}

// Only the word with the flags (and the MIS pdf, eta scale and medium) of path i.
void path_store_flags(uint i, PathState p) {
    path_word_store(2u * push.capacity + i, PathState_WORD2(p));
}

// Only the radiance word (with the sample index it shares) of path i.
void path_store_radiance(uint i, PathState p) {
    path_word_store(push.capacity + i, PathState_WORD1(p));
}

// The second-nearest hit of ray i (bvh_closest_two), which intersect keeps after the
// nearest ones in scenes whose rays cross null surfaces (vol_path.glsl).
HitItem hit_second_load(uint i) { return hit_load(push.capacity + i); }
void hit_second_store(uint i, HitItem h) { hit_store(push.capacity + i, h); }

#endif
