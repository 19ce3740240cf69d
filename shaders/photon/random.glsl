// Random numbers of photon paths: the stateless pcg4d hash of rng.glsl keyed by
// (photon path index, iteration, dimension, seed), with dimensions in a range of their
// own (PHOTON_RNG_DIM_BASE and up, camera paths use small ones). So a photon path's
// numbers depend on nothing but its index and the iteration (the photon map of a pass
// is the same whatever the batch size), and never coincide with the numbers of a
// camera path, whatever sampler those come from. Needs wavefront.glsl (frame.seed).
#ifndef PHOTON_RANDOM_GLSL
#define PHOTON_RANDOM_GLSL

#include "sampling/rng.glsl"

#define PHOTON_RNG_DIM_BASE 0x40000000u
// Emission takes dimensions 0 and 1; bounce k (0: the first surface) dimension 2 + k.
#define PHOTON_RNG_DIM_EMIT 0u
#define PHOTON_RNG_DIM_BOUNCE 2u

vec4 photon_rng(uint index, uint iteration, uint dim) {
    uvec4 h = rng_pcg4d(uvec4(index, iteration, PHOTON_RNG_DIM_BASE + dim, frame.seed));
    return vec4(rng_to_float(h.x), rng_to_float(h.y), rng_to_float(h.z), rng_to_float(h.w));
}

#endif
