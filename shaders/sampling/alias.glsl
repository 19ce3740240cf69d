// Sampling alias tables (Walker 1977; built on the host by render::alias). Needs
// scene_bindings.glsl for alias_load.
#ifndef ALIAS_GLSL
#define ALIAS_GLSL

#include "numeric/convert.glsl"

// Picks an entry of the alias table at entries [base, base + n) with one uniform u
// (pmf: the probability of the entry picked), and remaps u to a fresh uniform number:
// its position within the part of [0, 1) that picked the entry, rescaled (sample
// reuse, as Mitsuba's DiscreteDistribution::sample_reuse). A stratified u stays
// stratified within each part.
uint alias_sample_reuse(uint base, uint n, inout float u, out float pmf) {
    float x = u * float(n);
    uint i = min(floor_to_uint(x), n - 1u);
    float f = x - float(i);
    AliasEntry e = alias_load(base + i);
    bool own = f < e.prob;
    uint pick = own ? i : e.alias;
    u = own ? f / e.prob : (f - e.prob) / (1.0 - e.prob);
    u = clamp(u, 0.0, 0.99999994);
    pmf = alias_load(base + pick).pmf;
    return pick;
}

// Picks an entry of the table at [base, base + n) by inverting its cumulative pmf
// (each entry's `prim` holds the pmf of the entries before it as float bits:
// render::alias::set_cdf) and remaps u to its position within the entry's interval,
// rescaled: a binary search, log2(n) loads, where the alias method takes one, but each
// entry owns one interval of [0, 1), so a stratified u stays stratified for each entry
// (Mitsuba's DiscreteDistribution::sample_reuse; the alias method maps several pieces of
// [0, 1) onto one entry, and their remapped numbers overlap).
uint alias_sample_cdf(uint base, uint n, inout float u, out float pmf) {
    uint lo = 0u, hi = n;
    while (hi - lo > 1u) {
        uint mid = (lo + hi) >> 1;
        if (uintBitsToFloat(alias_load(base + mid).prim) <= u) lo = mid; else hi = mid;
    }
    AliasEntry e = alias_load(base + lo);
    pmf = e.pmf;
    u = clamp((u - uintBitsToFloat(e.prim)) / pmf, 0.0, 0.99999994);
    return lo;
}

// alias_sample_reuse without the remapped number.
uint alias_sample(uint base, uint n, float u, out float pmf) {
    return alias_sample_reuse(base, n, u, pmf);
}

#endif
