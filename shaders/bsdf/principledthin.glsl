// Mitsuba 3's thin principled BSDF (src/bsdfs/principledthin.cpp): a two-sided sheet,
// the same from both sides (the frame is mirrored so wo lies above). Diffuse, retro-
// reflection, fake subsurface and sheen weighted (1 - spec_trans)(1 - dt); Lambertian
// transmission (1 - spec_trans) dt; GGX reflection spec_trans · F_thin (dielectric
// Fresnel of eta lerped towards a tinted Schlick by spec_tint); GGX "transmission"
// spec_trans · base_color (1 - F): a reflection mirrored through the sheet (no
// bending), its roughness scaled by 0.65 η - 0.35 (Burley 2015, fig. 15). dt is
// diff_trans / 2 (given 0 to 2). Helpers in principled.glsl; parameters as there.
//
// Sampling: specular reflection ∝ spec_trans / 2, specular transmission ∝ spec_trans
// / 2, cosine reflection ∝ (1 - spec_trans)(1 - dt), cosine transmission ∝
// (1 - spec_trans) dt, each times its sampling rate, normalized.

// Mitsuba's lobe probabilities: (spec reflection, spec transmission, cosine
// reflection, cosine transmission).
vec4 bsdf_principledthin_probs(Principled p, float dt) {
    bool has_spec = (p.has & PRINCIPLED_HAS_SPEC_TRANS) != 0u;
    bool has_diff = (p.has & PRINCIPLED_HAS_DIFF_TRANS) != 0u;
    vec4 q = vec4(has_spec ? p.spec_trans * p.rates.x / 2.0 : 0.0, has_spec ? p.spec_trans * p.rates.y / 2.0 : 0.0,
                  p.rates.z * (1.0 - p.spec_trans) * (1.0 - dt),
                  has_diff ? p.rates.w * (1.0 - p.spec_trans) * dt : 0.0);
    return q / (q.x + q.y + q.z + q.w);
}

float principledthin_dt(Principled p) {
    return (p.has & PRINCIPLED_HAS_DIFF_TRANS) != 0u ? p.diff_trans / 2.0 : 0.0;
}

vec3 bsdf_principledthin_eval(BsdfRecord b, vec3 wo, vec3 wi) {
    vec3 value = vec3(0.0);
    if (wo.z != 0.0) {
        Principled p = principled_of(b);
        float dt = principledthin_dt(p);
        // Both directions mirrored so that wo lies above.
        vec3 v = wo.z < 0.0 ? -wo : wo;
        vec3 l = wo.z < 0.0 ? -wi : wi;
        float ci = v.z, co = l.z;
        bool reflect = co > 0.0, refract = co < 0.0;
        vec3 h = normalize(v + vec3(l.xy, abs(l.z)));
        if ((p.has & PRINCIPLED_HAS_SPEC_TRANS) != 0u && p.spec_trans > 0.0) {
            float f = fresnel_dielectric_f(dot(v, h), p.eta);
            if (reflect && principled_compatible(h, v, l, ci, true)) {
                Microfacet d = principled_ggx(p.anisotropic, p.roughness);
                float lum = principled_luminance(p.base_color);
                vec3 tint = lum > 0.0 ? p.base_color / lum : vec3(1.0);
                vec3 schlick = principled_schlick(tint * principled_r0(p.eta), dot(v, h), p.eta);
                vec3 ft = mix(vec3(f), schlick, p.spec_tint);
                value += p.spec_trans * ft * (microfacet_d(d, h) * microfacet_g(d, v, l, h) / (4.0 * ci));
            }
            if (refract && principled_compatible(h, v, l, ci, false)) {
                Microfacet d = principled_ggx(p.anisotropic, (0.65 * p.eta - 0.35) * p.roughness);
                value += p.spec_trans * p.base_color
                    * ((1.0 - f) * microfacet_d(d, h) * microfacet_g(d, v, l, h) / (4.0 * ci));
            }
        }
        if (reflect && p.spec_trans < 1.0 && dt < 1.0) {
            float cos_d = dot(h, l);
            float w = (1.0 - p.spec_trans) * (1.0 - dt);
            value += w * p.base_color * principled_diffuse(p, ci, co, cos_d);
            if (p.sheen > 0.0) {
                float fd = principled_schlick_weight(abs(cos_d));
                value += p.sheen * w * fd * principled_sheen_color(p) * abs(co);
            }
        }
        if (refract && p.spec_trans < 1.0 && dt > 0.0) {
            value += (1.0 - p.spec_trans) * dt * p.base_color * INV_PI * abs(co);
        }
    }
    return value;
}

float bsdf_principledthin_pdf(BsdfRecord b, vec3 wo, vec3 wi) {
    float pdf = 0.0;
    if (wo.z != 0.0) {
        Principled p = principled_of(b);
        vec4 q = bsdf_principledthin_probs(p, principledthin_dt(p));
        vec3 v = wo.z < 0.0 ? -wo : wo;
        vec3 l = wo.z < 0.0 ? -wi : wi;
        bool reflect = l.z > 0.0, refract = l.z < 0.0;
        if ((p.has & PRINCIPLED_HAS_SPEC_TRANS) != 0u) {
            vec3 lr = vec3(l.xy, abs(l.z));
            vec3 h = normalize(v + lr);
            float jacobian = abs(1.0 / (4.0 * dot(lr, h)));
            if (reflect && principled_compatible(h, v, l, v.z, true)) {
                pdf += q.x * microfacet_pdf(principled_ggx(p.anisotropic, p.roughness), v, h) * jacobian;
            }
            if (refract && principled_compatible(h, v, l, v.z, false)) {
                Microfacet d = principled_ggx(p.anisotropic, (0.65 * p.eta - 0.35) * p.roughness);
                pdf += q.y * microfacet_pdf(d, v, h) * jacobian;
            }
        }
        if (reflect) pdf += q.z * l.z * INV_PI;
        if (refract && (p.has & PRINCIPLED_HAS_DIFF_TRANS) != 0u) pdf += q.w * -l.z * INV_PI;
    }
    return pdf;
}

BsdfSample bsdf_principledthin_sample(BsdfRecord b, vec3 wo, vec3 u) {
    BsdfSample s = bsdf_sample_none();
    if (wo.z != 0.0) {
        Principled p = principled_of(b);
        vec4 q = bsdf_principledthin_probs(p, principledthin_dt(p));
        vec3 v = wo.z < 0.0 ? -wo : wo;
        vec3 l = vec3(0.0);
        bool ok = true;
        uint flags = BSDF_FLAG_REFLECTION;
        if (u.x < q.x + q.y) {
            // A GGX reflection; for transmission with the scaled roughness, mirrored
            // through the sheet.
            bool trans = u.x >= q.x;
            float r = trans ? (0.65 * p.eta - 0.35) * p.roughness : p.roughness;
            vec3 m = microfacet_sample(principled_ggx(p.anisotropic, r), v, u.yz);
            l = 2.0 * dot(v, m) * m - v;
            if (trans) {
                l.z = -l.z;
                flags = BSDF_FLAG_TRANSMISSION;
            }
            ok = principled_compatible(m, v, l, v.z, !trans) && (trans ? l.z < 0.0 : l.z > 0.0);
        } else if (u.x < q.x + q.y + q.z) {
            l = warp_cosine_hemisphere(u.yz);
        } else if ((p.has & PRINCIPLED_HAS_DIFF_TRANS) != 0u) {
            l = -warp_cosine_hemisphere(u.yz);
            flags = BSDF_FLAG_TRANSMISSION;
        }
        vec3 wi = wo.z < 0.0 ? -l : l;
        float pdf = ok ? bsdf_principledthin_pdf(b, wo, wi) : 0.0;
        if (pdf > 0.0) s = BsdfSample(wi, bsdf_principledthin_eval(b, wo, wi) / pdf, pdf, flags);
    }
    return s;
}

// Its lobes (kinds.rs hook `lobes`): transmission only where spec_trans or diff_trans
// was given.
uint bsdf_principledthin_lobes(BsdfRecord b, uint lobes) {
    uint has = b.table[7].y;
    return (has & (PRINCIPLED_HAS_SPEC_TRANS | PRINCIPLED_HAS_DIFF_TRANS)) != 0u ? lobes
                                                                                 : lobes & ~BSDF_LOBE_TRANSMISSION;
}
