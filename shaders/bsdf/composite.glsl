// Composite BSDFs (src/scene/bsdf/composite.rs): Mitsuba 3's mask, blendbsdf and
// twosided with two sides, resolved at a surface point into one leaf record, so that
// the kernels evaluate and sample one model per vertex without recursion. A blend
// (a mask is a blend of the pass-through mask_null and its BSDF by the opacity)
// takes child 1 with probability w and child 0 with 1 − w, from the vertex's lobe
// number u, which is rescaled to [0, 1) for the leaf (as Mitsuba's blendbsdf::sample
// and mask::sample): the mean of what the vertex evaluates and samples is the blend
// (pbrt-v4's MixMaterial). Needs scene_bindings.glsl, texture.glsl, surface.glsl,
// bsdf.glsl (BSDF_COMPOSITE, BSDF_HAS).
#ifndef BSDF_COMPOSITE_GLSL
#define BSDF_COMPOSITE_GLSL

// BsdfRecord.distribution of a node (kind BSDF_COMPOSITE).
#define COMPOSITE_BLEND 0u
#define COMPOSITE_TWOSIDED 1u
#define COMPOSITE_BUMP 2u
// Deepest nesting resolved (the loader's trees are finite; this bounds the loop).
#define COMPOSITE_MAX_DEPTH 16

// The leaf a surface point resolves to: its record index, the flags to add to it
// (BSDF_TWOSIDED where a twosided node chose a side), and the lobe number left for it.
struct CompositeLeaf {
    uint index;
    uint flags;
    float u;
};

// Resolves BSDF record `index` at surface point s seen from wo (world, towards the
// viewer) with the uniform number u. Records that are not nodes resolve to themselves.
CompositeLeaf bsdf_composite_resolve(uint index, Surface s, vec3 wo, float u) {
    CompositeLeaf leaf = CompositeLeaf(index, 0u, u);
    if (!BSDF_HAS(BSDF_COMPOSITE)) return leaf;
    for (int i = 0; i < COMPOSITE_MAX_DEPTH; i++) {
        BsdfRecord b = bsdf_load(leaf.index);
        if (b.kind != BSDF_COMPOSITE) break;
        uint c0 = b.tex_specular, c1 = b.tex_transmittance;
        if (b.distribution == COMPOSITE_TWOSIDED) {
            // Mitsuba's twosided: the back (wo below the shading normal) scatters by
            // its own BSDF in the mirrored frame.
            bool back = dot(wo, s.ns) < 0.0;
            leaf.index = back ? c1 : c0;
            leaf.flags |= BSDF_TWOSIDED;
        } else {
            // Blend or mask: w is child 1's probability (Mitsuba clamps it to [0, 1]).
            float w = b.tex_reflectance != 0u ? texture_luminance(texture_eval(b.tex_reflectance, s.uv)) : b.eta;
            w = clamp(w, 0.0, 1.0);
            bool second = leaf.u < w;
            leaf.index = second ? c1 : c0;
            leaf.u = second ? leaf.u / w : (leaf.u - w) / (1.0 - w);
            leaf.u = min(leaf.u, 0.99999994);
        }
    }
    return leaf;
}

#endif
