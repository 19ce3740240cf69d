// A `mask` at the root of a shape's BSDF, as the volumetric path tracers cross it
// (Mitsuba 3.9.1's volpath, src/integrators/volpath.cpp, and mask.cpp's
// eval_null_transmission): a path passes it as a null surface with probability
// 1 − opacity (no vertex, no bounce, its MIS state kept), and a shadow ray passes it
// scaled by 1 − opacity. Needs scene_bindings.glsl, texture.glsl, bsdf.glsl.
#ifndef BSDF_MASK_CROSSING_GLSL
#define BSDF_MASK_CROSSING_GLSL

// Whether BSDF record `index` is a mask: a blend node (src/scene/bsdf/composite.rs)
// whose child 0 is the pass-through.
bool bsdf_is_mask(uint index) {
    bool mask = false;
    if (BSDF_HAS(BSDF_COMPOSITE) && BSDF_HAS(BSDF_MASK_NULL)) {
        BsdfRecord b = bsdf_load(index);
        mask = b.kind == BSDF_COMPOSITE && b.distribution == 0u && bsdf_load(b.tex_specular).kind == BSDF_MASK_NULL;
    }
    return mask;
}

// The opacity of mask record `index` at uv, as Mitsuba's: its texture's eval_1 or
// its constant, clamped to [0, 1].
float bsdf_mask_opacity(uint index, vec2 uv) {
    BsdfRecord b = bsdf_load(index);
    float w = b.tex_reflectance != 0u ? texture_eval_1(b.tex_reflectance, uv) : b.eta;
    return clamp(w, 0.0, 1.0);
}

#endif
