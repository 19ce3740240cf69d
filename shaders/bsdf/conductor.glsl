// Smooth conductor (Mitsuba `conductor`, Nori `mirror`): a perfect specular
// reflection scaled by the Fresnel reflectance of the complex index η + iκ and by
// `specular_reflectance`. One-sided; a delta lobe, so eval and pdf are 0.

BsdfSample bsdf_conductor_sample(BsdfRecord b, vec3 wo, vec3 u) {
    BsdfSample s = bsdf_sample_none();
    if (wo.z <= 0.0) return s;
    vec3 weight = b.specular * fresnel_conductor(wo.z, b.cond_eta, b.cond_k);
    return BsdfSample(vec3(-wo.x, -wo.y, wo.z), weight, 0.0, BSDF_FLAG_REFLECTION | BSDF_FLAG_DELTA);
}
