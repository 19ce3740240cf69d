// How the viewer's window shows the picture (src/gpu/letterbox.rs): the picture fills
// the largest rectangle of its aspect ratio centred in the window, scaled with
// bilinear filtering, as vkCmdBlitImage's VK_FILTER_LINEAR does it (texel centres at
// half-integers, edges clamped), and bars of one grey around it. Where the rectangle
// is the picture's own size, every window pixel is exactly one picture pixel. The
// values are the 8-bit sRGB codes the tone mapping wrote, interpolated as codes.
#ifndef DISPLAY_LETTERBOX_GLSL
#define DISPLAY_LETTERBOX_GLSL

#include "numeric/convert.glsl"

// The picture's pixel (R in the lowest byte) at column x, row y, from the kernel's
// `letterbox_picture` (its pixels, top row first).
vec4 letterbox_texel(uint x, uint y, uint width) {
    return unpackUnorm4x8(letterbox_picture[y * width + x]);
}

// The picture sampled at window pixel p of the letterbox whose top-left is `origin`:
// the picture coordinates of p's centre (`step` picture pixels per window pixel),
// between the four nearest texel centres.
vec4 letterbox_sample(uvec2 p, uvec2 origin, vec2 step, uvec2 size) {
    vec2 c = max((vec2(p - origin) + 0.5) * step - 0.5, vec2(0.0));
    uvec2 i0 = min(uvec2(floor_to_uint(c.x), floor_to_uint(c.y)), size - 1u);
    uvec2 i1 = min(i0 + 1u, size - 1u);
    vec2 f = clamp(c - vec2(i0), 0.0, 1.0);
    vec4 top = mix(letterbox_texel(i0.x, i0.y, size.x), letterbox_texel(i1.x, i0.y, size.x), f.x);
    vec4 bottom =
        mix(letterbox_texel(i0.x, i1.y, size.x), letterbox_texel(i1.x, i1.y, size.x), f.x);
    return mix(top, bottom, f.y);
}

#endif
