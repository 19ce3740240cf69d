// Descriptor set 1: the wavefront's queues and path states, and the push constants.
// Bindings are mirrored in src/render/wavefront.rs.
#ifndef WAVEFRONT_GLSL
#define WAVEFRONT_GLSL

#include "layout.glsl"

#define WORKGROUP_SIZE 128
layout(local_size_x = WORKGROUP_SIZE) in;

layout(std430, set = 1, binding = 0) readonly buffer FrameBuffer { Frame frame; };
layout(std430, set = 1, binding = 1) buffer PathBuffer { PathState paths[]; };
layout(std430, set = 1, binding = 2) buffer RayBuffer { RayItem rays[]; };
layout(std430, set = 1, binding = 3) buffer HitBuffer { HitItem hits[]; };
layout(std430, set = 1, binding = 4) buffer ShadowBuffer { ShadowItem shadows[]; };
layout(std430, set = 1, binding = 5) buffer CounterBuffer { Counters counters; };
layout(std430, set = 1, binding = 6) buffer DispatchBuffer { DispatchArgs dispatch_args; };
layout(std430, set = 1, binding = 7) buffer FilmBuffer { vec4 film[]; };

layout(push_constant) uniform PushBlock { Push push; };

// Linear thread index over a 2D grid of workgroups (queues can exceed 65535 groups).
uint thread_index() {
    return (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * WORKGROUP_SIZE
        + gl_LocalInvocationID.x;
}

// Index of item i of ray queue q in the ray buffer.
uint ray_slot(uint q, uint i) { return q * push.capacity + i; }

#endif
