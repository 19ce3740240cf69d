// BSDFs: evaluation, sampling and density in the local shading frame (z = shading
// normal; wo, wi point away from the surface). Mitsuba's conventions: one-sided BRDFs,
// eval includes the cosine |cos θi|, pdf is per unit solid angle.
#ifndef BSDF_GLSL
#define BSDF_GLSL

#include "warp.glsl"

#define BSDF_FLAG_REFLECTION 1u
#define BSDF_FLAG_TRANSMISSION 2u
#define BSDF_FLAG_DELTA 4u

struct BsdfSample {
    vec3 wi;
    vec3 weight; // eval / pdf
    float pdf;
    uint flags;
};

// f(wo, wi) |cos θi|.
vec3 bsdf_eval(BsdfRecord b, vec3 wo, vec3 wi, vec2 uv) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return vec3(0.0);
    return b.reflectance * (INV_PI * wi.z);
}

float bsdf_pdf(BsdfRecord b, vec3 wo, vec3 wi, vec2 uv) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
    return warp_cosine_hemisphere_pdf(wi);
}

BsdfSample bsdf_sample(BsdfRecord b, vec3 wo, vec3 u, vec2 uv) {
    BsdfSample s;
    s.flags = BSDF_FLAG_REFLECTION;
    s.wi = warp_cosine_hemisphere(u.xy);
    s.pdf = warp_cosine_hemisphere_pdf(s.wi);
    s.weight = (wo.z > 0.0 && s.pdf > 0.0) ? b.reflectance : vec3(0.0);
    return s;
}

bool bsdf_is_delta(BsdfRecord b) { return false; }

#endif
