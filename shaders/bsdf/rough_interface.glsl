// What the microfacet models share beyond microfacet.glsl: the distribution a BSDF
// record holds, and the reflection off a rough dielectric interface that the coated
// models (roughplastic, pplastic) add to their diffuse part.

Microfacet bsdf_microfacet_of(BsdfRecord b) { return Microfacet(b.distribution, b.alpha_u, b.alpha_v); }

// f cos θi of the reflection off a rough dielectric interface of relative index b.eta,
// times b.specular: F(wo·m, η) D(m) G(wo, wi, m) / (4 cos θo), m = normalize(wo + wi)
// (Walter et al. 2007, eq. 20); wo and wi above the surface.
vec3 bsdf_rough_dielectric_reflection(BsdfRecord b, vec3 wo, vec3 wi) {
    Microfacet d = bsdf_microfacet_of(b);
    vec3 m = normalize(wo + wi);
    float D = microfacet_d(d, m);
    vec3 result = vec3(0.0);
    if (D > 0.0) {
        float F = fresnel_dielectric_f(dot(wo, m), b.eta);
        result = b.specular * (F * D * microfacet_g(d, wo, wi, m) / (4.0 * wo.z));
    }
    return result;
}
