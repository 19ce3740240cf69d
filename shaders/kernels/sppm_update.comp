#version 460
#extension GL_GOOGLE_include_directive : require
// sppm_update: after an iteration's photons, each pixel that gathered M > 0 of them
// shrinks its radius and rescales its flux (Hachisuka and Jensen 2009, eqs. 6-7 and
// 10-11, as pbrt-v4's SPPMIntegrator::Render updates them):
//   N' = N + α M,   r' = r sqrt(N' / (N + M)),   τ' = (τ + Φ) (r' / r)²,
// then clears Φ and M, and raises photon_counters.max_radius to its radius (the next
// grid's cells must hold the largest gather).
// Reads and writes: SPPM pixels, photon counters.

#include "generated/spec_constants.glsl"
#include "queue/wavefront.glsl"
#include "photon/bindings.glsl"

// α of the update (Hachisuka and Jensen's alpha; pbrt-v4 fixes it at 2/3).
SPEC(SPPM_ALPHA);

void main() {
    uint q = thread_index();
    if (q >= push.path_count) return;
    SppmPixel px = sppm_pixels[q];
    if (px.m > 0u) {
        float m = float(px.m);
        float n_new = px.n + SPPM_ALPHA * m;
        float r_new = px.radius * sqrt(n_new / (px.n + m));
        px.tau = (px.tau + px.phi) * ((r_new * r_new) / (px.radius * px.radius));
        px.n = n_new;
        px.radius = r_new;
        px.phi = vec3(0.0);
        px.m = 0u;
        sppm_pixels[q] = px;
    }
    atomicMax(photon_counters.max_radius, floatBitsToUint(px.radius));
}
