// Sampling alias tables (Walker 1977; built on the host by render::alias). Needs
// scene_bindings.glsl for alias_load.
#ifndef ALIAS_GLSL
#define ALIAS_GLSL

// Picks an entry of the alias table at entries [base, base + n) with one uniform u
// (pmf: the probability of the entry picked), and remaps u to a fresh uniform number:
// its position within the part of [0, 1) that picked the entry, rescaled (sample
// reuse, as Mitsuba's DiscreteDistribution::sample_reuse). A stratified u stays
// stratified within each part.
uint alias_sample_reuse(uint base, uint n, inout float u, out float pmf) {
    float x = u * float(n);
    uint i = min(uint(x), n - 1u);
    float f = x - float(i);
    AliasEntry e = alias_load(base + i);
    bool own = f < e.prob;
    uint pick = own ? i : e.alias;
    u = own ? f / e.prob : (f - e.prob) / (1.0 - e.prob);
    u = clamp(u, 0.0, 0.99999994);
    pmf = alias_load(base + pick).pmf;
    return pick;
}

// alias_sample_reuse without the remapped number.
uint alias_sample(uint base, uint n, float u, out float pmf) {
    return alias_sample_reuse(base, n, u, pmf);
}

#endif
