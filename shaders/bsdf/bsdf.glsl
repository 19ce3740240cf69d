// Surface scattering: the interface the integrators call, dispatching on
// BsdfRecord.kind to one file per model in bsdf/.
//
// Conventions (Mitsuba's): directions are in the local shading frame (z = shading
// normal, from frame_basis), both point away from the surface; wo is the direction
// towards the viewer (where radiance goes), wi the sampled or light direction.
// One-sided models (all but the dielectrics) are black unless cos θo > 0 and
// cos θi > 0; BSDF_TWOSIDED in b.flags mirrors the frame when wo is below, so both
// faces use the model. Dielectrics handle both sides (wo below = inside).
//
//   vec3  bsdf_eval(b, wo, wi, uv)   f(wo, wi) |cos θi|; 0 for delta lobes.
//   float bsdf_pdf(b, wo, wi, uv)    density of bsdf_sample choosing wi, per unit
//                                    solid angle; 0 for delta lobes.
//   BsdfSample bsdf_sample(b, wo, u, uv)
//       u: three uniform numbers in [0, 1) (u.x picks a lobe, u.yz the direction).
//       weight = f |cos θi| / pdf. A delta lobe has pdf = 0, BSDF_FLAG_DELTA and
//       weight = f |cos θi| / (discrete probability of choosing it). No sample
//       (absorbed, or wo on the wrong side): flags == 0 and weight == 0.
//   bool  bsdf_is_delta(b)           every lobe is a delta: skip emitter sampling.
//
// uv is the surface texture coordinate (unused until textures arrive).
//
// Models a scene does not use compile away: define BSDF_KINDS (a bit per BSDF_* kind,
// e.g. a specialization constant) before including this file; the default keeps all.
#ifndef BSDF_GLSL
#define BSDF_GLSL

#include "scene/layout.glsl"
#include "sampling/warp.glsl"
#include "bsdf/fresnel.glsl"
#include "bsdf/microfacet.glsl"

#ifndef BSDF_KINDS
#define BSDF_KINDS 0xffffffffu
#endif
// Whether the scene may hold BSDFs of kind k.
#define BSDF_HAS(k) ((BSDF_KINDS & (1u << (k))) != 0u)

#define BSDF_FLAG_REFLECTION 1u
#define BSDF_FLAG_TRANSMISSION 2u
#define BSDF_FLAG_DELTA 4u
// Transmission straight through without bending (thin dielectric): no (η_i/η_t)².
#define BSDF_FLAG_NULL 8u

struct BsdfSample {
    vec3 wi;
    vec3 weight; // f |cos θi| / pdf (delta: / discrete probability)
    float pdf;   // per unit solid angle; 0 for delta lobes
    uint flags;  // BSDF_FLAG_*; 0: no sample
};

BsdfSample bsdf_sample_none() { return BsdfSample(vec3(0.0, 0.0, 1.0), vec3(0.0), 0.0, 0u); }

#include "bsdf/diffuse.glsl"
#include "bsdf/conductor.glsl"
#include "bsdf/roughconductor.glsl"
#include "bsdf/dielectric.glsl"
#include "bsdf/roughdielectric.glsl"
#include "bsdf/plastic.glsl"
#include "bsdf/roughplastic.glsl"
#include "bsdf/nori_microfacet.glsl"
#include "bsdf/thindielectric.glsl"

// Twosided: mirror the frame so that wo lies above (Mitsuba src/bsdfs/twosided.cpp).
bool bsdf_flip(BsdfRecord b, vec3 wo) { return (b.flags & BSDF_TWOSIDED) != 0u && wo.z < 0.0; }
vec3 bsdf_mirror(vec3 v) { return vec3(v.xy, -v.z); }

vec3 bsdf_eval(BsdfRecord b, vec3 wo, vec3 wi, vec2 uv) {
    if (bsdf_flip(b, wo)) {
        wo = bsdf_mirror(wo);
        wi = bsdf_mirror(wi);
    }
    switch (b.kind) {
    case BSDF_DIFFUSE: if (BSDF_HAS(BSDF_DIFFUSE)) return bsdf_diffuse_eval(b, wo, wi); break;
    case BSDF_ROUGHCONDUCTOR: if (BSDF_HAS(BSDF_ROUGHCONDUCTOR)) return bsdf_roughconductor_eval(b, wo, wi); break;
    case BSDF_ROUGHDIELECTRIC: if (BSDF_HAS(BSDF_ROUGHDIELECTRIC)) return bsdf_roughdielectric_eval(b, wo, wi); break;
    case BSDF_PLASTIC: if (BSDF_HAS(BSDF_PLASTIC)) return bsdf_plastic_eval(b, wo, wi); break;
    case BSDF_ROUGHPLASTIC: if (BSDF_HAS(BSDF_ROUGHPLASTIC)) return bsdf_roughplastic_eval(b, wo, wi); break;
    case BSDF_NORI_MICROFACET: if (BSDF_HAS(BSDF_NORI_MICROFACET)) return bsdf_nori_microfacet_eval(b, wo, wi); break;
    default: return vec3(0.0); // conductor, dielectric, thindielectric: delta lobes only
    }
}

float bsdf_pdf(BsdfRecord b, vec3 wo, vec3 wi, vec2 uv) {
    if (bsdf_flip(b, wo)) {
        wo = bsdf_mirror(wo);
        wi = bsdf_mirror(wi);
    }
    switch (b.kind) {
    case BSDF_DIFFUSE: if (BSDF_HAS(BSDF_DIFFUSE)) return bsdf_diffuse_pdf(b, wo, wi); break;
    case BSDF_ROUGHCONDUCTOR: if (BSDF_HAS(BSDF_ROUGHCONDUCTOR)) return bsdf_roughconductor_pdf(b, wo, wi); break;
    case BSDF_ROUGHDIELECTRIC: if (BSDF_HAS(BSDF_ROUGHDIELECTRIC)) return bsdf_roughdielectric_pdf(b, wo, wi); break;
    case BSDF_PLASTIC: if (BSDF_HAS(BSDF_PLASTIC)) return bsdf_plastic_pdf(b, wo, wi); break;
    case BSDF_ROUGHPLASTIC: if (BSDF_HAS(BSDF_ROUGHPLASTIC)) return bsdf_roughplastic_pdf(b, wo, wi); break;
    case BSDF_NORI_MICROFACET: if (BSDF_HAS(BSDF_NORI_MICROFACET)) return bsdf_nori_microfacet_pdf(b, wo, wi); break;
    default: return 0.0;
    }
}

BsdfSample bsdf_sample(BsdfRecord b, vec3 wo, vec3 u, vec2 uv) {
    bool flip = bsdf_flip(b, wo);
    if (flip) wo = bsdf_mirror(wo);
    BsdfSample s;
    switch (b.kind) {
    case BSDF_DIFFUSE: s = BSDF_HAS(BSDF_DIFFUSE) ? bsdf_diffuse_sample(b, wo, u) : bsdf_sample_none(); break;
    case BSDF_CONDUCTOR: s = BSDF_HAS(BSDF_CONDUCTOR) ? bsdf_conductor_sample(b, wo, u) : bsdf_sample_none(); break;
    case BSDF_ROUGHCONDUCTOR: s = BSDF_HAS(BSDF_ROUGHCONDUCTOR) ? bsdf_roughconductor_sample(b, wo, u) : bsdf_sample_none(); break;
    case BSDF_DIELECTRIC: s = BSDF_HAS(BSDF_DIELECTRIC) ? bsdf_dielectric_sample(b, wo, u) : bsdf_sample_none(); break;
    case BSDF_ROUGHDIELECTRIC: s = BSDF_HAS(BSDF_ROUGHDIELECTRIC) ? bsdf_roughdielectric_sample(b, wo, u) : bsdf_sample_none(); break;
    case BSDF_PLASTIC: s = BSDF_HAS(BSDF_PLASTIC) ? bsdf_plastic_sample(b, wo, u) : bsdf_sample_none(); break;
    case BSDF_ROUGHPLASTIC: s = BSDF_HAS(BSDF_ROUGHPLASTIC) ? bsdf_roughplastic_sample(b, wo, u) : bsdf_sample_none(); break;
    case BSDF_NORI_MICROFACET: s = BSDF_HAS(BSDF_NORI_MICROFACET) ? bsdf_nori_microfacet_sample(b, wo, u) : bsdf_sample_none(); break;
    case BSDF_THINDIELECTRIC: s = BSDF_HAS(BSDF_THINDIELECTRIC) ? bsdf_thindielectric_sample(b, wo, u) : bsdf_sample_none(); break;
    default: s = bsdf_sample_none(); break;
    }
    if (flip) s.wi = bsdf_mirror(s.wi);
    return s;
}

bool bsdf_is_delta(BsdfRecord b) {
    return b.kind == BSDF_CONDUCTOR || b.kind == BSDF_DIELECTRIC || b.kind == BSDF_THINDIELECTRIC;
}

#endif
