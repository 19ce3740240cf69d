#version 460
#extension GL_GOOGLE_include_directive : require
// tonemap: the viewer's picture of the film. One thread per crop pixel develops the
// running mean from the film's sums and writes it as 8-bit sRGB RGBA, which the
// swapchain copies into the window (src/gpu/swapchain.rs); nothing goes to the host.
// Reads: the film's sums. Writes: the picture's pixels.

#include "scene/layout.glsl"
#include "display/tonemap.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) readonly buffer FilmSums { vec4 sums[]; };
layout(set = 0, binding = 1) writeonly buffer Pixels { uint pixels[]; };

layout(push_constant) uniform TonemapConstants { TonemapPush push; };

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= push.width || p.y >= push.height) return;
    uint i = p.y * push.width + p.x;
    pixels[i] = tonemap_pixel(sums[i], push.scale, push.luminance != 0u);
}
