// Float-to-integer conversions that stay in SIMD registers on llvmpipe. Mesa 26 turns
// GLSL's int(x) and uint(x) into LLVM's saturating conversions, which LLVM 22 does not
// vectorize on x86: 7 instructions a lane, 112 a 16-lane vector (GALLIVM_DEBUG=asm; the
// Cornell box's first_bounce held 18 such conversions). These take three vector
// instructions on any device: an integer-valued float of small magnitude plus 2^23
// (or 1.5 2^23) lies in [2^23, 2^24), where a float's ulp is 1, so the integer is the
// low bits of its mantissa.
#ifndef CONVERT_GLSL
#define CONVERT_GLSL

// floor(x) for x <= 2^23 (uint(x) there), 0 for x < 0 (as Mesa's uint(x)).
uint floor_to_uint(float x) {
    return floatBitsToUint(floor(max(x, 0.0)) + 8388608.0) - 0x4b000000u;
}

// trunc(x) for |x| < 2^22 (int(x) there).
int trunc_to_int(float x) { return floatBitsToInt(trunc(x) + 12582912.0) - 0x4b400000; }

#endif
