// Unsigned division by a float quotient: llvmpipe (Mesa 22.3) has no vector integer
// division and divides lane by lane, each a scalar divide of some 20-40 cycles on
// x86. The float quotient f of a / b is within (a / b) 2^-23 of it (a rounds to a
// float within 2^-24 a, the division within half an ulp), less than 1 while the
// quotient is below 2^23, so trunc(f) is the quotient or one off it and one
// correcting step makes it exact. The kernels' quotients stay below 2^23: path and
// pixel indices, within a batch of at most MAX_BATCH_PATHS paths (render/mod.rs).
#ifndef DIVIDE_GLSL
#define DIVIDE_GLSL

#include "numeric/convert.glsl"

// (a / b, a % b) for 0 < b <= 2^30 and a / b < 2^23.
uvec2 divide(uint a, uint b) {
    int q = int(floor_to_uint(float(a) / float(b)));
    // a - q b, within [-b, 2b): an int for b <= 2^30.
    int r = int(a - uint(q) * b);
    if (r < 0) {
        q -= 1;
        r += int(b);
    } else if (r >= int(b)) {
        q += 1;
        r -= int(b);
    }
    return uvec2(uint(q), uint(r));
}

#endif
