// The sampler: uniform numbers for dimension `dim` of sample `sample_index` of pixel
// `pixel`, a pure function of those and the Sampler parameters (seed included), so any
// sample can be computed alone: batches, sample ranges, merged and resumed renders draw
// the same numbers as one whole render.
//
// Kinds (SAMPLER_*, layout.glsl; the host side is src/scene/sampler.rs):
//   independent : the pcg4d hash of rng.glsl.
//   stratified, multijitter, orthogonal (two kinds: strength 2 and more), ldsampler:
//                 Mitsuba 3's (sampler_mitsuba.glsl).
//   zsobol      : pbrt-v4's (sampler_zsobol.glsl).
// A dimension is 1-D or 2-D as its consumer asks (rng.glsl allots them); a 2-D
// dimension of a stratified kind is stratified jointly.
//
// Sample counts: a stratified kind's pattern has `count` samples (the render's sample
// count as the sampler rounds it). Index i >= count is sample i % count of pass
// i / count: each pass is a new, independently randomized pattern (the pass is folded
// into the pixel's sequence seed), so every index is valid (progressive rendering,
// resumed renders), and any prefix of a pass is still unbiased (the order of the
// samples within a pass is randomly permuted).
//
// Pixel keys: `pixel` is a key unique to the pixel; zsobol reads (key % width,
// key / width) as its position (sampler_pixel_xy).
//
// A kernel may define SAMPLER_KIND (a specialization constant) before including this
// file: the code of the other kinds then compiles away. Otherwise s.kind is read at run
// time (test kernels).
#ifndef SAMPLER_GLSL
#define SAMPLER_GLSL

#include "scene/layout.glsl"
#include "sampling/rng.glsl"

struct Sampler {
    uint kind;   // SAMPLER_*
    uint count;  // samples of one pass (>= 1)
    uint res_x;  // stratified: grid side; multijitter: columns; orthogonal: prime s;
                 // zsobol: log2(count)
    uint res_y;  // multijitter: rows; zsobol: base-4 digits of the Morton index
    uint flags;  // SAMPLER_JITTER, strength << SAMPLER_STRENGTH_SHIFT, scrambling
                 // << SAMPLER_SCRAMBLE_SHIFT
    uint seed;
    uint width;  // film width: pixel key -> position
    uint height;
};

#include "sampler/sampler_hash.glsl"
#include "sampler/sampler_mitsuba.glsl"
#include "sampler/sampler_zsobol.glsl"

#ifndef SAMPLER_KIND
#define SAMPLER_KIND (s.kind)
#endif

// The pixel's sequence seed for pass `pass`: seeds its permutations and scramblings
// (Mitsuba: sample_tea_32(seed, per-pixel seed)).
uint sampler_sequence(Sampler s, uint pixel, uint pass) {
    return rng_pcg4d(uvec4(pixel, pass, s.seed, 0x2545f491u)).x;
}

// Jitter within a stratum: independent uniform numbers (Mitsuba draws them from the
// pixel's PCG32 stream), or the stratum's centre without SAMPLER_JITTER.
vec2 sampler_jitter(Sampler s, uint pixel, uint sample_index, uint dim) {
    if ((s.flags & SAMPLER_JITTER) == 0u) return vec2(0.5);
    return rng_4d(pixel, sample_index, dim, s.seed).xy;
}

float sampler_1d(Sampler s, uint pixel, uint sample_index, uint dim) {
    if (SAMPLER_KIND == SAMPLER_INDEPENDENT) return rng_4d(pixel, sample_index, dim, s.seed).x;
    uint pass = sample_index / s.count;
    uint j = sample_index - pass * s.count;
    if (SAMPLER_KIND == SAMPLER_ZSOBOL) return sampler_zsobol_1d(s, pixel, j, pass, dim);
    uint seq = sampler_sequence(s, pixel, pass);
    if (SAMPLER_KIND == SAMPLER_LDSAMPLER) return sampler_ldsampler_1d(s, seq, j, dim);
    float jit = sampler_jitter(s, pixel, sample_index, dim).x;
    if (SAMPLER_KIND == SAMPLER_STRATIFIED) return sampler_stratified_1d(s, seq, j, dim, jit);
    if (SAMPLER_KIND == SAMPLER_MULTIJITTER) return sampler_multijitter_1d(s, seq, j, dim, jit);
    return sampler_orthogonal(s, SAMPLER_KIND, seq, j, 2u * dim, jit);
}

vec2 sampler_2d(Sampler s, uint pixel, uint sample_index, uint dim) {
    if (SAMPLER_KIND == SAMPLER_INDEPENDENT) return rng_4d(pixel, sample_index, dim, s.seed).xy;
    uint pass = sample_index / s.count;
    uint j = sample_index - pass * s.count;
    if (SAMPLER_KIND == SAMPLER_ZSOBOL) return sampler_zsobol_2d(s, pixel, j, pass, dim);
    uint seq = sampler_sequence(s, pixel, pass);
    if (SAMPLER_KIND == SAMPLER_LDSAMPLER) return sampler_ldsampler_2d(s, seq, j, dim);
    vec2 jit = sampler_jitter(s, pixel, sample_index, dim);
    if (SAMPLER_KIND == SAMPLER_STRATIFIED) return sampler_stratified_2d(s, seq, j, dim, jit);
    if (SAMPLER_KIND == SAMPLER_MULTIJITTER) return sampler_multijitter_2d(s, seq, j, dim, jit);
    // Orthogonal: two columns of the array, each with its own jitter.
    return vec2(sampler_orthogonal(s, SAMPLER_KIND, seq, j, 2u * dim, jit.x),
                sampler_orthogonal(s, SAMPLER_KIND, seq, j, 2u * dim + 1u, jit.y));
}

#endif
