// Hashes, permutations and scramblings shared by the samplers (sampler.glsl). All are
// pure functions of their arguments: a sample is computed from (pixel, sample index,
// dimension, seed) alone.
#ifndef SAMPLER_HASH_GLSL
#define SAMPLER_HASH_GLSL

// Largest float below 1 (1 - 2^-24): samples are clamped to [0, 1).
#define SAMPLER_ONE_MINUS_EPSILON 0.99999994

// The top 24 bits of x as a float in [0, 1).
float sampler_u32_to_float(uint x) { return float(x >> 8) * (1.0 / 16777216.0); }

// Tiny Encryption Algorithm as a hash of two words (Zafar, Olano and Curtis 2010,
// "GPU Random Numbers via the Tiny Encryption Algorithm"), `rounds` Feistel rounds.
uvec2 sampler_tea(uint v0, uint v1, uint rounds) {
    uint sum = 0u;
    for (uint i = 0u; i < rounds; i++) {
        sum += 0x9e3779b9u;
        v0 += ((v1 << 4) + 0xa341316cu) ^ (v1 + sum) ^ ((v1 >> 5) + 0xc8013ea4u);
        v1 += ((v0 << 4) + 0xad90777du) ^ (v0 + sum) ^ ((v0 >> 5) + 0x7e95761eu);
    }
    return uvec2(v0, v1);
}

// Element i of a pseudo-random permutation of [0, n), n any length, chosen by `seed`
// (Kensler 2013, "Correlated Multi-Jittered Sampling", Pixar Technical Memo 13-01,
// listing of permute()): a hash that is a bijection on the next power of two, walked
// until it lands inside [0, n) (cycle walking; on average fewer than 2 steps).
uint sampler_permute_kensler(uint i, uint n, uint seed) {
    if (n <= 1u) return 0u;
    uint w = n - 1u;
    w |= w >> 1; w |= w >> 2; w |= w >> 4; w |= w >> 8; w |= w >> 16;
    do {
        i ^= seed;
        i *= 0xe170893du;
        i ^= seed >> 16;
        i ^= (i & w) >> 4;
        i ^= seed >> 8;
        i *= 0x0929eb3fu;
        i ^= seed >> 23;
        i ^= (i & w) >> 1;
        i *= 1u | seed >> 27;
        i *= 0x6935fa69u;
        i ^= (i & w) >> 11;
        i *= 0x74dcb303u;
        i ^= (i & w) >> 2;
        i *= 0x9e501cc3u;
        i ^= (i & w) >> 2;
        i *= 0xc860a3dfu;
        i &= w;
        i ^= i >> 5;
    } while (i >= n);
    return (i + seed) % n;
}

// Element i of a pseudo-random permutation of [0, n), n a power of two: a shuffling
// network that at each bit level swaps the pairs (i, i ^ bit) a TEA hash of the pair
// and the seed picks (the `permute` of Mitsuba 3's ldsampler). log2(n) TEA hashes of
// two rounds.
uint sampler_permute_tea(uint i, uint n, uint seed) {
    for (uint bit = 1u; bit < n; bit <<= 1) {
        uint r = sampler_tea(i | bit, seed, 2u).x;
        if ((r & bit) != 0u) i ^= bit;
    }
    return i;
}

// 32-bit finalizer (Wellons 2018, "Prospecting for Hash Functions": lowbias32).
uint sampler_mix32(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

// A seed for a permutation or scrambling, from a sequence seed and a salt (a
// dimension, a column). Mitsuba 3 uses seq + dim (and products with constants): with
// Kensler's permutation, seeds that close give dependent permutations (measured on
// Mitsuba 3.9.1's stratified sampler: dimensions 0 and 12 of 64 pixels x 16 samples
// give X² = 98-141 on an 8 x 8 grid, 63 degrees of freedom), so the salt is hashed in.
uint sampler_seed(uint seq, uint salt) {
    return sampler_mix32(seq ^ sampler_mix32(salt + 0x9e3779b9u));
}

// Owen scrambling of a base-2 fixed-point sample v (bit 31 the first digit), approximated
// by a hash: Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4): reverse the
// bits so that each bit only depends on the bits above it, apply a Laine-Karras style
// hash in which every bit only depends on lower bits, reverse back. The multiplier
// constants are the improved ones of Vegdahl 2021 ("Building a Better LK Hash"), as
// pbrt-v4's FastOwenScrambler uses them.
uint sampler_owen_fast(uint v, uint seed) {
    v = bitfieldReverse(v);
    v ^= v * 0x3d20adeau;
    v += seed;
    v *= (seed >> 16) | 1u;
    v ^= v * 0x05526c56u;
    v ^= v * 0x53a22864u;
    return bitfieldReverse(v);
}

// Exact Owen scrambling of a base-2 fixed-point sample (Owen 1995): digit b is flipped
// by a hash of the digits above it and the seed (pbrt-v4's OwenScrambler, with a 32-bit
// hash for its 64-bit one).
uint sampler_owen(uint v, uint seed) {
    if ((seed & 1u) != 0u) v ^= 1u << 31;
    for (uint b = 1u; b < 32u; b++) {
        uint mask = 0xffffffffu << (32u - b);
        if ((sampler_mix32((v & mask) ^ seed) & (1u << b)) != 0u) {
            v ^= 1u << (31u - b);
        }
    }
    return v;
}

// Randomizations of base-2 digits (SAMPLER_SCRAMBLE_*): none, a random digital shift
// (XOR, pbrt's PermuteDigits), hash-based Owen scrambling, exact Owen scrambling.
uint sampler_scramble(uint v, uint seed, uint how) {
    if (how == SAMPLER_SCRAMBLE_NONE) return v;
    if (how == SAMPLER_SCRAMBLE_XOR) return v ^ seed;
    if (how == SAMPLER_SCRAMBLE_OWEN) return sampler_owen(v, seed);
    return sampler_owen_fast(v, seed);
}

// Generator matrix of the second Sobol' dimension (polynomial x + 1, all direction
// numbers 1) times i, as a fixed-point sample (bit 31 the first digit). The matrix is
// Pascal's triangle mod 2: output digit r (bit 31 - r) is the parity of the bits c of i
// with C(c, r) odd, that is (Lucas) with r's bits a subset of c's. That superset parity
// over the 5-bit positions is 5 shift-and-XOR steps, then a bit reversal: no loop over
// the bits of i (which llvmpipe runs for as many steps as the longest lane needs).
uint sampler_sobol_dim1(uint i) {
    i ^= (i >> 1) & 0x55555555u;
    i ^= (i >> 2) & 0x33333333u;
    i ^= (i >> 4) & 0x0f0f0f0fu;
    i ^= (i >> 8) & 0x00ff00ffu;
    i ^= (i >> 16) & 0x0000ffffu;
    return bitfieldReverse(i);
}

#endif
