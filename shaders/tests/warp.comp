#version 460
#extension GL_GOOGLE_include_directive : require
// Test kernel for tests/chi2.rs: the warps of warp.glsl and the microfacet normal
// samplers of microfacet.glsl against their densities.
// warp: 0 square to disk (x, y), 1 uniform hemisphere, 2 cosine hemisphere, 3 uniform
// sphere, 4 spherical cap (param.x = cos θmax), 5 triangle barycentrics (b0, b1),
// 6 microfacet normal for wo = param.xyz (type, alpha_u, alpha_v in mf),
// 7 a deliberately mismatched pair for testing the test (wavetrace warptest
// mismatched_cosine): cosine-weighted samples against the uniform hemisphere's pdf,
// 8 the thin lens's aperture (x, y on the unit disk), 9 a projector's directions for
// uniform image points (param.xy = tan of the half fields of view).
// mode 0 (sample): out[i] = (point, pdf at the point); mode 1: out[i].x = pdf(points[i]).

#include "sampling/warp.glsl"
#include "bsdf/microfacet.glsl"
#include "sampling/rng.glsl"
#include "sensor/thinlens.glsl"
#include "emitter/projector.glsl"

layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly buffer PointBuffer { vec4 points[]; };
layout(std430, set = 0, binding = 1) writeonly buffer OutBuffer { vec4 outs[]; };

layout(push_constant) uniform PushBlock {
    vec4 param;
    vec4 mf; // x: type (as float), y: alpha_u, z: alpha_v
    uint warp;
    uint mode;
    uint count;
    uint seed;
} pc;

Microfacet mf() { return Microfacet(uint(pc.mf.x), pc.mf.y, pc.mf.z); }

float warp_pdf(vec3 p) {
    switch (pc.warp) {
    case 0u: return warp_square_to_disk_pdf(p.xy);
    case 1u: return warp_uniform_hemisphere_pdf(p);
    case 2u: return warp_cosine_hemisphere_pdf(p);
    case 3u: return warp_uniform_sphere_pdf(p);
    case 4u: return warp_uniform_cap_pdf(p, pc.param.x);
    case 5u: return warp_uniform_triangle_pdf(p.xy);
    case 7u: return warp_uniform_hemisphere_pdf(p);
    case 8u: return camera_thinlens_aperture_pdf(p.xy);
    case 9u: return emitter_projector_direction_pdf(p, pc.param.xy);
    default: return microfacet_pdf(mf(), pc.param.xyz, p);
    }
}

vec3 warp_sample(vec2 u) {
    switch (pc.warp) {
    case 0u: return vec3(warp_square_to_disk(u), 0.0);
    case 1u: return warp_uniform_hemisphere(u);
    case 2u: return warp_cosine_hemisphere(u);
    case 3u: return warp_uniform_sphere(u);
    case 4u: return warp_uniform_cap(u, pc.param.x);
    case 5u: return vec3(warp_uniform_triangle(u), 0.0);
    case 7u: return warp_cosine_hemisphere(u);
    case 8u: return vec3(camera_thinlens_aperture(u), 0.0);
    case 9u: return emitter_projector_direction(u, pc.param.xy);
    default: return microfacet_sample(mf(), pc.param.xyz, u);
    }
}

void main() {
    uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (i >= pc.count) return;
    if (pc.mode == 0u) {
        uvec4 h = rng_pcg4d(uvec4(i, pc.seed, 0x85ebca6bu, 3u));
        vec3 p = warp_sample(vec2(rng_to_float(h.x), rng_to_float(h.y)));
        outs[i] = vec4(p, warp_pdf(p));
    } else {
        outs[i] = vec4(warp_pdf(points[i].xyz), 0.0, 0.0, 0.0);
    }
}
