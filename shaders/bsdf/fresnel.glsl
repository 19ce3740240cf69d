// Fresnel reflectance of smooth dielectric and conductor interfaces (unpolarized).
#ifndef FRESNEL_GLSL
#define FRESNEL_GLSL

// Dielectric interface with relative index eta = η_int / η_ext (interior: below the
// surface, z < 0). cos_i is the cosine of the incident direction with the normal; its
// sign says from which side light arrives (> 0: from outside). Returns the reflectance
// F; cos_t is the signed cosine of the refracted direction (opposite sign to cos_i, 0
// on total internal reflection), eta_it = η_t/η_i and eta_ti = η_i/η_t for this side.
// Born and Wolf, "Principles of Optics", sec. 1.5.2 (Fresnel's s and p amplitudes);
// written as in Mitsuba 3's fresnel() (include/mitsuba/render/fresnel.h).
float fresnel_dielectric(float cos_i, float eta, out float cos_t, out float eta_it, out float eta_ti) {
    bool outside = cos_i >= 0.0;
    eta_it = outside ? eta : 1.0 / eta;
    eta_ti = 1.0 / eta_it;
    // Snell: sin²θt = (η_i/η_t)² sin²θi.
    float cos_t_sqr = 1.0 - eta_ti * eta_ti * (1.0 - cos_i * cos_i);
    float ci = abs(cos_i);
    if (eta == 1.0) {
        cos_t = -cos_i;
        return 0.0;
    }
    if (cos_t_sqr <= 0.0) {
        cos_t = 0.0;
        return 1.0; // total internal reflection
    }
    float ct = sqrt(cos_t_sqr);
    float a_s = (ci - eta_it * ct) / (ci + eta_it * ct);
    float a_p = (eta_it * ci - ct) / (eta_it * ci + ct);
    cos_t = outside ? -ct : ct;
    return 0.5 * (a_s * a_s + a_p * a_p);
}

float fresnel_dielectric_f(float cos_i, float eta) {
    float cos_t, eta_it, eta_ti;
    return fresnel_dielectric(cos_i, eta, cos_t, eta_it, eta_ti);
}

// Reflectance R' = 2R / (1 + R) of a thin dielectric slab (two parallel interfaces,
// light leaves undeflected) at cosine cos_i from either side: R, the Fresnel
// reflectance of one interface taken as from outside, with T = 1 - R summed over the
// inter-reflections, R' = R + T² R / (1 - R²) (Mitsuba's thindielectric.cpp).
float fresnel_thin_slab(float cos_i, float eta) {
    float r = fresnel_dielectric_f(abs(cos_i), eta);
    return 2.0 * r / (1.0 + r);
}

// Complex arithmetic on vec2 = (re, im).
vec2 fresnel_cmul(vec2 a, vec2 b) { return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }
vec2 fresnel_cdiv(vec2 a, vec2 b) { return vec2(a.x * b.x + a.y * b.y, a.y * b.x - a.x * b.y) / dot(b, b); }
vec2 fresnel_csqrt(vec2 z) {
    float n = length(z);
    if (n == 0.0) return vec2(0.0);
    float t1 = sqrt(0.5 * (n + abs(z.x)));
    float t2 = 0.5 * z.y / t1;
    return z.x >= 0.0 ? vec2(t1, t2) : vec2(abs(t2), z.y >= 0.0 ? t1 : -t1);
}

// Reflectance of a conductor with complex index η + iκ (relative to the outside) for
// light arriving at cos_i (> 0; |cos_i| is used). Fresnel equations with a complex
// index of refraction (PBR 4th ed., sec. 9.3.6, FrComplex); η = 0, κ = 1 gives 1.
float fresnel_conductor1(float cos_i, float eta, float k) {
    cos_i = clamp(abs(cos_i), 0.0, 1.0);
    vec2 e = vec2(eta, k);
    float sin2_i = 1.0 - cos_i * cos_i;
    vec2 sin2_t = fresnel_cdiv(vec2(sin2_i, 0.0), fresnel_cmul(e, e));
    vec2 cos_t = fresnel_csqrt(vec2(1.0, 0.0) - sin2_t);
    vec2 ec = e * cos_i;
    vec2 ect = fresnel_cmul(e, cos_t);
    vec2 r_parl = fresnel_cdiv(ec - cos_t, ec + cos_t);
    vec2 r_perp = fresnel_cdiv(vec2(cos_i, 0.0) - ect, vec2(cos_i, 0.0) + ect);
    return 0.5 * (dot(r_parl, r_parl) + dot(r_perp, r_perp));
}

vec3 fresnel_conductor(float cos_i, vec3 eta, vec3 k) {
    return vec3(fresnel_conductor1(cos_i, eta.x, k.x), fresnel_conductor1(cos_i, eta.y, k.y),
                fresnel_conductor1(cos_i, eta.z, k.z));
}

#endif
