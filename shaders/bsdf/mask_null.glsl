// The pass-through of Mitsuba 3's `mask` (src/bsdfs/mask.cpp), the leaf a mask's
// node resolves to with probability 1 − opacity (bsdf/composite.glsl): the ray goes on
// unchanged, a delta transmission of weight 1 (Mitsuba's null lobe, chosen with
// probability 1 − opacity and worth 1 − opacity). Like Mitsuba's null lobe it counts as
// a delta and as a bounce: the path's depth grows by one.
BsdfSample bsdf_mask_null_sample(BsdfRecord b, vec3 wo, vec3 u) {
    return BsdfSample(-wo, vec3(1.0), 0.0, BSDF_FLAG_TRANSMISSION | BSDF_FLAG_DELTA | BSDF_FLAG_NULL);
}
