// Nori's `microfacet` BRDF (the course's assignment 5): a diffuse term plus a Beckmann
// specular lobe with a dielectric Fresnel term,
//   f = kd/π + ks D(m) F(wo·m, η) G(wo, wi, m) / (4 cos θo cos θi),  m = normalize(wo + wi),
// ks = 1 - max(kd) (b.specular_weight), D Beckmann with α (b.alpha_u), G Smith with the
// rational G1 of Walter 2007 eq. 27 (Nori's). One-sided.
// Sampling as Nori: with probability ks a Beckmann normal (density D cos θm) mirrored,
// else cosine-weighted; pdf = ks D(m) cos θm / (4 |wi·m|) + (1 - ks) cos θi / π.

Microfacet bsdf_nori_microfacet_of(BsdfRecord b) {
    return Microfacet(MICROFACET_BECKMANN, b.alpha_u, b.alpha_u);
}

vec3 bsdf_nori_microfacet_eval(BsdfRecord b, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return vec3(0.0);
    Microfacet d = bsdf_nori_microfacet_of(b);
    vec3 m = normalize(wo + wi);
    float spec = b.specular_weight * microfacet_d(d, m) * fresnel_dielectric_f(dot(wo, m), b.eta)
               * microfacet_g(d, wo, wi, m) / (4.0 * wo.z);
    return b.reflectance * (INV_PI * wi.z) + vec3(spec);
}

float bsdf_nori_microfacet_pdf(BsdfRecord b, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
    vec3 m = normalize(wo + wi);
    float ks = b.specular_weight;
    return ks * microfacet_d(bsdf_nori_microfacet_of(b), m) * m.z / (4.0 * dot(wi, m))
         + (1.0 - ks) * warp_cosine_hemisphere_pdf(wi);
}

BsdfSample bsdf_nori_microfacet_sample(BsdfRecord b, vec3 wo, vec3 u) {
    BsdfSample s = bsdf_sample_none();
    if (wo.z <= 0.0) return s;
    vec3 wi;
    if (u.x < b.specular_weight) {
        vec3 m = microfacet_beckmann_sample(bsdf_nori_microfacet_of(b), u.yz);
        wi = 2.0 * dot(wo, m) * m - wo;
    } else {
        wi = warp_cosine_hemisphere(u.yz);
    }
    if (wi.z <= 0.0) return s;
    float pdf = bsdf_nori_microfacet_pdf(b, wo, wi);
    if (!(pdf > 0.0)) return s;
    return BsdfSample(wi, bsdf_nori_microfacet_eval(b, wo, wi) / pdf, pdf, BSDF_FLAG_REFLECTION);
}

// Its lobes (kinds.rs hook `lobes`): the diffuse one only where kd > 0.
uint bsdf_nori_microfacet_lobes(BsdfRecord b, uint lobes) {
    return any(greaterThan(b.reflectance, vec3(0.0))) ? lobes : lobes & ~BSDF_LOBE_DIFFUSE;
}

// With a textured kd (kinds.rs hook `textured`): ks = 1 - max(kd).
BsdfRecord bsdf_nori_microfacet_textured(BsdfRecord b) {
    if (b.tex_reflectance != 0u) {
        b.specular_weight = 1.0 - max(b.reflectance.x, max(b.reflectance.y, b.reflectance.z));
    }
    return b;
}
