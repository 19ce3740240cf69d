#version 460
#extension GL_GOOGLE_include_directive : require
// letterbox: the viewer's window image. One thread per window pixel writes the picture
// scaled into its letterbox, or the bars' grey around it, in the window's byte order;
// the swapchain copies the result into the window's image (src/gpu/swapchain.rs).
// Drawing it here rather than with vkCmdBlitImage keeps the window off the driver's
// graphics pipeline: llvmpipe at 512 bits (Mesa 26) crashes compiling its blit.
// Reads: the picture's pixels (tonemap's). Writes: the window's pixels.

#include "scene/layout.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) readonly buffer Picture { uint letterbox_picture[]; };
layout(set = 0, binding = 1) writeonly buffer Window { uint window[]; };

layout(push_constant) uniform LetterboxConstants { LetterboxPush push; };

#include "display/letterbox.glsl"

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= push.window_width || p.y >= push.window_height) return;
    uvec2 origin = uvec2(push.x, push.y);
    uvec2 end = origin + uvec2(push.width, push.height);
    uint pixel = push.bar;
    if (all(greaterThanEqual(p, origin)) && all(lessThan(p, end))) {
        vec4 c = letterbox_sample(p, origin, vec2(push.step_x, push.step_y),
                                  uvec2(push.picture_width, push.picture_height));
        pixel = packUnorm4x8(push.bgra != 0u ? c.bgra : c);
    }
    window[p.y * push.window_width + p.x] = pixel;
}
