// The integrators that shade only the first hit: `normals` (Nori's: |n_s| per
// component), `depth` (Mitsuba's: the hit's distance along the camera ray, from its
// origin on the near plane as Mitsuba's si.t), `ao` (ambient occlusion, ao.glsl) and `simple` (point lights on diffuse
// surfaces, Nori's first lighting integrator). Nothing emits in them: a ray that
// escapes (even a camera ray, as in Nori) carries no radiance. Surfaces are shaded
// from both sides. Needs wavefront.glsl, scene_bindings.glsl.
#ifndef FIRST_HIT_GLSL
#define FIRST_HIT_GLSL

#include "integrator/integrator.glsl"
#include "queue/queue.glsl"
#include "sampler/sampler_frame.glsl"
#include "shape/surface.glsl"
#include "integrator/ao.glsl"
#include "numeric/convert.glsl"

void first_hit_shade(uint integrator, RayItem r, HitItem h) {
    if (h.prim == NONE) return;
    PathState path = path_load(r.path);
    Surface s = surface_at(h.prim, h.u, h.v, r.origin, r.dir, h.t);
    if (integrator == INTEGRATOR_DEPTH) {
        path.radiance += vec3(h.t);
        path_store_radiance(r.path, path);
        return;
    }
    if (integrator == INTEGRATOR_NORMALS) {
        path.radiance += abs(s.ns); // before facing the viewer
        path_store_radiance(r.path, path);
        return;
    }
    surface_face(s, -r.dir);
    uint dim = rng_dim_bounce(push.depth, RNG_SLOT_EMITTER);
    if (integrator == INTEGRATOR_AO) {
        vec3 wi;
        vec2 u = sample_2d(path.pixel, path.sample_index, dim);
        float weight = ao_sample(s.ns, s.ng, u, frame.ao_uniform != 0u, wi);
        if (weight > 0.0) {
            queue_push_shadow(surface_spawn_origin(s, s.ng), r.path, wi, frame.ao_max_t, path.throughput * weight);
        }
    } else if (integrator == INTEGRATOR_SIMPLE) {
        // One point light chosen uniformly (they come first among the emitters):
        // L = (ρ/π) I cos θ / d² / P(light).
        uint count = frame.point_light_count;
        if (count == 0u) return;
        float u = sample_1d(path.pixel, path.sample_index, dim);
        EmitterRecord light = emitter_load(min(floor_to_uint(u * float(count)), count - 1u));
        vec3 to_light = light.position - s.p;
        float d2 = dot(to_light, to_light);
        vec3 wi = to_light * inversesqrt(d2);
        float cos_theta = dot(s.ns, wi);
        if (cos_theta <= 0.0 || dot(s.ng, wi) <= 0.0 || !(d2 > 0.0)) return;
        vec3 f = bsdf_textured(bsdf_load(shape_load(s.shape).bsdf), s.uv).reflectance * INV_PI;
        vec3 origin = surface_spawn_origin(s, s.ng);
        queue_push_shadow(origin, r.path, wi, length(light.position - origin) * (1.0 - 1e-5),
                          path.throughput * f * light.radiance * (cos_theta / d2) * float(count));
    }
}

#endif
