// Lambertian reflection: f = ρ/π (Mitsuba `diffuse`, Nori `diffuse`). One-sided.
// Sampling: cosine-weighted hemisphere (Malley), pdf cos θi / π per unit solid angle.

vec3 bsdf_diffuse_eval(BsdfRecord b, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return vec3(0.0);
    return b.reflectance * (INV_PI * wi.z);
}

float bsdf_diffuse_pdf(BsdfRecord b, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
    return warp_cosine_hemisphere_pdf(wi);
}

BsdfSample bsdf_diffuse_sample(BsdfRecord b, vec3 wo, vec3 u) {
    BsdfSample s = bsdf_sample_none();
    if (wo.z <= 0.0) return s;
    vec3 wi = warp_cosine_hemisphere(u.yz);
    float pdf = warp_cosine_hemisphere_pdf(wi);
    if (pdf <= 0.0) return s;
    // f cos / pdf = (ρ/π) cos / (cos/π) = ρ.
    return BsdfSample(wi, b.reflectance, pdf, BSDF_FLAG_REFLECTION);
}
