#version 460
#extension GL_GOOGLE_include_directive : require
// shade: turns each hit (or miss) into radiance, shadow rays and continuation rays,
// as the integrator chosen by specialization constant INTEGRATOR says.
// Reads: ray queue `queue_in`, hits. Writes: paths[], shadow queue, next ray queue.

#include "wavefront.glsl"
#include "scene_bindings.glsl"
#include "integrator.glsl"
#include "rng.glsl"
#include "surface.glsl"
#include "ao.glsl"
#include "emitter.glsl"

// The BSDF kinds the scene uses (a bit per BSDF_* kind): the others compile away.
layout(constant_id = 1) const uint SCENE_BSDF_KINDS = 0xffffffffu;
#define BSDF_KINDS SCENE_BSDF_KINDS
#include "bsdf.glsl"
#include "path.glsl"

layout(constant_id = 0) const uint INTEGRATOR = INTEGRATOR_AO;

void main() {
    uint i = thread_index();
    if (i >= counters.ray_count[push.queue_in]) return;
    RayItem r = rays[ray_slot(push.queue_in, i)];
    HitItem h = hits[i];
    if (INTEGRATOR >= INTEGRATOR_DIRECT_EMS) {
        path_shade(INTEGRATOR, r, h);
        return;
    }
    PathState path = paths[r.path];

    // Nothing emits in these integrators: an escaping ray (even a camera ray, as in
    // Nori's ao and normals) carries no radiance.
    if (h.prim == NONE) return;

    Surface s = surface_at(h.prim, h.u, h.v, r.origin, r.dir, h.t);
    surface_face(s, -r.dir);
    vec4 u = rng_4d(path.pixel, path.sample_index, rng_dim_bounce(push.depth, 0u), frame.seed);

    if (INTEGRATOR == INTEGRATOR_NORMALS) {
        // Nori's normals integrator: |n_s| per component. Unflipped normal here.
        Surface raw = surface_at(h.prim, h.u, h.v, r.origin, r.dir, h.t);
        paths[r.path].radiance += abs(raw.ns);
    } else if (INTEGRATOR == INTEGRATOR_AO) {
        vec3 wi;
        float weight = ao_sample(s.ns, s.ng, u.xy, frame.ao_uniform != 0u, wi);
        if (weight > 0.0) {
            path_push_shadow(surface_spawn_origin(s, s.ng), r.path, wi, frame.ao_max_t, path.throughput * weight);
        }
    } else if (INTEGRATOR == INTEGRATOR_SIMPLE) {
        // Point lights on diffuse surfaces (Nori's first lighting integrator): one
        // light chosen uniformly, L = (ρ/π) I cos θ / d² / P(light).
        uint count = frame.point_light_count;
        if (count == 0u) return;
        uint k = min(uint(u.x * float(count)), count - 1u);
        EmitterRecord light = emitters[k];
        vec3 to_light = light.position - s.p;
        float d2 = dot(to_light, to_light);
        float dist = sqrt(d2);
        vec3 wi = to_light / dist;
        float cos_theta = dot(s.ns, wi);
        if (cos_theta <= 0.0 || dot(s.ng, wi) <= 0.0 || d2 <= 0.0) return;
        BsdfRecord bsdf = bsdfs[shapes[s.shape].bsdf];
        vec3 f = bsdf.reflectance * INV_PI;
        vec3 contribution = path.throughput * f * light.radiance * (cos_theta / d2) * float(count);
        vec3 origin = surface_spawn_origin(s, s.ng);
        path_push_shadow(origin, r.path, wi, length(light.position - origin) * (1.0 - 1e-5), contribution);
    }
}
