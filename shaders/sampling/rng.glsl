// Stateless random numbers: a hash of (pixel, sample index, dimension, seed), so a
// render is reproducible and any range of samples can be rendered on its own. This is
// the `independent` sampler and the jitter of the stratified ones
// (shaders/sampler/sampler.glsl), and it serves the draws no sampler dimension is
// allotted to (the unbounded loops of delta and ratio tracking).
#ifndef RNG_GLSL
#define RNG_GLSL

// pcg4d: Jarzynski and Olano 2020, "Hash Functions for GPU Rendering", JCGT 9(3).
uvec4 rng_pcg4d(uvec4 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    v ^= v >> 16u;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    return v;
}

// 24 random bits to a float in [0, 1).
float rng_to_float(uint x) { return float(x >> 8) * (1.0 / 16777216.0); }

// Four independent uniform numbers in [0, 1) for dimension `dim` of a sample.
vec4 rng_4d(uint pixel, uint sample_index, uint dim, uint seed) {
    uvec4 h = rng_pcg4d(uvec4(pixel, sample_index, dim, seed));
    return vec4(rng_to_float(h.x), rng_to_float(h.y), rng_to_float(h.z), rng_to_float(h.w));
}

// Sampler dimensions, each drawn as 1-D or 2-D by its one consumer, so that a stratified
// sampler stratifies every 2-D need jointly (pixel position, emitter point, BSDF
// direction) and a dimension always serves the same purpose in every sample of a pixel.
// 0: position in the pixel (2-D); 1: the lens (2-D, for cameras with an aperture);
// then RNG_DIMS_PER_BOUNCE per path vertex (bounce `depth`, slot k):
#define RNG_DIM_CAMERA 0u
#define RNG_DIM_APERTURE 1u
#define RNG_DIMS_PER_BOUNCE 6u
// 2-D: emitter sampling (the emitter's choice reuses the first coordinate, as in
// Mitsuba's Scene::sample_emitter_direction); AO and `simple` use it too.
#define RNG_SLOT_EMITTER 0u
// 2-D: the BSDF's or phase function's direction.
#define RNG_SLOT_BSDF 1u
// 1-D: the BSDF's lobe (reflection or transmission, specular or diffuse).
#define RNG_SLOT_LOBE 2u
// 1-D: Russian roulette.
#define RNG_SLOT_RR 3u
// 2-D: the first draw of the medium stage (free flight: channel and distance;
// equiangular: segment and distance); later draws are hashed (medium.glsl).
#define RNG_SLOT_MEDIUM 4u
// 2-D: a second emitter sample, where the first chose an equiangular distance.
#define RNG_SLOT_EMITTER2 5u
uint rng_dim_bounce(uint depth, uint k) { return 2u + depth * RNG_DIMS_PER_BOUNCE + k; }

#endif
