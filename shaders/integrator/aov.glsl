// Mitsuba's AOVs (src/integrators/aov.cpp; scene::integrator::aov): what the first
// surface a camera ray meets records, by AOV kind (AOV_* = AovKind's codes). A ray
// that meets nothing gives 0 in every channel, as Mitsuba zeroes the invalid
// interaction. The kernel's list of AOVs is the constants FILM_AOVS_LO/HI, 4 bits a
// kind, 8 a word, 0 ending the list (defined before including this file).
// Needs scene_bindings.glsl, bvh.glsl, surface.glsl, bsdf.glsl, bsdf_textured.glsl.
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

// Kind i of the list (0 past its end).
uint aov_kind(uint i) {
    return ((i < 8u ? FILM_AOVS_LO : FILM_AOVS_HI) >> (4u * (i & 7u))) & 15u;
}

// Channels of an AOV kind.
uint aov_channels(uint kind) {
    return (kind == AOV_DEPTH || kind == AOV_PRIM_INDEX || kind == AOV_SHAPE_INDEX) ? 1u
        : kind == AOV_UV ? 2u : 3u;
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
};

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

// The AOVs of the first surface the ray (o, d) meets before tmax; `needs_albedo`:
// evaluate the BSDF.
AovHit aov_trace(vec3 o, vec3 d, float tmax, bool needs_albedo) {
    AovHit a = AovHit(false, 0.0, vec3(0.0), vec2(0.0), vec3(0.0), vec3(0.0), vec3(0.0), 0.0, 0.0);
    Hit h = bvh_closest(o, d, 0.0, tmax);
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
        : vec3(a.shape_index);
    float x = c == 0u ? v.x : (c == 1u ? v.y : v.z);
    return a.valid ? x : 0.0;
}

#endif
