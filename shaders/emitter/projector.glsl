// A projector's directions (Mitsuba `projector`; emitter::projector): image point uv
// to a unit direction in the projector's frame, through the image plane z = 1 that
// spans ±tan_half; and the density per unit solid angle of that direction when uv is
// uniform: 1 / (A cos³ θ) (A = 4 tan_x tan_y the plane's area; dω = cos³ θ dA on the
// plane z = 1). `wavetrace warptest projector` tests the pair.
#ifndef EMITTER_PROJECTOR_GLSL
#define EMITTER_PROJECTOR_GLSL

vec3 emitter_projector_direction(vec2 uv, vec2 tan_half) {
    return normalize(vec3((1.0 - 2.0 * uv) * tan_half, 1.0));
}

float emitter_projector_direction_pdf(vec3 d, vec2 tan_half) {
    if (!(d.z > 0.0)) return 0.0;
    vec2 p = d.xy / d.z;
    if (any(greaterThan(abs(p), tan_half))) return 0.0;
    return 1.0 / (4.0 * tan_half.x * tan_half.y * d.z * d.z * d.z);
}

#endif
