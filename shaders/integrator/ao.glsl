// Ambient occlusion as Nori defines it: the cosine-weighted visibility integral
//   AO(x) = (1/π) ∫_{H²(n_s)} V(x, ω) cos θ dω,
// the radiance reflected by a white Lambertian surface under a uniform sky of
// radiance 1 (so it equals Mitsuba's `direct` under a `constant` emitter).
#ifndef AO_GLSL
#define AO_GLSL

#include "sampling/frame.glsl"
#include "sampling/warp.glsl"

// Samples a direction for one AO estimate at a surface with shading normal ns and
// geometric normal ng (both facing the viewer). Returns the estimator weight
// (1/π) cos θ / pdf, which is 0 for directions under the geometric surface (they
// would leak light through it).
float ao_sample(vec3 ns, vec3 ng, vec2 u, bool uniform_sampling, out vec3 wi) {
    vec3 local = uniform_sampling ? warp_uniform_hemisphere(u) : warp_cosine_hemisphere(u);
    wi = frame_to_world(ns, local);
    if (dot(wi, ng) <= 0.0 || local.z <= 0.0) return 0.0;
    // cosine pdf = cos θ / π: weight 1. uniform pdf = 1 / 2π: weight 2 cos θ.
    return uniform_sampling ? 2.0 * local.z : 1.0;
}

#endif
