#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
// The smallest kernel that shows llvmpipe's 512-bit abort (examples/int64_store.rs,
// tools/mesa_int64_store.sh): each invocation stores one 16-byte word as two 64-bit
// components (u64vec2 from packUint2x32), as the WAVEFRONT_INT64 queue stores of
// shaders/queue/wavefront.glsl do.
// MODE, a specialization constant (so the driver sees only that mode's code):
//   0: words[i] = u64vec2(packUint2x32(..), ..)   (each lane its own slot, in order)
//   1: words[(i * 7) % count] = the same           (a divergent scatter, as queue pushes)
//   2: words32[(i * 7) % count] = uvec4            (32-bit stores: the control)
//   3: words[i] built with shifts and ors instead of packUint2x32
layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) writeonly buffer Words64 { u64vec2 words[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Words32 { uvec4 words32[]; };

layout(constant_id = 0) const uint MODE = 1u;

layout(push_constant) uniform PushBlock {
    uint count;
} pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    uvec4 w = uvec4(i, i ^ 0x55555555u, ~i, i * 2654435761u);
    uint slot = MODE == 1u || MODE == 2u ? (i * 7u) % pc.count : i;
    if (MODE == 2u) {
        words32[slot] = w;
    } else if (MODE == 3u) {
        words[slot] = u64vec2(uint64_t(w.x) | (uint64_t(w.y) << 32), uint64_t(w.z) | (uint64_t(w.w) << 32));
    } else {
        words[slot] = u64vec2(packUint2x32(w.xy), packUint2x32(w.zw));
    }
}
