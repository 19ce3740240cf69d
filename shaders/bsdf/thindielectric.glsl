// Thin dielectric slab (Mitsuba `thindielectric`, src/bsdfs/thindielectric.cpp): two
// parallel interfaces so close that light leaves undeflected. With the Fresnel
// reflectance R of one interface at the incident angle (fresnel_dielectric of |cos θ|,
// as from outside: both faces alike) and T = 1 - R, the inter-reflections sum to
//   R' = R + T² R (1 + R² + R⁴ + ...) = R + T² R / (1 - R²) = 2R / (1 + R)
// (fresnel_thin_slab) reflected specularly, and 1 - R' transmitted straight through (wi = -wo): Mitsuba's
// null lobe (no bending, relative index 1, so no (η_i/η_t)² radiance scaling).
// Sampling picks reflection with probability R' (weight specular_reflectance) or
// transmission with 1 - R' (weight specular_transmittance). Delta lobes only, so eval
// and pdf are 0. The volumetric path tracers treat the transmission as a null
// crossing instead (vol_path.glsl, transmittance.glsl), as Mitsuba's volpath does.

BsdfSample bsdf_thindielectric_sample(BsdfRecord b, vec3 wo, vec3 u) {
    if (wo.z == 0.0) return bsdf_sample_none();
    float r = fresnel_thin_slab(wo.z, b.eta);
    if (u.x < r) {
        // f cos / P = R' specular / R'.
        return BsdfSample(vec3(-wo.x, -wo.y, wo.z), b.specular, 0.0, BSDF_FLAG_REFLECTION | BSDF_FLAG_DELTA);
    }
    return BsdfSample(-wo, b.transmittance, 0.0, BSDF_FLAG_TRANSMISSION | BSDF_FLAG_NULL | BSDF_FLAG_DELTA);
}
