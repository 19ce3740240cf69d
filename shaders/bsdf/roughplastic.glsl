// Rough plastic (Mitsuba `roughplastic`): microfacet reflection from a rough
// dielectric coating (as roughconductor, with the dielectric Fresnel term) plus a
// diffuse base seen through it:
//   f cos θi = spec · F D G / (4 cos θo)
//            + ρ / (1 - R_int ρ') · (1/η²) T(cos θo) T(cos θi) cos θi / π
// T(μ) = the rough coating's transmittance at μ (light that enters and is not
// shadowed), tabulated on the host at μ = i/63 as Mitsuba does (b.table, linear
// interpolation), R_int = b.internal its internal reflectance. Mitsuba 3,
// src/bsdfs/roughplastic.cpp; the tables: src/scene/bsdf/roughplastic.rs. Isotropic;
// one-sided.
// Sampling: the specular lobe with probability P_s = (1 - T_o) w / ((1 - T_o) w + T_o (1 - w)),
// else cosine-weighted; pdf is the mixture, weight = eval / pdf.

#include "numeric/convert.glsl"

// Word k (0..31) of b.table (entries 2k and 2k + 1 as unorm16), picked by selects
// between constant-indexed words: llvmpipe (Mesa 22.3) keeps a local array read at a
// dynamic index (b.table[k >> 2]) in per-lane scratch memory, so every shade of a
// rough-plastic scene copied the whole record there and read it back lane by lane;
// with selects the record stays in registers. Measured: shade of a rough plastic
// under a constant sky (320 x 320, 16 spp) 1043-1289 ms -> 396-447 ms, the same image
// bit for bit.
vec2 bsdf_roughplastic_table_word(BsdfRecord b, int k) {
    int r = k >> 2;
    uvec4 row = b.table[0];
    row = r == 1 ? b.table[1] : row;
    row = r == 2 ? b.table[2] : row;
    row = r == 3 ? b.table[3] : row;
    row = r == 4 ? b.table[4] : row;
    row = r == 5 ? b.table[5] : row;
    row = r == 6 ? b.table[6] : row;
    row = r == 7 ? b.table[7] : row;
    int c = k & 3;
    return unpackUnorm2x16(c == 0 ? row.x : c == 1 ? row.y : c == 2 ? row.z : row.w);
}

// T(mu), linear between the 64 entries at mu = i/63 (Mitsuba's lerp_gather).
float bsdf_roughplastic_transmittance(BsdfRecord b, float mu) {
    float x = clamp(mu, 0.0, 1.0) * 63.0;
    int i = min(trunc_to_int(x), 62); // x in [0, 63]: convert.glsl
    float w = x - float(i);
    // Entries i and i + 1: one word when i is even, two neighbouring words when odd.
    vec2 lo = bsdf_roughplastic_table_word(b, i >> 1);
    vec2 hi = bsdf_roughplastic_table_word(b, (i + 1) >> 1);
    float t0 = (i & 1) == 0 ? lo.x : lo.y;
    float t1 = (i & 1) == 0 ? lo.y : hi.x;
    return mix(t0, t1, w);
}

float bsdf_roughplastic_prob_specular(BsdfRecord b, float to) {
    float ps = (1.0 - to) * b.specular_weight;
    float pd = to * (1.0 - b.specular_weight);
    return ps / (ps + pd);
}

vec3 bsdf_roughplastic_eval(BsdfRecord b, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return vec3(0.0);
    vec3 result = bsdf_rough_dielectric_reflection(b, wo, wi);
    vec3 rho = b.reflectance;
    vec3 denom = 1.0 - ((b.flags & BSDF_NONLINEAR) != 0u ? rho * b.internal : vec3(b.internal));
    float to = bsdf_roughplastic_transmittance(b, wo.z);
    float ti = bsdf_roughplastic_transmittance(b, wi.z);
    return result + rho / denom * (to * ti * wi.z * INV_PI / (b.eta * b.eta));
}

float bsdf_roughplastic_pdf(BsdfRecord b, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
    float ps = bsdf_roughplastic_prob_specular(b, bsdf_roughplastic_transmittance(b, wo.z));
    vec3 m = normalize(wo + wi);
    float wim = dot(wi, m);
    float spec = wim > 0.0 ? microfacet_pdf(bsdf_microfacet_of(b), wo, m) / (4.0 * wim) : 0.0;
    return ps * spec + (1.0 - ps) * warp_cosine_hemisphere_pdf(wi);
}

BsdfSample bsdf_roughplastic_sample(BsdfRecord b, vec3 wo, vec3 u) {
    BsdfSample s = bsdf_sample_none();
    if (wo.z <= 0.0) return s;
    float ps = bsdf_roughplastic_prob_specular(b, bsdf_roughplastic_transmittance(b, wo.z));
    vec3 wi;
    uint flags = BSDF_FLAG_REFLECTION;
    if (u.x < ps) {
        vec3 m = microfacet_sample(bsdf_microfacet_of(b), wo, u.yz);
        wi = 2.0 * dot(wo, m) * m - wo;
    } else {
        wi = warp_cosine_hemisphere(u.yz);
    }
    if (wi.z <= 0.0) return s;
    float pdf = bsdf_roughplastic_pdf(b, wo, wi);
    if (!(pdf > 0.0)) return s;
    return BsdfSample(wi, bsdf_roughplastic_eval(b, wo, wi) / pdf, pdf, flags);
}
