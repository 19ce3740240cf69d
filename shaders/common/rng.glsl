// Stateless random numbers: a hash of (pixel, sample index, dimension, seed), so a
// render is reproducible and any range of samples can be rendered on its own.
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

// Dimensions: 0 for the pixel position and lens, then RNG_DIMS_PER_BOUNCE per bounce.
#define RNG_DIM_CAMERA 0u
#define RNG_DIMS_PER_BOUNCE 4u
uint rng_dim_bounce(uint depth, uint k) { return 1u + depth * RNG_DIMS_PER_BOUNCE + k; }

#endif
