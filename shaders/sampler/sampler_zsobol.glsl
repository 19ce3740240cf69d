// pbrt-v4's ZSobolSampler (Pharr, Jakob, Humphreys, PBR 4th ed., sec. 8.7.7; Ahmed and
// Wonka 2020, "Screen-Space Blue-Noise Diffusion of Monte Carlo Sampling Error via
// Hierarchical Ordering of Pixels"): one 2-D Sobol' sequence (dimensions 0 and 1) over
// the whole image, indexed by the pixel's Morton code followed by the sample index, with
// the base-4 digits of that index randomly permuted per dimension (by a hash of the
// digits above, so the permutation is a nested, Owen-like one over the quadtree of
// pixels). Neighbouring pixels then get complementary parts of one low-discrepancy
// sequence: error is distributed as blue noise across the image. Samples are randomized
// by Owen scrambling per dimension (sampler_scramble). Needs sampler_hash.glsl.
#ifndef SAMPLER_ZSOBOL_GLSL
#define SAMPLER_ZSOBOL_GLSL

// Bits of x (< 2^16) spread to the even bit positions.
uint sampler_spread_bits(uint x) {
    x &= 0xffffu;
    x = (x | (x << 8)) & 0x00ff00ffu;
    x = (x | (x << 4)) & 0x0f0f0f0fu;
    x = (x | (x << 2)) & 0x33333333u;
    x = (x | (x << 1)) & 0x55555555u;
    return x;
}

// A 64-bit index as (low word, high word): llvmpipe emulates 64-bit multiplies, so the
// index and its hashes stay in 32-bit words.
// Morton code of pixel (x, y) (x in the even bits) followed by log2spp bits of j.
uvec2 sampler_morton_index(uint x, uint y, uint log2spp, uint j) {
    uint lo = sampler_spread_bits(x) | (sampler_spread_bits(y) << 1);
    uint hi = sampler_spread_bits(x >> 16) | (sampler_spread_bits(y >> 16) << 1);
    if (log2spp > 0u) {
        hi = (hi << log2spp) | (lo >> (32u - log2spp));
        lo = (lo << log2spp) | j;
    }
    return uvec2(lo, hi);
}

// Permutation p (of the 24 of {0, 1, 2, 3}, in lexicographic order) applied to digit d:
// the table packs 2 bits per entry, a permutation per byte.
uint sampler_permute4(uint p, uint d) {
    uint w = p < 12u ? (p < 4u ? 0x78d8b4e4u : (p < 8u ? 0xb1e16c9cu : 0x2d8d39c9u))
                     : (p < 16u ? 0x36c672d2u : (p < 20u ? 0x63931e4eu : 0x1b4b2787u));
    return (w >> (8u * (p & 3u) + 2u * d)) & 3u;
}

// The sample index of dimension `dim` for Morton index m (pixel Morton code << log2spp
// | sample): each base-4 digit, from the top (`digits` base-4 digits for the pixel and
// sample parts), permuted by a hash of the digits above it and the dimension, so the
// permutation is nested (pbrt-v4's ZSobolSampler::GetSampleIndex); with an odd log2spp
// the last, single bit is flipped by such a hash. pbrt hashes the higher digits anew at
// each digit with a 64-bit MixBits; here a 32-bit hash is carried down the digits
// (h <- mix(h ^ (digit + 1))), which is as random a function of them and an order of
// magnitude cheaper on llvmpipe. The pass (sampler.glsl) is hashed in too, so later
// passes take other blocks of the sequence even without scrambling. The Sobol' points
// take the low 32 bits of the index, as pbrt's 32-bit generator matrices do.
uint sampler_zsobol_index(uvec2 m, uint dim, uint pass, uint log2spp, uint digits) {
    bool odd = (log2spp & 1u) != 0u;
    uint last = odd ? 1u : 0u;
    uint h = sampler_mix32((0x55555555u * dim + 0x9e3779b9u) ^ sampler_mix32(pass));
    uint index = 0u;
    for (uint i = digits; i-- > last;) {
        uint shift = 2u * i - last;
        uint digit = (shift < 32u ? m.x >> shift : m.y >> (shift - 32u)) & 3u;
        // (24 (top 24 bits of h)) >> 24: in [0, 24) without a division (which llvmpipe
        // runs lane by lane).
        uint p = ((h >> 8) * 24u) >> 24;
        if (shift < 32u) index |= sampler_permute4(p, digit) << shift;
        h = sampler_mix32(h ^ (digit + 1u));
    }
    if (odd) index |= (m.x & 1u) ^ (h & 1u);
    return index;
}

// Owen-scrambling seeds of a dimension: the same for every pixel (pixels differ by their
// part of the sequence), new for every pass of `count` samples.
uvec2 sampler_zsobol_seeds(Sampler s, uint dim, uint pass) {
    return rng_pcg4d(uvec4(dim, s.seed, pass, 0x7a50b01u)).xy;
}

vec2 sampler_zsobol_2d(Sampler s, uint pixel, uint j, uint pass, uint dim) {
    uint x = pixel % s.width;
    uint y = pixel / s.width;
    uint log2spp = s.res_x;
    uint i = sampler_zsobol_index(sampler_morton_index(x, y, log2spp, j), dim, pass, log2spp, s.res_y);
    uvec2 seeds = sampler_zsobol_seeds(s, dim, pass);
    uint how = (s.flags >> SAMPLER_SCRAMBLE_SHIFT) & 0xfu;
    return vec2(sampler_u32_to_float(sampler_scramble(bitfieldReverse(i), seeds.x, how)),
                sampler_u32_to_float(sampler_scramble(sampler_sobol_dim1(i), seeds.y, how)));
}

float sampler_zsobol_1d(Sampler s, uint pixel, uint j, uint pass, uint dim) {
    uint x = pixel % s.width;
    uint y = pixel / s.width;
    uint log2spp = s.res_x;
    uint i = sampler_zsobol_index(sampler_morton_index(x, y, log2spp, j), dim, pass, log2spp, s.res_y);
    uint how = (s.flags >> SAMPLER_SCRAMBLE_SHIFT) & 0xfu;
    return sampler_u32_to_float(sampler_scramble(bitfieldReverse(i), sampler_zsobol_seeds(s, dim, pass).x, how));
}

#endif
