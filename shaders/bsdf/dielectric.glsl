// Smooth dielectric interface (Mitsuba `dielectric`, Nori `dielectric`): specular
// reflection with probability F and refraction with probability 1 - F (Fresnel of
// eta = int_ior / ext_ior), both sides: wo below the surface is inside, where the
// relative index is 1/eta. Radiance transport: refracted radiance is scaled by
// (η_i/η_t)², as Mitsuba does in radiance mode (Veach 1997, thesis, sec. 5.2).
// Delta lobes only, so eval and pdf are 0.

BsdfSample bsdf_dielectric_sample(BsdfRecord b, vec3 wo, vec3 u) {
    BsdfSample s = bsdf_sample_none();
    if (wo.z == 0.0) return s;
    float cos_t, eta_it, eta_ti;
    float F = fresnel_dielectric(wo.z, b.eta, cos_t, eta_it, eta_ti);
    if (u.x < F) {
        // f cos / P = F specular / F.
        return BsdfSample(vec3(-wo.x, -wo.y, wo.z), b.specular, 0.0, BSDF_FLAG_REFLECTION | BSDF_FLAG_DELTA);
    }
    // Snell's law in vector form (refract about n = +z).
    vec3 wi = vec3(-eta_ti * wo.x, -eta_ti * wo.y, cos_t);
    return BsdfSample(wi, b.transmittance * (eta_ti * eta_ti), 0.0, BSDF_FLAG_TRANSMISSION | BSDF_FLAG_DELTA);
}
