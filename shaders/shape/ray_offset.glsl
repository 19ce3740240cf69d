// Spawning rays off a surface without hitting it again.
#ifndef RAY_OFFSET_GLSL
#define RAY_OFFSET_GLSL

#include "numeric/convert.glsl"

// Wächter and Binder 2019, "A Fast and Robust Method for Avoiding Self-Intersection",
// Ray Tracing Gems ch. 6, listing 6-1: move p along the geometric normal n by a few
// ulps of its own magnitude (an integer offset of the float bits), or by a small
// absolute amount near the origin where ulps are tiny. Holds at every scene scale.
vec3 ray_offset(vec3 p, vec3 n) {
    const float origin = 1.0 / 32.0;
    const float float_scale = 1.0 / 65536.0;
    const float int_scale = 256.0;
    ivec3 of_i = ivec3(trunc_to_int(int_scale * n.x), trunc_to_int(int_scale * n.y),
                       trunc_to_int(int_scale * n.z));
    vec3 p_i = vec3(
        intBitsToFloat(floatBitsToInt(p.x) + (p.x < 0.0 ? -of_i.x : of_i.x)),
        intBitsToFloat(floatBitsToInt(p.y) + (p.y < 0.0 ? -of_i.y : of_i.y)),
        intBitsToFloat(floatBitsToInt(p.z) + (p.z < 0.0 ? -of_i.z : of_i.z)));
    return vec3(
        abs(p.x) < origin ? p.x + float_scale * n.x : p_i.x,
        abs(p.y) < origin ? p.y + float_scale * n.y : p_i.y,
        abs(p.z) < origin ? p.z + float_scale * n.z : p_i.z);
}

#endif
