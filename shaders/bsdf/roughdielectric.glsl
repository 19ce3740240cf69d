// Rough dielectric interface (Mitsuba `roughdielectric`): microfacet reflection and
// refraction of Walter, Marschner, Li, Torrance 2007, "Microfacet Models for
// Refraction through Rough Surfaces". Both sides; eta = int_ior / ext_ior, wo below
// the surface is inside (relative index 1/eta). Radiance transport, as Mitsuba's
// radiance mode: the (η_t/η_i)² of Walter's eq. 21 cancels against the 1/η² scaling
// of radiance, leaving f_t |cos θi| = (1-F) D G |wo·m| |wi·m| / (|cos θo| (wo·m + η wi·m)²).
// Sampling: a microfacet normal for wo (flipped to the upper side), reflection with
// probability F(wo·m), else refraction; pdf per unit solid angle with the Jacobians
// 1/(4|wi·m|) (eq. 14) and η² |wi·m| / (wo·m + η wi·m)² (eq. 17).

// Generalized half vector (eq. 13 / 16) on the upper side, or 0 if degenerate.
vec3 bsdf_roughdielectric_half(vec3 wo, vec3 wi, float eta, bool reflect) {
    vec3 m = wo + wi * (reflect ? 1.0 : eta);
    float len = length(m);
    if (len == 0.0) return vec3(0.0);
    m /= len;
    return m.z < 0.0 ? -m : m;
}

vec3 bsdf_roughdielectric_eval(BsdfRecord b, vec3 wo, vec3 wi) {
    float co = wo.z, ci = wi.z;
    if (co == 0.0 || ci == 0.0) return vec3(0.0);
    bool reflect = co * ci > 0.0;
    float eta = co > 0.0 ? b.eta : 1.0 / b.eta;
    vec3 m = bsdf_roughdielectric_half(wo, wi, eta, reflect);
    if (m.z == 0.0) return vec3(0.0);
    float wom = dot(wo, m), wim = dot(wi, m);
    // Both directions must see the front of m from their own side (eq. 15, 19).
    if (wom * co <= 0.0 || wim * ci <= 0.0) return vec3(0.0);
    Microfacet d = bsdf_microfacet_of(b);
    float D = microfacet_d(d, m);
    if (D == 0.0) return vec3(0.0);
    float G = microfacet_g(d, wo, wi, m);
    float F = fresnel_dielectric_f(wom, b.eta);
    if (reflect) return b.specular * (F * D * G / (4.0 * abs(co)));
    float denom = wom + eta * wim;
    return b.transmittance * abs((1.0 - F) * D * G * wom * wim / (co * denom * denom));
}

float bsdf_roughdielectric_pdf(BsdfRecord b, vec3 wo, vec3 wi) {
    float co = wo.z, ci = wi.z;
    if (co == 0.0 || ci == 0.0) return 0.0;
    bool reflect = co * ci > 0.0;
    float eta = co > 0.0 ? b.eta : 1.0 / b.eta;
    vec3 m = bsdf_roughdielectric_half(wo, wi, eta, reflect);
    if (m.z == 0.0) return 0.0;
    float wom = dot(wo, m), wim = dot(wi, m);
    if (wom * co <= 0.0 || wim * ci <= 0.0) return 0.0;
    float jacobian;
    if (reflect) {
        jacobian = 1.0 / (4.0 * abs(wim));
    } else {
        float denom = wom + eta * wim;
        jacobian = eta * eta * abs(wim) / (denom * denom);
    }
    Microfacet d = bsdf_microfacet_of(b);
    float F = fresnel_dielectric_f(wom, b.eta);
    float pm = microfacet_pdf(d, co > 0.0 ? wo : -wo, m);
    return pm * (reflect ? F : 1.0 - F) * jacobian;
}

BsdfSample bsdf_roughdielectric_sample(BsdfRecord b, vec3 wo, vec3 u) {
    BsdfSample s = bsdf_sample_none();
    float co = wo.z;
    if (co == 0.0) return s;
    Microfacet d = bsdf_microfacet_of(b);
    vec3 wo_up = co > 0.0 ? wo : -wo;
    vec3 m = microfacet_sample(d, wo_up, u.yz);
    float pm = microfacet_pdf(d, wo_up, m);
    float wom = dot(wo, m);
    if (!(pm > 0.0) || wom * co <= 0.0) return s;
    float cos_t, eta_it, eta_ti;
    float F = fresnel_dielectric(wom, b.eta, cos_t, eta_it, eta_ti);
    vec3 wi;
    float pdf;
    vec3 tint;
    uint flags;
    if (u.x < F) {
        wi = 2.0 * wom * m - wo;
        if (wi.z * co <= 0.0) return s;
        pdf = pm * F / (4.0 * abs(wom));
        tint = b.specular;
        flags = BSDF_FLAG_REFLECTION;
    } else {
        // Refraction about m (Walter 2007, eq. 40, in Mitsuba's form).
        wi = m * (wom * eta_ti + cos_t) - wo * eta_ti;
        if (wi.z * co >= 0.0) return s;
        float wim = dot(wi, m);
        float denom = wom + eta_it * wim;
        pdf = pm * (1.0 - F) * eta_it * eta_it * abs(wim) / (denom * denom);
        tint = b.transmittance * (eta_ti * eta_ti);
        flags = BSDF_FLAG_TRANSMISSION;
    }
    if (!(pdf > 0.0)) return s;
    // f cos / pdf: the microfacet terms leave G1(wi, m) (visible normals) or
    // G |wo·m| / (|cos θo| cos θm) (D cos θm sampling); Fresnel cancels.
    float g = microfacet_samples_visible(d) ? microfacet_g1(d, wi, m)
                                            : microfacet_g(d, wo, wi, m) * abs(wom) / (abs(co) * m.z);
    return BsdfSample(wi, tint * g, pdf, flags);
}
