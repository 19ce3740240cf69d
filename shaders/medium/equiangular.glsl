// Equiangular sampling of a distance along a ray towards a point c (Kulla and Fajardo
// 2012, "Importance Sampling Techniques for Path Tracing in Participating Media",
// EGSR, sec. 4.1): t in [a, b] with density proportional to 1 / (D² + (t - Δ)²), the
// inverse squared distance from o + t d to c, where Δ = d·(c - o) is the foot of the
// perpendicular from c and D = |c - o - Δ d| its length. With θ the angle at c from
// the perpendicular, t - Δ = D tan θ and θ is uniform on [θa, θb]:
//   pdf(t) = D / ((θb - θa) (D² + (t - Δ)²))  per unit length.
// b may be infinite (θb = π/2). d must be unit.
#ifndef EQUIANGULAR_GLSL
#define EQUIANGULAR_GLSL

#include "sampling/warp.glsl"

struct Equiangular {
    float delta;
    float D;
    float theta_a;
    float theta_b;
};

Equiangular equiangular_setup(vec3 o, vec3 d, vec3 c, float a, float b) {
    Equiangular e;
    e.delta = dot(c - o, d);
    // A point on the line itself would make the density 1/(t - Δ)², not integrable:
    // keep it a tiny distance off.
    e.D = max(length(c - o - e.delta * d), 1e-6 * (abs(e.delta) + length(c - o) + 1e-20));
    e.theta_a = atan(a - e.delta, e.D);
    e.theta_b = isinf(b) ? 0.5 * PI : atan(b - e.delta, e.D);
    return e;
}

float equiangular_pdf(Equiangular e, float t) {
    float x = t - e.delta;
    return e.D / ((e.theta_b - e.theta_a) * (e.D * e.D + x * x));
}

// t for uniform u in [0, 1), clamped to [a, b] against rounding.
float equiangular_sample(Equiangular e, float a, float b, float u) {
    float theta = mix(e.theta_a, e.theta_b, u);
    return clamp(e.delta + e.D * tan(theta), a, b);
}

#endif
