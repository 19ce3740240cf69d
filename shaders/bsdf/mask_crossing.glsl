// A `mask` at the root of a shape's BSDF, as the volumetric path tracers cross it
// (Mitsuba 3.9.1's volpath, src/integrators/volpath.cpp, and mask.cpp's
// eval_null_transmission): a path passes it as a null surface with probability
// 1 − opacity (no vertex, no bounce, its MIS state kept), and a shadow ray passes it
// scaled by 1 − opacity. Needs scene_bindings.glsl, texture.glsl, bsdf.glsl.
//
// A mask inside another composite (a blend with a mask child, a mask of a mask, a
// bump map over a mask; twosided refuses masks, as Mitsuba's) is crossed the same
// way with the tree's null weight: Mitsuba's volpath passes a surface whenever the
// BSDF's sample has the Null flag, which a blend's or mask's sample has with the
// product of the weights down to a pass-through (the sum over its pass-throughs),
// a bump map's sample weighed by its shadowing term (bsdf_composite_null_pass), and
// a shadow ray passes scaled by eval_null_transmission, which blendbsdf and mask
// forward with their weights but bumpmap does not (Mitsuba 3.9.1: 0 below a bump
// map; bsdf_null_weight). Where the path does not pass, path_shade takes the tree
// without its pass-throughs (bsdf_composite_solid), its MIS weights by the whole
// tree's pdf (path.glsl's mis_scale).
#ifndef BSDF_MASK_CROSSING_GLSL
#define BSDF_MASK_CROSSING_GLSL

// The weight of child 1 of blend or mask node b (src/scene/bsdf/composite.rs) at uv,
// child 0 having 1 − it: its texture's eval_1 or its constant, clamped to [0, 1] as
// Mitsuba 3.9.1's blendbsdf::eval_weight and mask::eval_opacity clamp it.
float bsdf_blend_weight(BsdfRecord b, vec2 uv) {
    float w = b.tex_reflectance != 0u ? texture_eval_1(b.tex_reflectance, uv) : b.eta;
    return clamp(w, 0.0, 1.0);
}

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

// How a volumetric path tracer crosses BSDF record `index` (MASK_CROSSING_*).
#define MASK_CROSSING_NONE 0u
// A mask at the root whose BSDF has no pass-through of its own: 1 − opacity.
#define MASK_CROSSING_ROOT 1u
// Any other tree with pass-throughs: bsdf_composite_null_pass, bsdf_null_weight.
#define MASK_CROSSING_TREE 2u

// Nodes a tree walk visits at most (the loader's trees are finite; this bounds it),
// and its stack.
#define MASK_WALK_STEPS 32
#define MASK_WALK_STACK 8

// Whether the tree of record `index` has a pass-through (mask_null) leaf that a
// path can reach (not below a twosided node: none can be).
bool bsdf_has_null_leaf(uint index) {
    bool found = false;
    if (BSDF_HAS(BSDF_COMPOSITE) && BSDF_HAS(BSDF_MASK_NULL)) {
        uint stack[MASK_WALK_STACK];
        stack[0] = index;
        uint top = 1u;
        for (int i = 0; i < MASK_WALK_STEPS && top > 0u && !found; i++) {
            BsdfRecord b = bsdf_load(stack[--top]);
            if (b.kind == BSDF_MASK_NULL) found = true;
            if (b.kind != BSDF_COMPOSITE || b.distribution == 1u /* COMPOSITE_TWOSIDED */) continue;
            // A bump map (2u) has child 0 only; a blend or mask both.
            if (top < uint(MASK_WALK_STACK)) stack[top++] = b.tex_specular;
            if (b.distribution == 0u && top < uint(MASK_WALK_STACK)) stack[top++] = b.tex_transmittance;
        }
    }
    return found;
}

// How the volumetric path tracers cross record `index` (MASK_CROSSING_*).
uint bsdf_mask_crossing(uint index) {
    uint crossing = MASK_CROSSING_NONE;
    if (BSDF_HAS(BSDF_COMPOSITE) && BSDF_HAS(BSDF_MASK_NULL) && bsdf_has_null_leaf(index)) {
        crossing = bsdf_is_mask(index) && !bsdf_has_null_leaf(bsdf_load(index).tex_transmittance)
            ? MASK_CROSSING_ROOT : MASK_CROSSING_TREE;
    }
    return crossing;
}

// What a shadow ray passing the tree of record `index` at uv is scaled by, as
// Mitsuba 3.9.1's eval_null_transmission: the sum over its mask_null leaves of the
// product of the blend and mask weights above each (as bsdf_composite_mix weighs
// leaves), a bump map's subtree counting 0 (bumpmap.cpp does not forward it). A path
// passes by sampling (bsdf_composite_null_pass, composite.glsl), bump maps included.
float bsdf_null_weight(uint index, vec2 uv) {
    float sum = 0.0;
    uint stack[MASK_WALK_STACK];
    float weight[MASK_WALK_STACK];
    stack[0] = index;
    weight[0] = 1.0;
    uint top = 1u;
    for (int i = 0; i < MASK_WALK_STEPS && top > 0u; i++) {
        top--;
        uint k = stack[top];
        float w0 = weight[top];
        BsdfRecord b = bsdf_load(k);
        if (b.kind == BSDF_MASK_NULL) sum += w0;
        // Twosided (1u) and bump map (2u) nodes pass nothing.
        if (b.kind != BSDF_COMPOSITE || b.distribution != 0u /* COMPOSITE_BLEND */) continue;
        // Blend or mask: child 1 has weight w, child 0 1 − w.
        float w = bsdf_blend_weight(b, uv);
        if (top + 2u <= uint(MASK_WALK_STACK)) {
            stack[top] = b.tex_specular;
            weight[top++] = w0 * (1.0 - w);
            stack[top] = b.tex_transmittance;
            weight[top++] = w0 * w;
        }
    }
    return sum;
}

// The opacity of mask record `index` at uv.
float bsdf_mask_opacity(uint index, vec2 uv) {
    return bsdf_blend_weight(bsdf_load(index), uv);
}

#endif
