// Phase functions of participating media: isotropic and Henyey-Greenstein, with
// eval, sample and pdf. Directions follow Mitsuba's convention: wo points from the
// scattering point back along the incoming ray (wo = -ray.d), wi is the new direction,
// and every density is per unit solid angle around wi. A phase function is its own
// sampling density, so sampling weights are exactly 1.
#ifndef PHASE_GLSL
#define PHASE_GLSL

#include "sampling/frame.glsl"
#include "sampling/warp.glsl"

// Below this |g| the HG inversion loses precision; the function is isotropic there
// to within 1e-4 relative.
#define PHASE_HG_ISOTROPIC_EPS 1e-4

struct PhaseSample {
    vec3 wi;
    float pdf; // = phase_eval(g, wo, wi)
};

// Henyey and Greenstein 1941, "Diffuse radiation in the galaxy", ApJ 93, eq. (3),
// with θ the angle between the propagation directions -wo and wi:
//   p(wo, wi) = (1 - g²) / (4π (1 + g² + 2g (wo·wi))^{3/2}).
// g > 0 scatters forwards (wi near -wo), g < 0 backwards, g = 0 is isotropic (1/4π).
float phase_hg(float g, float cos_wo_wi) {
    float denom = 1.0 + g * g + 2.0 * g * cos_wo_wi;
    return INV_FOUR_PI * (1.0 - g * g) / (denom * sqrt(max(denom, 1e-30)));
}

float phase_eval(float g, vec3 wo, vec3 wi) {
    return phase_hg(g, dot(wo, wi));
}

float phase_pdf(float g, vec3 wo, vec3 wi) {
    return phase_eval(g, wo, wi);
}

// Samples wi with density phase_eval(g, wo, .). u: two uniform numbers. Inverts the
// CDF of cos θ = wi·(-wo) (Pharr, Jakob, Humphreys, PBR 3rd ed., sec. 15.2.3):
//   cos θ = (1 + g² - ((1 - g²) / (1 - g + 2g u))²) / (2g),
// and φ = 2π u uniform around -wo.
PhaseSample phase_sample(float g, vec3 wo, vec2 u) {
    float cos_theta;
    if (abs(g) < PHASE_HG_ISOTROPIC_EPS) {
        cos_theta = 1.0 - 2.0 * u.x;
    } else {
        float sqr = (1.0 - g * g) / (1.0 - g + 2.0 * g * u.x);
        cos_theta = clamp((1.0 + g * g - sqr * sqr) / (2.0 * g), -1.0, 1.0);
    }
    float sin_theta = sqrt(max(0.0, 1.0 - cos_theta * cos_theta));
    float phi = 2.0 * PI * u.y;
    vec3 local = vec3(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta);
    PhaseSample s;
    s.wi = normalize(frame_to_world(-wo, local));
    s.pdf = phase_eval(g, wo, s.wi);
    return s;
}

#endif
