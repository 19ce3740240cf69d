// Rough conductor (Mitsuba `roughconductor`): Cook-Torrance microfacet reflection
// f = F(wo·m) D(m) G(wo, wi, m) / (4 cos θo cos θi), m = normalize(wo + wi)
// (Walter et al. 2007, eq. 20), F the conductor Fresnel term times
// `specular_reflectance`. One-sided.
// Sampling: a microfacet normal from microfacet_sample, then mirror wo about it;
// pdf(wi) = pdf(m) / (4 |wi·m|) per unit solid angle (Walter 2007, eq. 14).

vec3 bsdf_roughconductor_eval(BsdfRecord b, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return vec3(0.0);
    Microfacet d = bsdf_microfacet_of(b);
    vec3 m = normalize(wo + wi);
    float D = microfacet_d(d, m);
    if (D == 0.0) return vec3(0.0);
    float G = microfacet_g(d, wo, wi, m);
    vec3 F = b.specular * fresnel_conductor(dot(wo, m), b.cond_eta, b.cond_k);
    // f cos θi = F D G / (4 cos θo).
    return F * (D * G / (4.0 * wo.z));
}

float bsdf_roughconductor_pdf(BsdfRecord b, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
    Microfacet d = bsdf_microfacet_of(b);
    vec3 m = normalize(wo + wi);
    float wim = dot(wi, m);
    if (wim <= 0.0) return 0.0;
    return microfacet_pdf(d, wo, m) / (4.0 * wim);
}

BsdfSample bsdf_roughconductor_sample(BsdfRecord b, vec3 wo, vec3 u) {
    BsdfSample s = bsdf_sample_none();
    if (wo.z <= 0.0) return s;
    Microfacet d = bsdf_microfacet_of(b);
    vec3 m = microfacet_sample(d, wo, u.yz);
    float wom = dot(wo, m);
    if (wom <= 0.0) return s;
    vec3 wi = 2.0 * wom * m - wo;
    if (wi.z <= 0.0) return s;
    float pdf = microfacet_pdf(d, wo, m) / (4.0 * wom);
    if (!(pdf > 0.0)) return s;
    // f cos / pdf: visible normals give G1(wi, m) (Heitz 2018, eq. 19);
    // D cos θm sampling gives G |wo·m| / (cos θo cos θm) (Walter 2007, eq. 38).
    float g = microfacet_samples_visible(d) ? microfacet_g1(d, wi, m)
                                            : microfacet_g(d, wo, wi, m) * wom / (wo.z * m.z);
    vec3 F = b.specular * fresnel_conductor(wom, b.cond_eta, b.cond_k);
    return BsdfSample(wi, F * g, pdf, BSDF_FLAG_REFLECTION);
}
