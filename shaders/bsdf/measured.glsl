// Mitsuba 3's `measured` BSDF: an RGL .bsdf file (Dupuy and Jakob 2018, "An Adaptive
// Parameterization for Efficient Material Acquisition and Rendering"), evaluated and
// sampled as Mitsuba's src/bsdfs/measured.cpp does. Its tables are words of the
// scene's texel buffer from b.table[0].x on, laid out by src/scene/bsdf/measured.rs
// (MeasuredData::words); a kernel without the scene bindings (the BSDF test kernel)
// defines BSDF_TABLE_WORD_DEFINED and its own bsdf_table_word.
//
// Directions: Mitsuba's wi (towards the viewer) is our wo, its wo our wi. u-space:
// u = (sqrt(2θ/π), (φ + π) / 2π). Each 2-D table is Mitsuba's Marginal2D<Float, Dim,
// true> over the unit square (bilinear in the square, linear in the parameters φi, θi).

#ifndef BSDF_TABLE_WORD_DEFINED
uint bsdf_table_word(uint k) { return texel_word(k).x; }
#endif

float measured_value(uint k) { return uintBitsToFloat(bsdf_table_word(k)); }

// The header (MeasuredData::words): word i from the start.
uint measured_head(uint base, uint i) { return bsdf_table_word(base + i); }
#define MEASURED_N_PHI 0u
#define MEASURED_N_THETA 1u
#define MEASURED_FLAGS 2u
#define MEASURED_REDUCTION 3u
#define MEASURED_NDF_SIZE 4u
#define MEASURED_SIGMA_SIZE 6u
#define MEASURED_VNDF_SIZE 8u
#define MEASURED_LUM_SIZE 10u
#define MEASURED_PHI_I 12u
#define MEASURED_THETA_I 13u
#define MEASURED_NDF 14u
#define MEASURED_SIGMA 15u
#define MEASURED_VNDF 16u  // density, marginal, conditional: 16, 17, 18
#define MEASURED_LUM 19u   // 19, 20, 21
#define MEASURED_RGB 22u

// Where the (φi, θi) interpolation lands: the first slice, the slice steps to the next
// φi and θi, and the weights of those next ones (Distribution2D::interpolate_weights).
struct MeasuredParams {
    uint slice;
    uint dphi;
    uint dtheta;
    float wphi;
    float wtheta;
};

// find_interval over the n values at `at`: the i in [0, n-2] with values[i] <= x
// (clamped), and the weight of values[i+1].
void measured_interval(uint at, uint n, float x, out uint index, out float weight) {
    if (n == 1u) {
        index = 0u;
        weight = 0.0;
        return;
    }
    uint lo = 1u, hi = n - 1u;
    while (lo < hi) {
        uint mid = (lo + hi) >> 1u;
        if (measured_value(at + mid) < x) lo = mid + 1u; else hi = mid;
    }
    index = lo - 1u;
    float p0 = measured_value(at + index), p1 = measured_value(at + index + 1u);
    weight = clamp((x - p0) / (p1 - p0), 0.0, 1.0);
}

// The interpolation at (φi, θi) for tables of `channels` slices per direction.
MeasuredParams measured_params(uint base, float phi_i, float theta_i, uint channels) {
    uint np = measured_head(base, MEASURED_N_PHI), nt = measured_head(base, MEASURED_N_THETA);
    uint ip, it;
    MeasuredParams p;
    measured_interval(base + measured_head(base, MEASURED_PHI_I), np, phi_i, ip, p.wphi);
    measured_interval(base + measured_head(base, MEASURED_THETA_I), nt, theta_i, it, p.wtheta);
    p.dtheta = nt > 1u ? channels : 0u;
    p.dphi = np > 1u ? channels * nt : 0u;
    p.slice = p.dphi * ip + p.dtheta * it;
    return p;
}

// Entry i of the slices (size words each) of the table at `at`, interpolated in φi, θi
// (Marginal2D::lookup: the φi pair first, then θi).
float measured_lookup(uint at, uint size, uint i, MeasuredParams p) {
    uint i0 = at + p.slice * size + i;
    uint sp = p.dphi * size, st = p.dtheta * size;
    float a = measured_value(i0) * (1.0 - p.wphi) + measured_value(i0 + sp) * p.wphi;
    float b = measured_value(i0 + st) * (1.0 - p.wphi) + measured_value(i0 + st + sp) * p.wphi;
    return a * (1.0 - p.wtheta) + b * p.wtheta;
}

// The bilinear interpolant of the w x h table at `at` (one slice per parameter
// position, `p`) at pos in [0, 1]² (Marginal2D::eval).
float measured_eval2(uint at, uint w, uint h, vec2 pos, MeasuredParams p) {
    pos = clamp(pos, 0.0, 1.0) * vec2(w - 1u, h - 1u);
    uvec2 o = min(uvec2(pos), uvec2(w - 2u, h - 2u));
    pos -= vec2(o);
    uint i = o.x + o.y * w, n = w * h;
    float v00 = measured_lookup(at, n, i, p), v10 = measured_lookup(at, n, i + 1u, p);
    float v01 = measured_lookup(at, n, i + w, p), v11 = measured_lookup(at, n, i + w + 1u, p);
    return mix(mix(v00, v10, pos.x), mix(v01, v11, pos.x), pos.y);
}

// A table without parameters (ndf, sigma).
float measured_eval2_plain(uint at, uint w, uint h, vec2 pos) {
    return measured_eval2(at, w, h, pos, MeasuredParams(0u, 0u, 0u, 0.0, 0.0));
}

// One Marginal2D warp: its size and its three arrays.
struct MeasuredWarp {
    uint w, h, density, marginal, conditional;
};

MeasuredWarp measured_warp(uint base, uint size_word, uint first) {
    return MeasuredWarp(measured_head(base, size_word), measured_head(base, size_word + 1u),
                        base + measured_head(base, first), base + measured_head(base, first + 1u),
                        base + measured_head(base, first + 2u));
}

float measured_sample_segment(float s, float inv_width, float v0, float v1) {
    bool non_const = abs(v0 - v1) > 1e-4 * (v0 + v1);
    float divisor = non_const ? v0 - v1 : v0 + v1;
    s *= 2.0 * inv_width;
    if (non_const) s = v0 - sqrt(max(v0 * v0 + s * (v1 - v0), 0.0));
    if (divisor != 0.0) s /= divisor;
    return s;
}

float measured_invert_segment(float s, float width, float v0, float v1) {
    return s * mix(v0, v1, 0.5 * s) * width;
}

// The conditional CDF of row `row` at column `idx`, between that row and the next by y.
float measured_cond(MeasuredWarp m, MeasuredParams p, uint row, uint idx, float y) {
    uint nc = m.h * (m.w - 1u), k = row * (m.w - 1u) + idx;
    return mix(measured_lookup(m.conditional, nc, k, p),
               measured_lookup(m.conditional, nc, k + m.w - 1u, p), y);
}

// Marginal2D::sample_continuous: a point of the square distributed as the density,
// and the density there.
vec2 measured_sample2(MeasuredWarp m, MeasuredParams p, vec2 s, out float pdf) {
    uint nc = m.h * (m.w - 1u), nm = m.h - 1u, nd = m.w * m.h;
    s = clamp(s, 5.9604645e-8, 0.99999994);
    uint lo = 0u, hi = nm - 1u;
    while (lo < hi) {
        uint mid = (lo + hi) >> 1u;
        if (measured_lookup(m.marginal, nm, mid, p) < s.y) lo = mid + 1u; else hi = mid;
    }
    uint row = lo;
    if (row > 0u) s.y -= measured_lookup(m.marginal, nm, row - 1u, p);
    uint oc = row * (m.w - 1u);
    float r0 = measured_lookup(m.conditional, nc, oc + m.w - 2u, p);
    float r1 = measured_lookup(m.conditional, nc, oc + 2u * (m.w - 1u) - 1u, p);
    s.y = measured_sample_segment(s.y, float(m.h - 1u), r0, r1);
    s.x *= mix(r0, r1, s.y);
    lo = 0u;
    hi = m.w - 1u;
    while (lo < hi) {
        uint mid = (lo + hi) >> 1u;
        if (measured_cond(m, p, row, mid, s.y) < s.x) lo = mid + 1u; else hi = mid;
    }
    uint col = min(lo, m.w - 2u);
    if (col > 0u) s.x -= measured_cond(m, p, row, col - 1u, s.y);
    uint od = row * m.w + col;
    float v00 = measured_lookup(m.density, nd, od, p), v10 = measured_lookup(m.density, nd, od + 1u, p);
    float v01 = measured_lookup(m.density, nd, od + m.w, p);
    float v11 = measured_lookup(m.density, nd, od + m.w + 1u, p);
    float c0 = mix(v00, v01, s.y), c1 = mix(v10, v11, s.y);
    s.x = measured_sample_segment(s.x, float(m.w - 1u), c0, c1);
    pdf = mix(c0, c1, s.x);
    return (vec2(col, row) + s) * (1.0 / vec2(m.w - 1u, m.h - 1u));
}

// Marginal2D::invert_continuous: the inverse of measured_sample2, and the density.
vec2 measured_invert2(MeasuredWarp m, MeasuredParams p, vec2 s, out float pdf) {
    uint nc = m.h * (m.w - 1u), nm = m.h - 1u, nd = m.w * m.h;
    s = clamp(s, 0.0, 1.0) * vec2(m.w - 1u, m.h - 1u);
    uvec2 pos = min(uvec2(s), uvec2(m.w - 2u, m.h - 2u));
    s -= vec2(pos);
    uint od = pos.y * m.w + pos.x;
    float v00 = measured_lookup(m.density, nd, od, p), v10 = measured_lookup(m.density, nd, od + 1u, p);
    float v01 = measured_lookup(m.density, nd, od + m.w, p);
    float v11 = measured_lookup(m.density, nd, od + m.w + 1u, p);
    float c0 = mix(v00, v01, s.y), c1 = mix(v10, v11, s.y);
    pdf = mix(c0, c1, s.x);
    s.x = measured_invert_segment(s.x, 1.0 / float(m.w - 1u), c0, c1);
    if (pos.x > 0u) s.x += measured_cond(m, p, pos.y, pos.x - 1u, s.y);
    uint oc = pos.y * (m.w - 1u);
    float r0 = measured_lookup(m.conditional, nc, oc + m.w - 2u, p);
    float r1 = measured_lookup(m.conditional, nc, oc + 2u * (m.w - 1u) - 1u, p);
    s.x /= mix(r0, r1, s.y);
    s.y = measured_invert_segment(s.y, 1.0 / float(m.h - 1u), r0, r1);
    if (pos.y > 0u) s.y += measured_lookup(m.marginal, nm, pos.y - 1u, p);
    return s;
}

// The `rgb` table at sample-space point s (3 slices a direction).
vec3 measured_rgb(uint base, MeasuredParams p3, vec2 s) {
    uint n = measured_head(base, MEASURED_LUM_SIZE);
    uint at = base + measured_head(base, MEASURED_RGB);
    vec3 c;
    for (uint k = 0u; k < 3u; ++k) {
        MeasuredParams q = p3;
        q.slice += k;
        c[k] = measured_eval2(at, n, n, s, q);
    }
    return c;
}

// atan of x in [0, 1] to a few ulps (Cephes' atanf: one reduction by π/4 and a
// polynomial). GLSL's atan and asin may be approximations (lavapipe's lowering is off
// by ~1e-4 rad), and the tables' steepest parts (σ near the horizon) amplify that.
float measured_atan01(float x) {
    float base = 0.0;
    if (x > 0.41421356237) {
        base = 0.78539816339;
        x = (x - 1.0) / (x + 1.0);
    }
    float z = x * x;
    return base + ((((8.05374449538e-2 * z - 1.38776856032e-1) * z + 1.99777106478e-1) * z
                    - 3.33329491539e-1) * z * x + x);
}

// atan2 with IEEE's signed zeros (drjit's: atan2(-0, -0) = -π).
float measured_atan2(float y, float x) {
    float ax = abs(x), ay = abs(y);
    float r = 0.0;
    if (ax > 0.0 || ay > 0.0) {
        r = ay <= ax ? measured_atan01(ay / ax) : 0.5 * PI - measured_atan01(ax / ay);
    }
    if ((floatBitsToUint(x) & 0x80000000u) != 0u) r = PI - r;
    return (floatBitsToUint(y) & 0x80000000u) != 0u ? -r : r;
}

// Mitsuba's elevation(): acos(d.z) as 2 asin(|d - z|/2), stable near the pole.
float measured_elevation(vec3 d) {
    float h = min(0.5 * sqrt(d.x * d.x + d.y * d.y + (d.z - 1.0) * (d.z - 1.0)), 1.0);
    return 2.0 * measured_atan2(h, sqrt(max((1.0 - h) * (1.0 + h), 0.0)));
}

float measured_theta2u(float theta) { return sqrt(theta * (2.0 / PI)); }
float measured_phi2u(float phi) { return (phi + PI) * (0.5 / PI); }

// drjit's mulsign_neg(a, b): a with the sign flipped unless b's sign bit is set.
float measured_mulsign_neg(float a, float b) {
    return (floatBitsToUint(b) & 0x80000000u) != 0u ? a : -a;
}

// D(m) / (4 σ(wi)), the factor of files whose `rgb` is divided by it (`jacobian`).
float measured_jacobian_factor(uint base, vec2 u_m, vec2 u_wi) {
    if ((measured_head(base, MEASURED_FLAGS) & 2u) == 0u) return 1.0;
    uint nw = measured_head(base, MEASURED_NDF_SIZE), nh = measured_head(base, MEASURED_NDF_SIZE + 1u);
    uint sw = measured_head(base, MEASURED_SIGMA_SIZE), sh = measured_head(base, MEASURED_SIGMA_SIZE + 1u);
    float ndf = measured_eval2_plain(base + measured_head(base, MEASURED_NDF), nw, nh, u_m);
    float sigma = measured_eval2_plain(base + measured_head(base, MEASURED_SIGMA), sw, sh, u_wi);
    return ndf / (4.0 * sigma);
}

// Mirrors v into the tabulated azimuths (reduction 2 or 4) by the signs of wi (sx, sy).
vec3 measured_mirror(vec3 v, float sx, float sy) {
    return vec3(measured_mulsign_neg(v.x, sx), measured_mulsign_neg(v.y, sy), v.z);
}

// What eval and pdf share: the directions mirrored, the u coordinates of wi and the
// half vector, and the interpolation at wi.
struct MeasuredQuery {
    vec3 wi;     // Mitsuba's wi (our wo), mirrored
    vec3 m;      // the half vector
    vec2 u_wi;
    vec2 u_m;
    float phi_i;
    float theta_i;
};

MeasuredQuery measured_query(uint base, vec3 wo, vec3 wi) {
    MeasuredQuery q;
    vec3 a = wo, b = wi;  // Mitsuba's wi, wo
    if (measured_head(base, MEASURED_REDUCTION) >= 2u) {
        float sy = a.y, sx = measured_head(base, MEASURED_REDUCTION) == 4u ? a.x : sy;
        a = measured_mirror(a, sx, sy);
        b = measured_mirror(b, sx, sy);
    }
    q.wi = a;
    q.m = normalize(a + b);
    q.theta_i = measured_elevation(a);
    q.phi_i = measured_atan2(a.y, a.x);
    float theta_m = measured_elevation(q.m), phi_m = measured_atan2(q.m.y, q.m.x);
    bool iso = (measured_head(base, MEASURED_FLAGS) & 1u) != 0u;
    q.u_wi = vec2(measured_theta2u(q.theta_i), measured_phi2u(q.phi_i));
    q.u_m = vec2(measured_theta2u(theta_m), measured_phi2u(iso ? phi_m - q.phi_i : phi_m));
    q.u_m.y -= floor(q.u_m.y);
    return q;
}

vec3 bsdf_measured_eval(BsdfRecord b, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return vec3(0.0);
    uint base = b.table[0].x;
    MeasuredQuery q = measured_query(base, wo, wi);
    MeasuredParams p = measured_params(base, q.phi_i, q.theta_i, 1u);
    float vndf_pdf;
    vec2 s = measured_invert2(measured_warp(base, MEASURED_VNDF_SIZE, MEASURED_VNDF), p, q.u_m, vndf_pdf);
    MeasuredParams p3 = measured_params(base, q.phi_i, q.theta_i, 3u);
    return measured_rgb(base, p3, s) * measured_jacobian_factor(base, q.u_m, q.u_wi);
}

// Density per unit solid angle: the VNDF's over u and the luminance's, over the
// Jacobian of u -> m (2π² u sin θm) and of m -> wi (4 wi·m).
float bsdf_measured_pdf(BsdfRecord b, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
    uint base = b.table[0].x;
    MeasuredQuery q = measured_query(base, wo, wi);
    MeasuredParams p = measured_params(base, q.phi_i, q.theta_i, 1u);
    float vndf_pdf;
    vec2 s = measured_invert2(measured_warp(base, MEASURED_VNDF_SIZE, MEASURED_VNDF), p, q.u_m, vndf_pdf);
    MeasuredWarp lum = measured_warp(base, MEASURED_LUM_SIZE, MEASURED_LUM);
    float lum_pdf = measured_eval2(lum.density, lum.w, lum.h, s, p);
    float sin_m = sqrt(q.m.x * q.m.x + q.m.y * q.m.y);
    float jacobian = max(2.0 * PI * PI * q.u_m.x * sin_m, 1e-6) * 4.0 * dot(q.wi, q.m);
    return vndf_pdf * lum_pdf / jacobian;
}

BsdfSample bsdf_measured_sample(BsdfRecord b, vec3 wo, vec3 u) {
    if (wo.z <= 0.0) return bsdf_sample_none();
    uint base = b.table[0].x;
    vec3 wi = wo;  // Mitsuba's wi
    float sx = -1.0, sy = -1.0;
    uint reduction = measured_head(base, MEASURED_REDUCTION);
    if (reduction >= 2u) {
        sy = wi.y;
        sx = reduction == 4u ? wi.x : sy;
        wi = measured_mirror(wi, sx, sy);
    }
    float theta_i = measured_elevation(wi), phi_i = measured_atan2(wi.y, wi.x);
    vec2 u_wi = vec2(measured_theta2u(theta_i), measured_phi2u(phi_i));
    MeasuredParams p = measured_params(base, phi_i, theta_i, 1u);
    // Mitsuba's sample2 = (u.y, u.z), swapped.
    float lum_pdf, vndf_pdf;
    vec2 s = measured_sample2(measured_warp(base, MEASURED_LUM_SIZE, MEASURED_LUM), p, u.zy, lum_pdf);
    vec2 u_m = measured_sample2(measured_warp(base, MEASURED_VNDF_SIZE, MEASURED_VNDF), p, s, vndf_pdf);
    float phi_m = (2.0 * u_m.y - 1.0) * PI, theta_m = u_m.x * u_m.x * (0.5 * PI);
    if ((measured_head(base, MEASURED_FLAGS) & 1u) != 0u) phi_m += phi_i;
    float sin_m = sin(theta_m);
    vec3 m = vec3(cos(phi_m) * sin_m, sin(phi_m) * sin_m, cos(theta_m));
    float jacobian = max(2.0 * PI * PI * u_m.x * sin_m, 1e-6) * 4.0 * dot(wi, m);
    vec3 out_dir = 2.0 * dot(m, wi) * m - wi;
    float pdf = vndf_pdf * lum_pdf / jacobian;
    MeasuredParams p3 = measured_params(base, phi_i, theta_i, 3u);
    vec3 spec = measured_rgb(base, p3, s) * measured_jacobian_factor(base, u_m, u_wi);
    out_dir = measured_mirror(out_dir, sx, sy);
    if (out_dir.z <= 0.0 || !(pdf > 0.0)) return bsdf_sample_none();
    return BsdfSample(out_dir, spec / pdf, pdf, BSDF_FLAG_REFLECTION);
}
