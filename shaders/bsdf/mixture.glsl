// The one-sample mixture of BSDFs that Mitsuba's blendbsdf is (Mitsuba 3.9.1,
// src/bsdfs/blendbsdf.cpp): leaves with weights wₖ summing to 1, f = Σ wₖ fₖ and
// pdf = Σ wₖ pdfₖ (solid angle). Sampling picks leaf j with probability wⱼ and
// samples it; a smooth sample's weight is then f / pdf of the whole mixture at its
// direction (Veach 1997, sec. 9.2.4: the balance heuristic over the leaves), a delta
// sample keeps the leaf's own weight and pdf 0, since no other leaf has mass at its
// direction (Mitsuba 3.9.1 mixes the delta's discrete probability with the others'
// densities there, which is biased). Used by path.glsl through composite.glsl and by
// the warptest kernel (shaders/tests/sample_bsdf.comp). Needs bsdf.glsl.
#ifndef BSDF_MIXTURE_GLSL
#define BSDF_MIXTURE_GLSL

// Sample bs of the leaf of weight wj, with others = Σ over the other leaves of
// wₖ (fₖ(wo, bs.wi) |cos θi|, pdfₖ(wo, bs.wi)): the mixture's sample.
BsdfSample bsdf_mixture_sample(BsdfSample bs, float wj, vec4 others) {
    if (bs.flags != 0u && (bs.flags & BSDF_FLAG_DELTA) == 0u) {
        float pdf = wj * bs.pdf + others.a;
        bs.weight = pdf > 0.0 ? (wj * bs.pdf * bs.weight + others.rgb) / pdf : vec3(0.0);
        bs.pdf = pdf;
    }
    return bs;
}

#endif
