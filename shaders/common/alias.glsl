// Sampling alias tables (Walker 1977; built on the host by render::alias). Needs
// scene_bindings.glsl for alias_load.
#ifndef ALIAS_GLSL
#define ALIAS_GLSL

// Picks an entry of the alias table at entries [base, base + n) with one uniform u.
// pmf: the probability of the entry picked.
uint alias_sample(uint base, uint n, float u, out float pmf) {
    float x = u * float(n);
    uint i = min(uint(x), n - 1u);
    AliasEntry e = alias_load(base + i);
    uint pick = (x - float(i)) < e.prob ? i : e.alias;
    pmf = alias_load(base + pick).pmf;
    return pick;
}

#endif
