// Polarized plastic (Mitsuba `pplastic`, after Baek et al. 2018) as Mitsuba's RGB
// (unpolarized) variants compute it: a rough dielectric microfacet reflection plus a
// Lambertian lobe attenuated by a smooth refraction in and one out, summed ad hoc:
//   f cos θi = spec · F(wo·m, η) D(m) G(wo, wi, m) / (4 cos θo)
//            + ρ (1 - F(cos θo, η)) (1 - F(cos θi, η)) cos θi / π
// Mitsuba 3, src/bsdfs/pplastic.cpp. Anisotropic; one-sided.
// Sampling: the microfacet lobe with the fixed probability b.specular_weight
// (s / (d + s), channel means), else cosine-weighted; pdf is the mixture (its
// specular part zero where wi sees the back of m), weight = eval / pdf.

vec3 bsdf_pplastic_eval(BsdfRecord b, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return vec3(0.0);
    vec3 result = bsdf_rough_dielectric_reflection(b, wo, wi);
    float to = 1.0 - fresnel_dielectric_f(wo.z, b.eta);
    float ti = 1.0 - fresnel_dielectric_f(wi.z, b.eta);
    return result + b.reflectance * (to * ti * wi.z * INV_PI);
}

float bsdf_pplastic_pdf(BsdfRecord b, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
    float ps = b.specular_weight;
    vec3 m = normalize(wo + wi);
    float wim = dot(wi, m);
    float spec = wim > 0.0 && dot(wo, m) > 0.0
        ? microfacet_pdf(bsdf_microfacet_of(b), wo, m) / (4.0 * wim) : 0.0;
    return ps * spec + (1.0 - ps) * warp_cosine_hemisphere_pdf(wi);
}

BsdfSample bsdf_pplastic_sample(BsdfRecord b, vec3 wo, vec3 u) {
    BsdfSample s = bsdf_sample_none();
    if (wo.z <= 0.0) return s;
    vec3 wi;
    if (u.x < b.specular_weight) {
        vec3 m = microfacet_sample(bsdf_microfacet_of(b), wo, u.yz);
        wi = 2.0 * dot(wo, m) * m - wo;
    } else {
        wi = warp_cosine_hemisphere(u.yz);
    }
    if (wi.z <= 0.0) return s;
    float pdf = bsdf_pplastic_pdf(b, wo, wi);
    if (!(pdf > 0.0)) return s;
    return BsdfSample(wi, bsdf_pplastic_eval(b, wo, wi) / pdf, pdf, BSDF_FLAG_REFLECTION);
}
