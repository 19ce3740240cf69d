// Mitsuba 3's hair BSDF (src/bsdfs/hair.cpp), after Chiang et al. 2016, "A Practical
// and Controllable Hair and Fur Model for Production Path Tracing" (pbrt-v4's
// HairBxDF is the same model): a dielectric cylinder seen whole in one scattering
// event, the sum of the lobes p = 0 (R), 1 (TT), 2 (TRT) and the rest (p >= 3), each
// a longitudinal lobe M_p (d'Eon et al. 2011, tilted by the scales: 2^k α) times an
// attenuation A_p (Fresnel and absorption along the chords) times an azimuthal
// trimmed logistic N_p around the perfect specular Δφ (the rest: uniform in φ).
//
// Frame (Mitsuba's, for curves): the fiber runs along local y (the shading frame's
// second axis, n × ∂p/∂u); θ is the angle to the normal plane (sin θ = w.y), φ =
// atan2(w.z, w.x). The offset h across the fiber is sin γ of the viewer's direction
// in the normal plane (Mitsuba's gamma(si.wi)), not a texture coordinate. Both sides
// (no hemisphere test). Light crosses the whole fiber: the record's eta is 1 (no
// radiance scaling), the relative index is in the table.
//
// Names: wo here is Mitsuba's si.wi (towards the viewer), wi here Mitsuba's wo.
// eval = Mitsuba's value (M_p N_p A_p per solid angle: the cosine is part of it).
// Parameters (src/scene/bsdf/hair.rs): b.reflectance = σ_a (textured as Mitsuba's
// sigma_a), table: v[0..3], s, sin 2^k α, cos 2^k α, η, scale of σ_a.

#define HAIR_P_MAX 3

struct Hair {
    float v[4];         // longitudinal variances
    float s;            // azimuthal logistic scale
    float sin2k[3], cos2k[3];
    float eta;
    vec3 sigma_a;
};

Hair hair_of(BsdfRecord b) {
    Hair h;
    vec4 t0 = uintBitsToFloat(b.table[0]);
    vec4 t1 = uintBitsToFloat(b.table[1]);
    vec4 t2 = uintBitsToFloat(b.table[2]);
    vec4 t3 = uintBitsToFloat(b.table[3]);
    h.v[0] = t0.x;
    h.v[1] = t0.y;
    h.v[2] = t0.z;
    h.v[3] = t0.w;
    h.s = t1.x;
    h.sin2k[0] = t1.y;
    h.sin2k[1] = t1.z;
    h.sin2k[2] = t1.w;
    h.cos2k[0] = t2.x;
    h.cos2k[1] = t2.y;
    h.cos2k[2] = t2.z;
    h.eta = t2.w;
    h.sigma_a = b.reflectance * t3.x;
    return h;
}

float hair_safe_sqrt(float x) { return sqrt(max(x, 0.0)); }

// γ: the angle in the normal plane between the normal (z) and w (Mitsuba's gamma():
// acos(z / |(x, z)|), negative where x > 0), by atan2: llvmpipe's acos and asin are
// off by up to 1.5e-4 rad, which the azimuthal lobe (slope 1/s, s ≈ 0.1) magnifies.
float hair_gamma(vec3 w) {
    return w.x == 0.0 && w.z == 0.0 ? 0.0 : atan(-w.x, w.z);
}

float hair_asin(float x) {
    float c = clamp(x, -1.0, 1.0);
    return atan(c, hair_safe_sqrt(1.0 - c * c));
}

// (sin θ, cos θ) of the direction tilted by the scales for lobe p (Mitsuba's
// reframe_with_scales; p >= 3 unchanged); cos θ as its absolute value.
vec2 hair_reframe(Hair h, float sin_t, float cos_t, int p) {
    vec2 r = vec2(sin_t, cos_t);
    if (p == 0) {
        r = vec2(sin_t * h.cos2k[1] - cos_t * h.sin2k[1], cos_t * h.cos2k[1] + sin_t * h.sin2k[1]);
    } else if (p == 1) {
        r = vec2(sin_t * h.cos2k[0] + cos_t * h.sin2k[0], cos_t * h.cos2k[0] - sin_t * h.sin2k[0]);
    } else if (p == 2) {
        r = vec2(sin_t * h.cos2k[2] + cos_t * h.sin2k[2], cos_t * h.cos2k[2] - sin_t * h.sin2k[2]);
    }
    return vec2(r.x, abs(r.y));
}

// I0, the modified Bessel function of the first kind (Mitsuba's warp::detail::i0),
// and its logarithm.
float hair_i0(float x) {
    float result = 1.0, x2 = x * x, xi = x2, denom = 4.0;
    for (int i = 1; i <= 10; ++i) {
        float factor = float(i) + 1.0;
        result += xi / denom;
        xi *= x2;
        denom *= 4.0 * factor * factor;
    }
    return result;
}

float hair_log_i0(float x) {
    return x > 12.0 ? x + 0.5 * (log(1.0 / (2.0 * PI * x)) + 1.0 / (8.0 * x)) : log(hair_i0(x));
}

// M_p / 2π: d'Eon's longitudinal lobe for directions with sin θ = sin_i, sin_o and
// variance v (Mitsuba's square_to_rough_fiber_pdf, κ = 1/v).
float hair_longitudinal(float sin_i, float sin_o, float v) {
    float kappa = 1.0 / v;
    float cos_i = hair_safe_sqrt(1.0 - sin_i * sin_i);
    float cos_o = hair_safe_sqrt(1.0 - sin_o * sin_o);
    float c = cos_i * cos_o * kappa, s = sin_i * sin_o * kappa;
    return kappa > 10.0
        ? exp(-s + hair_log_i0(c) - kappa + 0.6931 + log(0.5 * kappa)) * (0.5 * INV_PI)
        : exp(-s) * hair_i0(c) * kappa / (2.0 * sinh(kappa)) * (0.5 * INV_PI);
}

float hair_logistic(float x, float s) {
    float e = exp(-abs(x) / s);
    return e / (s * (1.0 + e) * (1.0 + e));
}

float hair_logistic_cdf(float x, float s) { return 1.0 / (1.0 + exp(-x / s)); }

float hair_trimmed_logistic_sample(float u, float s) {
    float k = hair_logistic_cdf(PI, s) - hair_logistic_cdf(-PI, s);
    float x = -s * log(1.0 / (u * k + hair_logistic_cdf(-PI, s)) - 1.0);
    return clamp(x, -PI, PI);
}

// N_p: the trimmed logistic around lobe p's perfect Δφ.
float hair_azimuthal(float delta_phi, int p, float s, float gamma_i, float gamma_t) {
    float fp = float(p);
    float phi = delta_phi - (2.0 * fp * gamma_t - 2.0 * gamma_i + fp * PI);
    phi -= 2.0 * PI * trunc(phi / (2.0 * PI)); // C's fmod
    if (phi < PI) phi += 2.0 * PI;
    if (phi > PI) phi -= 2.0 * PI;
    return hair_logistic(phi, s) / (hair_logistic_cdf(PI, s) - hair_logistic_cdf(-PI, s));
}

float hair_luminance(vec3 c) { return dot(c, vec3(0.212671, 0.715160, 0.072169)); }

// What eval, pdf and sample share for the viewer's direction wo: γ_i, γ_t, θ_i, φ_i,
// the attenuations A_p and the lobe probabilities (luminance of A_p, normalized).
struct HairIn {
    float gamma_i, gamma_t, sin_t, cos_t, phi;
    vec3 a[4];
    float a_pdf[4];
};

HairIn hair_in(Hair h, vec3 wo) {
    HairIn r;
    r.gamma_i = hair_gamma(wo);
    float hh = sin(r.gamma_i);
    r.sin_t = wo.y;
    r.cos_t = hair_safe_sqrt(1.0 - wo.y * wo.y);
    r.phi = atan(wo.z, wo.x);
    // Refraction in the longitudinal plane, and in the normal plane with the modified
    // index η' (Bravais).
    float sin_theta_t = r.sin_t / h.eta;
    float cos_theta_t = hair_safe_sqrt(1.0 - sin_theta_t * sin_theta_t);
    float eta_p = hair_safe_sqrt(h.eta * h.eta - r.sin_t * r.sin_t) / r.cos_t;
    float sin_gamma_t = hh / eta_p;
    float cos_gamma_t = hair_safe_sqrt(1.0 - sin_gamma_t * sin_gamma_t);
    r.gamma_t = hair_asin(sin_gamma_t);
    vec3 transmittance = exp(-h.sigma_a * (2.0 * cos_gamma_t / cos_theta_t));
    // Fresnel at the cosine of the fiber's surface (Mitsuba's attenuation()).
    float f = fresnel_dielectric_f(r.cos_t * hair_safe_sqrt(1.0 - hh * hh), h.eta);
    r.a[0] = vec3(f);
    r.a[1] = (1.0 - f) * (1.0 - f) * transmittance;
    r.a[2] = r.a[1] * transmittance * f;
    r.a[3] = r.a[2] * f * transmittance / (1.0 - transmittance * f);
    float lum[4];
    float sum = 0.0;
    for (int i = 0; i <= HAIR_P_MAX; ++i) {
        lum[i] = hair_luminance(r.a[i]);
        sum += lum[i];
    }
    for (int i = 0; i <= HAIR_P_MAX; ++i) r.a_pdf[i] = lum[i] / sum;
    return r;
}

bool hair_bad(float x) { return isnan(x) || isinf(x); }

// Mitsuba's eval_pdf: the value (f |cos θi|) and the pdf for the light direction wi.
void hair_eval_pdf(BsdfRecord b, vec3 wo, vec3 wi, out vec3 value, out float pdf) {
    Hair h = hair_of(b);
    HairIn r = hair_in(h, wo);
    float delta_phi = atan(wi.z, wi.x) - r.phi;
    value = vec3(0.0);
    pdf = 0.0;
    for (int p = 0; p < HAIR_P_MAX; ++p) {
        vec2 ip = hair_reframe(h, r.sin_t, r.cos_t, p);
        float m = hair_longitudinal(ip.x, wi.y, h.v[p]) * (2.0 * PI)
            * hair_azimuthal(delta_phi, p, h.s, r.gamma_i, r.gamma_t);
        pdf += m * r.a_pdf[p];
        value += m * r.a[p];
    }
    float m = hair_longitudinal(r.sin_t, wi.y, h.v[HAIR_P_MAX]);
    pdf += m * r.a_pdf[HAIR_P_MAX];
    value += m * r.a[HAIR_P_MAX];
    pdf = hair_bad(pdf) ? 0.0 : pdf;
    value = vec3(hair_bad(value.x) ? 0.0 : value.x, hair_bad(value.y) ? 0.0 : value.y,
                 hair_bad(value.z) ? 0.0 : value.z);
}

vec3 bsdf_hair_eval(BsdfRecord b, vec3 wo, vec3 wi) {
    vec3 value;
    float pdf;
    hair_eval_pdf(b, wo, wi, value, pdf);
    return value;
}

float bsdf_hair_pdf(BsdfRecord b, vec3 wo, vec3 wi) {
    vec3 value;
    float pdf;
    hair_eval_pdf(b, wo, wi, value, pdf);
    return pdf;
}

// Mitsuba's sample: u.x picks the lobe p by the A_p luminances and is rescaled to
// pick Δφ; u.y the longitudinal angle, u.z the cone's azimuth.
BsdfSample bsdf_hair_sample(BsdfRecord b, vec3 wo, vec3 u) {
    Hair h = hair_of(b);
    HairIn r = hair_in(h, wo);
    float u0 = u.x;
    float u1 = u0 / r.a_pdf[0];
    int p = 0;
    for (int i = 0; i < HAIR_P_MAX; ++i) {
        bool take = r.a_pdf[i] < u0;
        u0 -= r.a_pdf[i];
        if (take) {
            p = i + 1;
            u1 = u0 / r.a_pdf[i + 1];
        }
    }
    u1 = clamp(u1, 0.0, 1.0);
    vec2 ip = hair_reframe(h, r.sin_t, r.cos_t, p);
    float v = h.v[p];
    float cos_theta = clamp(1.0 + v * log(u.y + (1.0 - u.y) * exp(-2.0 / v)), -1.0, 1.0);
    float sin_theta = hair_safe_sqrt(1.0 - cos_theta * cos_theta);
    float cos_phi = cos(2.0 * PI * u.z);
    float sin_theta_o = -cos_theta * ip.x + sin_theta * cos_phi * ip.y;
    float cos_theta_o = hair_safe_sqrt(1.0 - sin_theta_o * sin_theta_o);
    float fp = float(p);
    float delta_phi = p < HAIR_P_MAX
        ? 2.0 * fp * r.gamma_t - 2.0 * r.gamma_i + fp * PI + hair_trimmed_logistic_sample(u1, h.s)
        : 2.0 * PI * u1;
    float phi_o = r.phi + delta_phi;
    vec3 wi = normalize(vec3(cos_theta_o * cos(phi_o), sin_theta_o, cos_theta_o * sin(phi_o)));
    vec3 value;
    float pdf;
    hair_eval_pdf(b, wo, wi, value, pdf);
    bool ok = pdf > 0.0;
    uint flags = wi.z * wo.z > 0.0 ? BSDF_FLAG_REFLECTION : BSDF_FLAG_TRANSMISSION;
    return ok ? BsdfSample(wi, value / pdf, pdf, flags) : bsdf_sample_none();
}
