// Smooth plastic (Mitsuba `plastic`): a diffuse base under a smooth dielectric coating
// of relative index eta. Specular part: a delta reflection with weight F(cos θo)
// `specular_reflectance`. Diffuse part, with the internal scattering of the coating
// summed in closed form (Mitsuba 3, src/bsdfs/plastic.cpp; Weidlich and Wilkie 2007,
// "Arbitrarily Layered Micro-Facet Surfaces"):
//   f cos θi = ρ / (1 - F_dr ρ') · (1/η²) (1 - F(cos θo)) (1 - F(cos θi)) cos θi / π
// with F_dr = b.internal the diffuse Fresnel reflectance of the inside of the coating,
// ρ' = ρ when `nonlinear`, else 1. One-sided.
// Sampling: specular with probability P_s = F_o w / (F_o w + (1 - F_o)(1 - w)),
// w = b.specular_weight; else cosine-weighted, pdf (1 - P_s) cos θi / π.

vec3 bsdf_plastic_diffuse(BsdfRecord b, float fo, float fi, float cos_i) {
    vec3 rho = b.reflectance;
    vec3 denom = 1.0 - ((b.flags & BSDF_NONLINEAR) != 0u ? rho * b.internal : vec3(b.internal));
    return rho / denom * ((1.0 - fo) * (1.0 - fi) * cos_i * INV_PI / (b.eta * b.eta));
}

float bsdf_plastic_prob_specular(BsdfRecord b, float fo) {
    float ps = fo * b.specular_weight;
    float pd = (1.0 - fo) * (1.0 - b.specular_weight);
    return ps / (ps + pd);
}

vec3 bsdf_plastic_eval(BsdfRecord b, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return vec3(0.0);
    float fo = fresnel_dielectric_f(wo.z, b.eta);
    float fi = fresnel_dielectric_f(wi.z, b.eta);
    return bsdf_plastic_diffuse(b, fo, fi, wi.z);
}

float bsdf_plastic_pdf(BsdfRecord b, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
    float fo = fresnel_dielectric_f(wo.z, b.eta);
    return (1.0 - bsdf_plastic_prob_specular(b, fo)) * warp_cosine_hemisphere_pdf(wi);
}

BsdfSample bsdf_plastic_sample(BsdfRecord b, vec3 wo, vec3 u) {
    BsdfSample s = bsdf_sample_none();
    if (wo.z <= 0.0) return s;
    float fo = fresnel_dielectric_f(wo.z, b.eta);
    float ps = bsdf_plastic_prob_specular(b, fo);
    if (u.x < ps) {
        return BsdfSample(vec3(-wo.x, -wo.y, wo.z), b.specular * (fo / ps), 0.0,
                          BSDF_FLAG_REFLECTION | BSDF_FLAG_DELTA);
    }
    vec3 wi = warp_cosine_hemisphere(u.yz);
    float pdf = (1.0 - ps) * warp_cosine_hemisphere_pdf(wi);
    if (!(pdf > 0.0)) return s;
    float fi = fresnel_dielectric_f(wi.z, b.eta);
    return BsdfSample(wi, bsdf_plastic_diffuse(b, fo, fi, wi.z) / pdf, pdf, BSDF_FLAG_REFLECTION);
}
