// Mitsuba's AOVs (src/integrators/aov.cpp; scene::integrator::aov): what the first
// surface a camera ray meets records, by AOV kind (AOV_* = AovKind's codes). A ray
// that meets nothing gives 0 in every channel, as Mitsuba zeroes the invalid
// interaction. The kernel's list of AOVs is the constants FILM_AOVS_LO/HI, 4 bits a
// kind, 8 a word, 0 ending the list (defined before including this file).
// Needs scene_bindings.glsl, bvh.glsl, surface.glsl (with SURFACE_PARTIALS defined),
// bsdf.glsl, bsdf_textured.glsl.
#ifndef AOV_GLSL
#define AOV_GLSL

#define AOV_DEPTH 1u
#define AOV_POSITION 2u
#define AOV_UV 3u
#define AOV_GEO_NORMAL 4u
#define AOV_SH_NORMAL 5u
#define AOV_ALBEDO 6u
#define AOV_PRIM_INDEX 7u
#define AOV_SHAPE_INDEX 8u
#define AOV_DP_DU 9u
#define AOV_DP_DV 10u
#define AOV_DUV_DX 11u
#define AOV_DUV_DY 12u

// Kind i of the list (0 past its end).
uint aov_kind(uint i) {
    return ((i < 8u ? FILM_AOVS_LO : FILM_AOVS_HI) >> (4u * (i & 7u))) & 15u;
}

// Channels of an AOV kind.
uint aov_channels(uint kind) {
    return (kind == AOV_DEPTH || kind == AOV_PRIM_INDEX || kind == AOV_SHAPE_INDEX) ? 1u
        : (kind == AOV_UV || kind == AOV_DUV_DX || kind == AOV_DUV_DY) ? 2u : 3u;
}

// What a hit records, for every kind at once.
struct AovHit {
    bool valid;
    float t;
    vec3 p;
    vec2 uv;
    vec3 ng;
    vec3 ns;
    vec3 albedo;
    float prim_index;
    float shape_index;
    vec3 dp_du;
    vec3 dp_dv;
    vec2 duv_dx;
    vec2 duv_dy;
};

// A camera ray with Mitsuba's differentials (camera_ray_differentials).
struct AovRay {
    vec3 o;
    vec3 d;
    float tmax;
    bool has_differentials;
    vec3 o_x;
    vec3 d_x;
    vec3 o_y;
    vec3 d_y;
};

// Mitsuba's SurfaceInteraction::compute_uv_partials: the offset rays meet the tangent
// plane at p (normal n) at p + ∂p/∂x and p + ∂p/∂y, which the least-squares solve
// against ∂p/∂u and ∂p/∂v turns into uv; zero where ∂p/∂u and ∂p/∂v are degenerate.
void aov_uv_partials(AovRay r, vec3 p, vec3 n, vec3 dp_du, vec3 dp_dv,
                     out vec2 duv_dx, out vec2 duv_dy) {
    float d = dot(n, p);
    float t_x = (d - dot(n, r.o_x)) / dot(n, r.d_x);
    float t_y = (d - dot(n, r.o_y)) / dot(n, r.d_y);
    vec3 dp_dx = r.d_x * t_x + r.o_x - p;
    vec3 dp_dy = r.d_y * t_y + r.o_y - p;
    float a00 = dot(dp_du, dp_du);
    float a01 = dot(dp_du, dp_dv);
    float a11 = dot(dp_dv, dp_dv);
    float inv_det = 1.0 / (a00 * a11 - a01 * a01);
    if (isinf(inv_det) || isnan(inv_det)) inv_det = 0.0;
    float b0x = dot(dp_du, dp_dx);
    float b1x = dot(dp_dv, dp_dx);
    float b0y = dot(dp_du, dp_dy);
    float b1y = dot(dp_dv, dp_dy);
    duv_dx = vec2(a11 * b0x - a01 * b1x, a00 * b1x - a01 * b0x) * inv_det;
    duv_dy = vec2(a11 * b0y - a01 * b1y, a00 * b1y - a01 * b0y) * inv_det;
}

// Mitsuba's BSDF::eval_diffuse_reflectance: the diffuse reflectance of diffuse,
// plastic and roughplastic, the base color of principled and principledthin (all in
// b.reflectance); for the others its default, the BSDF evaluated towards the shading
// normal times π (cosine included), seen from the ray's direction.
vec3 aov_albedo(Surface s, vec3 ray_d) {
    BsdfRecord b = bsdf_textured(bsdf_load(shape_load(s.shape).bsdf), s.uv);
    if (b.kind == BSDF_DIFFUSE || b.kind == BSDF_PLASTIC || b.kind == BSDF_ROUGHPLASTIC
        || b.kind == BSDF_PRINCIPLED || b.kind == BSDF_PRINCIPLEDTHIN) {
        return b.reflectance;
    }
    vec3 t = cross(s.ns, s.ss);
    vec3 wo = -ray_d;
    vec3 wo_local = vec3(dot(wo, s.ss), dot(wo, t), dot(wo, s.ns));
    return bsdf_eval(b, wo_local, vec3(0.0, 0.0, 1.0), s.uv) * PI;
}

// The AOVs of the first surface the ray r meets before its tmax; `needs_albedo`:
// evaluate the BSDF; `needs_uv_partials`: compute duv_dx, duv_dy.
AovHit aov_trace(AovRay r, bool needs_albedo, bool needs_uv_partials) {
    vec3 o = r.o, d = r.d;
    AovHit a = AovHit(false, 0.0, vec3(0.0), vec2(0.0), vec3(0.0), vec3(0.0), vec3(0.0), 0.0, 0.0,
                      vec3(0.0), vec3(0.0), vec2(0.0), vec2(0.0));
    Hit h = bvh_closest(o, d, 0.0, r.tmax);
    if (h.prim == HIT_NONE) return a;
    Surface s = surface_at(h.prim, h.u, h.v, o, d, h.t);
    a.valid = true;
    a.t = h.t;
    a.p = s.p;
    a.uv = s.uv;
    a.ng = s.ng;
    a.ns = s.ns;
    if (needs_albedo) a.albedo = aov_albedo(s, d);
    Prim prim = instance_prim_load(h.prim);
    a.prim_index = float(prim.kind == PRIM_TRIANGLE ? prim.index - film_aov_shape_first[prim.shape] : 0u);
    a.shape_index = float(s.shape + 1u);
    a.dp_du = surface_dp_du;
    a.dp_dv = surface_dp_dv;
    if (needs_uv_partials && r.has_differentials) {
        aov_uv_partials(r, s.p, s.ng, a.dp_du, a.dp_dv, a.duv_dx, a.duv_dy);
    }
    return a;
}

// Channel c of an AOV of kind `kind` of hit a.
float aov_value(AovHit a, uint kind, uint c) {
    vec3 v = kind == AOV_DEPTH ? vec3(a.t)
        : kind == AOV_POSITION ? a.p
        : kind == AOV_UV ? vec3(a.uv, 0.0)
        : kind == AOV_GEO_NORMAL ? a.ng
        : kind == AOV_SH_NORMAL ? a.ns
        : kind == AOV_ALBEDO ? a.albedo
        : kind == AOV_PRIM_INDEX ? vec3(a.prim_index)
        : kind == AOV_SHAPE_INDEX ? vec3(a.shape_index)
        : kind == AOV_DP_DU ? a.dp_du
        : kind == AOV_DP_DV ? a.dp_dv
        : kind == AOV_DUV_DX ? vec3(a.duv_dx, 0.0)
        : vec3(a.duv_dy, 0.0);
    float x = c == 0u ? v.x : (c == 1u ? v.y : v.z);
    return a.valid ? x : 0.0;
}

#endif
