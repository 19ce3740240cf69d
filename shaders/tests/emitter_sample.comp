#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel: emitter_sample from a point, then the ray along each sampled direction
// traced to what it hits and emitter_pdf_hit / emitter_pdf_env evaluated there, so
// tests/emitters.rs can check the choice of emitter and triangle and that the density
// used for MIS on a hit equals the density of sampling that point. With mode 1, the
// directions come from dirs[] instead (nothing is sampled): the probe then holds the
// density of emitter sampling in that direction, for a chi-square test of the
// sampled directions.

#include "scene/scene_bindings.glsl"

layout(local_size_x = 64) in;

layout(std430, set = 1, binding = 0) readonly buffer FrameBuffer { Frame frame; };
// Per sample two vec4: (wi, pdf), (dist, pdf at the hit, hit primitive, emitter).
layout(std430, set = 1, binding = 1) writeonly buffer OutBuffer { vec4 probe[]; };
layout(std430, set = 1, binding = 2) readonly buffer DirBuffer { vec4 dirs[]; };

layout(push_constant) uniform PushBlock {
    vec3 x;
    uint count;
    uint seed;
    uint mode;
} pc;

// The primitives the traversal tests in turn (accel::FlatPrims::constants of the
// tree: the scene's few quadrics apart from it), as in the renderer's kernels.
layout(constant_id = 0) const uint FLAT_PRIMS = 0u;
layout(constant_id = 1) const uint FLAT_KINDS = 0u;
#define BVH_FLAT_PRIMS FLAT_PRIMS
#define BVH_FLAT_KINDS FLAT_KINDS
#include "accel/bvh.glsl"
#include "sampling/rng.glsl"
#include "emitter/emitter.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    EmitterSample es;
    if (pc.mode == 1u) {
        es = EmitterSample(normalize(dirs[i].xyz), 0.0, vec3(0.0), 1.0, false, NONE);
    } else {
        es = emitter_sample(pc.x, rng_4d(i, 0u, 7u, pc.seed).xy);
    }
    float pdf_hit = 0.0;
    uint prim = NONE;
    if (!es.delta && es.pdf > 0.0) {
        Hit h = bvh_closest(pc.x, es.wi, 0.0, EMITTER_INFINITY);
        prim = h.prim;
        if (h.prim != HIT_NONE) {
            Surface s = surface_at(h.prim, h.u, h.v, pc.x, es.wi, h.t);
            uint e = shape_load(s.shape).emitter;
            if (e != NONE) pdf_hit = emitter_pdf_hit(e, pc.x, es.wi, h.t, s.ng, s.uv);
        } else if (frame.env_emitter != NONE) {
            pdf_hit = emitter_pdf_env(es.wi);
        }
    }
    probe[2u * i] = vec4(es.wi, es.pdf);
    probe[2u * i + 1u] = vec4(es.dist, pdf_hit, uintBitsToFloat(prim), uintBitsToFloat(es.emitter));
}
