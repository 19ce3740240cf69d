// Mitsuba 3's principled BSDF (src/bsdfs/principled.cpp, principledhelpers.h), after
// Burley 2012, "Physically Based Shading at Disney", and Burley 2015, "Extending the
// Disney BRDF to a BSDF with Integrated Subsurface Scattering": diffuse with
// retro-reflection and fake subsurface, sheen, a GGX lobe reflecting with a blended
// dielectric / metallic / tinted Fresnel term and transmitting (Walter et al. 2007),
// and a GTR1 clearcoat. Both sides (wo below = inside, only the GGX lobes). Radiance
// transport, as roughdielectric.glsl. The parameters are in b.table
// (src/scene/bsdf/principled.rs), base_color in b.reflectance; the helpers here serve
// principledthin.glsl too.
//
// Names: wo here is Mitsuba's si.wi (towards the viewer), wi here Mitsuba's wo.
// Sampling picks a lobe with Mitsuba's probabilities (see bsdf_principled_probs), then
// GGX visible normals (Heitz 2018), GTR1 normals (Burley 2012, eq. 2) or a cosine
// hemisphere; pdf per unit solid angle is the mixture; weight = eval / pdf.

struct Principled {
    vec3 base_color;
    float roughness, anisotropic, metallic, spec_trans;
    float spec_tint, sheen, sheen_tint, flatness;
    float clearcoat, clearcoat_gloss, diff_trans, eta;
    vec4 rates; // sampling rates, principled.rs T_RATES
    uint has;   // PRINCIPLED_HAS_*
};

#define PRINCIPLED_HAS_SPEC_TRANS 1u
#define PRINCIPLED_HAS_DIFF_TRANS 2u

Principled principled_of(BsdfRecord b) {
    Principled p;
    p.base_color = b.reflectance;
    p.roughness = uintBitsToFloat(b.table[0].x);
    p.anisotropic = uintBitsToFloat(b.table[0].y);
    p.metallic = uintBitsToFloat(b.table[0].z);
    p.spec_trans = uintBitsToFloat(b.table[0].w);
    p.spec_tint = uintBitsToFloat(b.table[1].x);
    p.sheen = uintBitsToFloat(b.table[1].y);
    p.sheen_tint = uintBitsToFloat(b.table[1].z);
    p.flatness = uintBitsToFloat(b.table[1].w);
    p.clearcoat = uintBitsToFloat(b.table[2].x);
    p.clearcoat_gloss = uintBitsToFloat(b.table[2].y);
    p.diff_trans = uintBitsToFloat(b.table[2].z);
    p.eta = uintBitsToFloat(b.table[2].w);
    p.rates = uintBitsToFloat(b.table[3]);
    p.has = b.table[7].y;
    return p;
}

// Mitsuba's luminance of linear sRGB (mitsuba::luminance).
float principled_luminance(vec3 c) { return dot(c, vec3(0.212671, 0.715160, 0.072169)); }

// (1 - cos)^5, Schlick's weight.
float principled_schlick_weight(float c) {
    float m = clamp(1.0 - c, 0.0, 1.0);
    float m2 = m * m;
    return m2 * m2 * m;
}

// Schlick's Fresnel R0 + (1 - R0)(1 - cos)^5 at the cosine of the denser side
// (Mitsuba's calc_schlick: the transmitted angle's when light leaves the denser side).
vec3 principled_schlick(vec3 r0, float cos_i, float eta) {
    bool outside = cos_i >= 0.0;
    float eta_it = outside ? eta : 1.0 / eta;
    float eta_ti = outside ? 1.0 / eta : eta;
    float cos_t = sqrt(max(0.0, 1.0 - (1.0 - cos_i * cos_i) * eta_ti * eta_ti));
    float w = principled_schlick_weight(eta_it > 1.0 ? abs(cos_i) : cos_t);
    return mix(vec3(w), vec3(1.0), r0);
}

float principled_r0(float eta) {
    float r = (eta - 1.0) / (eta + 1.0);
    return r * r;
}

// Mitsuba's mac_mic_compatibility: both directions on the side of the microfacet m
// (as seen from wo's side, cos_o its cosine) that reflection or refraction needs.
bool principled_compatible(vec3 m, vec3 wo, vec3 wi, float cos_o, bool reflect) {
    vec3 mm = cos_o < 0.0 ? -m : m;
    return dot(wo, mm) > 0.0 && (reflect ? dot(wi, mm) > 0.0 : dot(wi, mm) < 0.0);
}

// GGX of the main lobes: α = roughness², stretched by anisotropic (Burley 2012,
// addenda), at least 0.001 (Mitsuba's calc_dist_params).
Microfacet principled_ggx(float anisotropic, float roughness) {
    float r2 = roughness * roughness;
    float aspect = sqrt(1.0 - 0.9 * anisotropic);
    return Microfacet(MICROFACET_GGX, max(0.001, r2 / aspect), max(0.001, r2 * aspect));
}

// GTR1 (Burley 2012, appendix B, eq. 4) of the clearcoat, α = lerp(0.1, 0.001, gloss).
float principled_gtr1_alpha(float gloss) { return mix(0.1, 0.001, gloss); }

float principled_gtr1_d(float alpha, vec3 m) {
    float a2 = alpha * alpha;
    float r = (a2 - 1.0) / (PI * log(a2) * (1.0 + (a2 - 1.0) * m.z * m.z));
    return r * m.z > 1e-20 ? r : 0.0;
}

// Density of principled_gtr1_sample per unit solid angle of m: D(m) cos θm.
float principled_gtr1_pdf(float alpha, vec3 m) { return m.z < 0.0 ? 0.0 : m.z * principled_gtr1_d(alpha, m); }

vec3 principled_gtr1_sample(float alpha, vec2 u) {
    float a2 = alpha * alpha;
    float phi = 2.0 * PI * u.x;
    float cos2 = (1.0 - pow(a2, 1.0 - u.y)) / (1.0 - a2);
    float sin_t = sqrt(max(0.0, 1.0 - cos2)), cos_t = sqrt(max(0.0, cos2));
    return vec3(cos(phi) * sin_t, sin(phi) * sin_t, cos_t);
}

// Smith G1 of GGX with α (Mitsuba's smith_ggx1, the clearcoat's α = 0.25).
float principled_smith_ggx1(vec3 v, vec3 m, float alpha) {
    float c2 = v.z * v.z;
    float tan2 = (1.0 - c2) / c2;
    float r = 2.0 / (1.0 + sqrt(1.0 + alpha * alpha * tan2));
    r = v.z == 1.0 ? 1.0 : r;
    return dot(v, m) * v.z <= 0.0 ? 0.0 : r;
}

// Diffuse with retro-reflection (Burley 2012, sec. 5.3) and its blend towards the
// Hanrahan-Krueger-like fake subsurface by flatness, times cos θi / π (no color).
float principled_diffuse(Principled p, float ci, float co, float cos_d) {
    float fo = principled_schlick_weight(abs(co)), fi = principled_schlick_weight(abs(ci));
    float f_diff = (1.0 - 0.5 * fi) * (1.0 - 0.5 * fo);
    float rr = 2.0 * p.roughness * cos_d * cos_d;
    float f_retro = rr * (fo + fi + fo * fi * (rr - 1.0));
    float fss90 = rr / 2.0;
    float fss = mix(1.0, fss90, fo) * mix(1.0, fss90, fi);
    float f_ss = 1.25 * (fss * (1.0 / (abs(co) + abs(ci)) - 0.5) + 0.5);
    return abs(co) * INV_PI * mix(f_diff + f_retro, f_ss, p.flatness);
}

// The sheen's color: white tinted towards base_color / luminance by sheen_tint.
vec3 principled_sheen_color(Principled p) {
    float lum = principled_luminance(p.base_color);
    vec3 tint = lum > 0.0 ? p.base_color / lum : vec3(1.0);
    return mix(vec3(1.0), tint, p.sheen_tint);
}

// The generalized half vector on the upper side (Walter 2007, eq. 13 / 16).
vec3 principled_half(vec3 wo, vec3 wi, float eta_path, bool reflect) {
    vec3 h = normalize(wo + wi * (reflect ? 1.0 : eta_path));
    return h.z < 0.0 ? -h : h;
}

vec3 bsdf_principled_eval(BsdfRecord b, vec3 wo, vec3 wi) {
    float ci = wo.z, co = wi.z;
    vec3 value = vec3(0.0);
    if (ci != 0.0) {
        Principled p = principled_of(b);
        float brdf = (1.0 - p.metallic) * (1.0 - p.spec_trans);
        float bsdf = (1.0 - p.metallic) * p.spec_trans;
        bool reflect = ci * co > 0.0, refract = ci * co < 0.0, front = ci > 0.0;
        float eta_path = front ? p.eta : 1.0 / p.eta;
        Microfacet d = principled_ggx(p.anisotropic, p.roughness);
        vec3 h = principled_half(wo, wi, eta_path, reflect);
        float woh = dot(wo, h), wih = dot(wi, h);
        float f = fresnel_dielectric_f(woh, p.eta);
        bool reflect_ok = reflect && principled_compatible(h, wo, wi, ci, true);
        bool refract_ok = refract && principled_compatible(h, wo, wi, ci, false);
        float D = microfacet_d(d, h);
        float G = microfacet_g(d, wo, wi, h);
        // Main specular reflection: Fresnel blended from the dielectric, a Schlick
        // metal of base_color and a tinted Schlick dielectric (principled_fresnel);
        // from inside the dielectric's alone, weighted by bsdf.
        if (reflect_ok && f > 0.0) {
            vec3 fp = vec3(bsdf * f);
            if (front) {
                float lum = principled_luminance(p.base_color);
                vec3 tint = lum > 0.0 ? p.base_color / lum : vec3(1.0);
                float eta_it = woh >= 0.0 ? p.eta : 1.0 / p.eta;
                vec3 schlick = p.metallic * principled_schlick(p.base_color, woh, p.eta)
                    + (1.0 - p.metallic) * p.spec_tint * principled_schlick(tint * principled_r0(eta_it), woh, p.eta);
                fp = (1.0 - p.metallic) * (1.0 - p.spec_tint) * f + schlick;
            }
            value += fp * (D * G / (4.0 * abs(ci)));
        }
        // Main specular transmission, sqrt(base_color)-tinted (radiance: the η² of
        // Walter's eq. 21 cancels against radiance's 1/η²).
        if (refract_ok && bsdf > 0.0 && f < 1.0) {
            float denom = woh + eta_path * wih;
            value += sqrt(p.base_color) * bsdf * abs((1.0 - f) * D * G * woh * wih / (ci * denom * denom));
        }
        // Clearcoat: GTR1, Schlick F0 = 0.04, Smith GGX α = 0.25 (no 1 / (4 cos cos), as
        // Mitsuba).
        if (reflect_ok && front && p.clearcoat > 0.0) {
            float fcc = principled_schlick(vec3(0.04), woh, p.eta).x;
            float dcc = principled_gtr1_d(principled_gtr1_alpha(p.clearcoat_gloss), h);
            float gcc = principled_smith_ggx1(wo, h, 0.25) * principled_smith_ggx1(wi, h, 0.25);
            value += vec3(p.clearcoat * 0.25 * fcc * dcc * gcc * abs(co));
        }
        // Diffuse, retro-reflection, fake subsurface, sheen.
        if (reflect && front && brdf > 0.0) {
            float cos_d = dot(h, wi);
            value += brdf * p.base_color * principled_diffuse(p, ci, co, cos_d);
            if (p.sheen > 0.0 && 1.0 - p.metallic > 0.0) {
                float fd = principled_schlick_weight(abs(cos_d));
                value += p.sheen * (1.0 - p.metallic) * fd * principled_sheen_color(p) * abs(co);
            }
        }
    }
    return value;
}

// Mitsuba's lobe probabilities at the dielectric Fresnel term f: (diffuse, clearcoat,
// transmission, reflection), normalized. Outside: diffuse ∝ brdf, clearcoat ∝
// clearcoat / 4, transmission ∝ bsdf (1 - f), reflection ∝ 1 - bsdf (1 - f), each
// times its sampling rate; inside: reflection f, transmission 1 - f (when spec_trans
// was given).
vec4 bsdf_principled_probs(Principled p, bool front, float f) {
    float brdf = (1.0 - p.metallic) * (1.0 - p.spec_trans);
    bool has_trans = (p.has & PRINCIPLED_HAS_SPEC_TRANS) != 0u;
    float bsdf = has_trans ? (1.0 - p.metallic) * p.spec_trans : 0.0;
    vec4 q;
    if (front) {
        q = vec4(brdf * p.rates.z, 0.25 * p.clearcoat * p.rates.y, p.rates.x * bsdf * (1.0 - f),
                 p.rates.x * (1.0 - bsdf * (1.0 - f)));
    } else {
        q = vec4(0.0, 0.0, has_trans ? 1.0 - f : 0.0, f);
    }
    return q / (q.x + q.y + q.z + q.w);
}

float bsdf_principled_pdf(BsdfRecord b, vec3 wo, vec3 wi) {
    float ci = wo.z, co = wi.z;
    float pdf = 0.0;
    if (ci != 0.0) {
        Principled p = principled_of(b);
        bool reflect = ci * co > 0.0, refract = ci * co < 0.0, front = ci > 0.0;
        float eta_path = front ? p.eta : 1.0 / p.eta;
        vec3 h = principled_half(wo, wi, eta_path, reflect);
        float woh = dot(wo, h), wih = dot(wi, h);
        vec4 q = bsdf_principled_probs(p, front, fresnel_dielectric_f(woh, p.eta));
        // dh/dwi: Walter 2007, eq. 14 (reflection) and 17 (refraction).
        float denom = woh + eta_path * wih;
        float jacobian = abs(reflect ? 1.0 / (4.0 * wih) : eta_path * eta_path * wih / (denom * denom));
        Microfacet d = principled_ggx(p.anisotropic, p.roughness);
        float pm = microfacet_pdf(d, front ? wo : -wo, h);
        if (reflect && principled_compatible(h, wo, wi, ci, true)) {
            pdf += (q.w * pm + q.y * principled_gtr1_pdf(principled_gtr1_alpha(p.clearcoat_gloss), h)) * jacobian;
        }
        if (reflect) pdf += q.x * co * INV_PI;
        if (refract && principled_compatible(h, wo, wi, ci, false)) pdf += q.z * pm * jacobian;
    }
    return pdf;
}

BsdfSample bsdf_principled_sample(BsdfRecord b, vec3 wo, vec3 u) {
    BsdfSample s = bsdf_sample_none();
    float ci = wo.z;
    Principled p = principled_of(b);
    bool front = ci > 0.0;
    bool has_trans = (p.has & PRINCIPLED_HAS_SPEC_TRANS) != 0u;
    float bsdf = has_trans ? (1.0 - p.metallic) * p.spec_trans : 0.0;
    if (ci != 0.0 && (front || bsdf > 0.0)) {
        Microfacet d = principled_ggx(p.anisotropic, p.roughness);
        vec3 m = microfacet_sample(d, front ? wo : -wo, u.yz);
        float wom = dot(wo, m);
        float cos_t, eta_it, eta_ti;
        float f = fresnel_dielectric(wom, p.eta, cos_t, eta_it, eta_ti);
        vec4 q = bsdf_principled_probs(p, front, f);
        vec3 wi = vec3(0.0);
        bool ok;
        uint flags = BSDF_FLAG_REFLECTION;
        if (u.x < q.x) {
            wi = warp_cosine_hemisphere(u.yz);
            ok = ci * wi.z > 0.0;
        } else if (u.x < q.x + q.y) {
            vec3 mc = principled_gtr1_sample(principled_gtr1_alpha(p.clearcoat_gloss), u.yz);
            wi = 2.0 * dot(wo, mc) * mc - wo;
            ok = principled_compatible(mc, wo, wi, ci, true) && ci * wi.z > 0.0;
        } else if (u.x < q.x + q.y + q.z) {
            // Refraction about m (Walter 2007, eq. 40, in Mitsuba's form).
            wi = m * (wom * eta_ti + cos_t) - wo * eta_ti;
            ok = principled_compatible(m, wo, wi, ci, false) && ci * wi.z < 0.0;
            flags = BSDF_FLAG_TRANSMISSION;
        } else {
            wi = 2.0 * wom * m - wo;
            ok = principled_compatible(m, wo, wi, ci, true) && ci * wi.z > 0.0;
        }
        float pdf = ok ? bsdf_principled_pdf(b, wo, wi) : 0.0;
        if (pdf > 0.0) s = BsdfSample(wi, bsdf_principled_eval(b, wo, wi) / pdf, pdf, flags);
    }
    return s;
}

// Its lobes (kinds.rs hook `lobes`): transmission only where spec_trans was given.
uint bsdf_principled_lobes(BsdfRecord b, uint lobes) {
    uint has = b.table[7].y;
    return (has & PRINCIPLED_HAS_SPEC_TRANS) != 0u ? lobes : lobes & ~BSDF_LOBE_TRANSMISSION;
}
