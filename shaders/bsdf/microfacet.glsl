// Microfacet normal distributions (Beckmann and GGX / Trowbridge-Reitz, anisotropic),
// Smith shadowing-masking and the sampling of microfacet normals. Directions in the
// local frame (z = macro-surface normal).
//
// Walter, Marschner, Li, Torrance 2007, "Microfacet Models for Refraction through
// Rough Surfaces" (EGSR): D, G1 for Beckmann (eq. 25, 27) and GGX (eq. 33, 34).
// Anisotropic forms: Heitz 2014, "Understanding the Masking-Shadowing Function in
// Microfacet-Based BRDFs", JCGT 3(2), sec. 5.
//
// Sampling: GGX samples the distribution of visible normals (Heitz 2018, "Sampling the
// GGX Distribution of Visible Normals", JCGT 7(4), listing 1). Beckmann samples the
// full distribution D(m) cos θm (Walter 2007, eq. 28 with the anisotropic azimuth of
// Mitsuba), not its visible normals.
#ifndef MICROFACET_GLSL
#define MICROFACET_GLSL

#include "sampling/warp.glsl"

// Distribution types; the values of BSDF_BECKMANN / BSDF_GGX in layout.glsl.
#define MICROFACET_BECKMANN 0u
#define MICROFACET_GGX 1u

struct Microfacet {
    uint type;
    float alpha_u; // roughness along the tangent (x)
    float alpha_v; // roughness along the bitangent (y)
};

// D(m): density of microfacet normals per unit projected area and solid angle, so that
// ∫ D(m) cos θm dωm = 1.
float microfacet_d(Microfacet d, vec3 m) {
    float cos2 = m.z * m.z;
    if (m.z <= 0.0) return 0.0;
    float ax = m.x / d.alpha_u, ay = m.y / d.alpha_v;
    float r;
    if (d.type == MICROFACET_BECKMANN) {
        r = exp(-(ax * ax + ay * ay) / cos2) / (PI * d.alpha_u * d.alpha_v * cos2 * cos2);
    } else {
        float t = ax * ax + ay * ay + cos2;
        r = 1.0 / (PI * d.alpha_u * d.alpha_v * t * t);
    }
    // As Mitsuba: drop values too small to matter (they only cause trouble later).
    return r * m.z > 1e-20 ? r : 0.0;
}

// Smith's G1 for direction v and microfacet m. Beckmann: the rational approximation of
// Walter 2007, eq. 27 (< 0.35% relative error); GGX: eq. 34. Zero when v sees the back
// of the microfacet or lies on the other side of the macro-surface.
float microfacet_g1(Microfacet d, vec3 v, vec3 m) {
    if (dot(v, m) * v.z <= 0.0) return 0.0;
    float xy = d.alpha_u * d.alpha_u * v.x * v.x + d.alpha_v * d.alpha_v * v.y * v.y;
    if (xy == 0.0) return 1.0;
    float tan2 = xy / (v.z * v.z); // α² tan² θv
    if (d.type == MICROFACET_BECKMANN) {
        float a = inversesqrt(tan2);
        if (a >= 1.6) return 1.0;
        return (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a);
    }
    return 2.0 / (1.0 + sqrt(1.0 + tan2));
}

// Separable Smith shadowing-masking G(wo, wi, m) = G1(wo, m) G1(wi, m) (Walter eq. 23).
float microfacet_g(Microfacet d, vec3 wo, vec3 wi, vec3 m) {
    return microfacet_g1(d, wo, m) * microfacet_g1(d, wi, m);
}

// GGX visible normals for wo in the upper hemisphere: Heitz 2018, listing 1.
vec3 microfacet_ggx_sample_visible(Microfacet d, vec3 wo, vec2 u) {
    vec3 vh = normalize(vec3(d.alpha_u * wo.x, d.alpha_v * wo.y, wo.z));
    float lensq = vh.x * vh.x + vh.y * vh.y;
    vec3 t1 = lensq > 0.0 ? vec3(-vh.y, vh.x, 0.0) * inversesqrt(lensq) : vec3(1.0, 0.0, 0.0);
    vec3 t2 = cross(vh, t1);
    float r = sqrt(u.x);
    float phi = 2.0 * PI * u.y;
    float p1 = r * cos(phi);
    float p2 = r * sin(phi);
    float s = 0.5 * (1.0 + vh.z);
    p2 = (1.0 - s) * sqrt(max(0.0, 1.0 - p1 * p1)) + s * p2;
    vec3 nh = p1 * t1 + p2 * t2 + sqrt(max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
    return normalize(vec3(d.alpha_u * nh.x, d.alpha_v * nh.y, max(1e-7, nh.z)));
}

// Beckmann normals with density D(m) cos θm: Walter 2007, eq. 28; for α_u != α_v the
// azimuth follows tan φ = (α_v/α_u) tan(2π u) and α² the projected roughness.
vec3 microfacet_beckmann_sample(Microfacet d, vec2 u) {
    float phi = 2.0 * PI * u.y;
    float cos_phi = cos(phi), sin_phi = sin(phi);
    float alpha2 = d.alpha_u * d.alpha_u;
    if (d.alpha_u != d.alpha_v) {
        // Keep φ in the quadrant of 2πu (atan of the scaled tangent).
        vec2 c = normalize(vec2(d.alpha_u * cos_phi, d.alpha_v * sin_phi));
        cos_phi = c.x;
        sin_phi = c.y;
        alpha2 = 1.0 / (cos_phi * cos_phi / (d.alpha_u * d.alpha_u) + sin_phi * sin_phi / (d.alpha_v * d.alpha_v));
    }
    float tan2 = -alpha2 * log(1.0 - u.x);
    float cos_theta = inversesqrt(1.0 + tan2);
    float sin_theta = sqrt(max(0.0, 1.0 - cos_theta * cos_theta));
    return vec3(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta);
}

// A microfacet normal for outgoing direction wo (wo.z > 0).
vec3 microfacet_sample(Microfacet d, vec3 wo, vec2 u) {
    if (d.type == MICROFACET_GGX) return microfacet_ggx_sample_visible(d, wo, u);
    return microfacet_beckmann_sample(d, u);
}

// Density of microfacet_sample choosing m, per unit solid angle of m. GGX: the visible
// normal density D_wo(m) = G1(wo, m) max(0, wo·m) D(m) / cos θo (Heitz 2018, eq. 3);
// Beckmann: D(m) cos θm.
float microfacet_pdf(Microfacet d, vec3 wo, vec3 m) {
    if (d.type == MICROFACET_GGX) {
        if (wo.z <= 0.0) return 0.0;
        return microfacet_d(d, m) * microfacet_g1(d, wo, m) * max(0.0, dot(wo, m)) / wo.z;
    }
    return microfacet_d(d, m) * max(0.0, m.z);
}

// Whether wo's G1 factor is already in the sampling density (visible normals).
bool microfacet_samples_visible(Microfacet d) { return d.type == MICROFACET_GGX; }

#endif
