// Photon emission: a ray leaving an emitter and the flux it carries (pbrt-v4's
// Light::SampleLe; Pharr, Jakob, Humphreys, PBR 4th ed., sec. 12.x), as
// power = L |cos θ| / (P(emitter) p(position) p(direction)) for one photon path.
// Needs wavefront.glsl, scene_bindings.glsl, emitter.glsl, bindings.glsl.
#ifndef PHOTON_EMIT_GLSL
#define PHOTON_EMIT_GLSL

#include "emitter/projector.glsl"
#include "emitter/directionalarea.glsl"
#include "numeric/convert.glsl"

struct PhotonEmission {
    vec3 origin;
    vec3 dir;
    vec3 power; // zero: no photon
};

// A projector's photon through image point uv (uniform over the image: density 1 per
// unit uv, 1 / (A cos³ θ) per unit solid angle), with power π scale irradiance(uv) A.
PhotonEmission photon_emit_projector(EmitterRecord e, vec2 uv) {
    PhotonEmission em;
    vec3 l = emitter_projector_direction(uv, vec2(e.cutoff, e.inv_transition));
    mat3 to_local = transpose(mat3(e.to_world_x.xyz, e.to_world_y.xyz, e.to_world_z.xyz));
    em.origin = e.position;
    em.dir = normalize(inverse(to_local) * l);
    em.power = e.radiance * e.area;
    if (TEXTURE_USES(TEXTURE_FEATURE_EMITTER_PROFILE) && e.texture != 0u) em.power *= texture_eval(e.texture, uv);
    return em;
}

// Samples a photon path's first ray. The emitter is chosen uniformly with
// `uniform_choice` (Nori's Scene::getRandomEmitter, the photonmapper) or by power
// through its own alias table at frame.photon_alias (sppm, as pbrt-v4's power light
// sampler); u0, u1: eight uniform numbers.
PhotonEmission photon_emit_sample(bool uniform_choice, vec4 u0, vec4 u1) {
    PhotonEmission em;
    em.origin = vec3(0.0);
    em.dir = vec3(0.0, 0.0, 1.0);
    em.power = vec3(0.0);
    uint n = frame.emitter_count;
    if (n == 0u) return em;
    uint index;
    float pmf;
    if (uniform_choice) {
        index = min(floor_to_uint(u0.x * float(n)), n - 1u);
        pmf = 1.0 / float(n);
    } else {
        index = alias_sample(frame.photon_alias, n, u0.x, pmf);
    }
    EmitterRecord e = emitter_load(index);
    if ((EMITTER_HAS(EMITTER_POINT) && e.kind == EMITTER_POINT)
        || (EMITTER_HAS(EMITTER_SPOT) && e.kind == EMITTER_SPOT)) {
        em.origin = e.position;
        if (EMITTER_HAS(EMITTER_SPOT) && e.kind == EMITTER_SPOT) {
            // Uniform in the cone of the cutoff angle, weighted by the falloff.
            float one_minus_cos = 1.0 - e.cos_cutoff;
            em.dir = frame_to_world(e.axis, warp_uniform_cone(u0.yz, one_minus_cos));
            em.power = emitter_spot_intensity(e, em.dir) / (warp_uniform_cone_pdf(one_minus_cos) * pmf);
        } else {
            // Intensity I in every direction: flux 4π I.
            em.dir = warp_uniform_sphere(u0.yz);
            em.power = e.radiance * (4.0 * PI / pmf);
        }
    } else if (EMITTER_HAS(EMITTER_DIRECTIONAL) && e.kind == EMITTER_DIRECTIONAL) {
        // From a disk of the scene's bounding-sphere radius R facing the light, behind
        // the scene: flux E π R² (Mitsuba's directional sample_ray).
        float R = photon_params.scene_radius;
        vec3 s, t;
        frame_basis(e.axis, s, t);
        vec2 disk = warp_square_to_disk(u0.yz) * R;
        em.origin = photon_params.scene_center - R * e.axis + disk.x * s + disk.y * t;
        em.dir = e.axis;
        em.power = e.radiance * (PI * R * R / pmf);
    } else if (EMITTER_HAS(EMITTER_PROJECTOR) && e.kind == EMITTER_PROJECTOR) {
        // Through a uniform point of the image rectangle (area A) at z = 1: power
        // π scale irradiance(uv) A (emitter::projector; Mitsuba's sample_ray draws uv
        // by the texture, with the same mean).
        PhotonEmission p = photon_emit_projector(e, u0.yz);
        em.origin = p.origin;
        em.dir = p.dir;
        em.power = p.power / pmf;
    } else if ((EMITTER_HAS(EMITTER_CONSTANT) && e.kind == EMITTER_CONSTANT)
               || (EMITTER_HAS(EMITTER_ENVMAP) && e.kind == EMITTER_ENVMAP)) {
        // Light from infinity along -d crosses a disk of the scene's bounding-sphere
        // radius R facing d, placed tangent to that sphere on the side of d: flux
        // L(d) π R² per unit solid angle of d (PBR 4th ed., sec. 12.5, infinite lights'
        // SampleLe).
        vec3 d;
        float pdf_dir;
        if (EMITTER_HAS(EMITTER_ENVMAP) && e.kind == EMITTER_ENVMAP) {
            if (!TEXTURE_USES(TEXTURE_FEATURE_ENVMAP)) return em;
            d = envmap_sample(e, u0.yz, pdf_dir);
        } else {
            d = warp_uniform_sphere(u0.yz);
            pdf_dir = warp_uniform_sphere_pdf(d);
        }
        if (!(pdf_dir > 0.0)) return em;
        float R = photon_params.scene_radius;
        vec3 s, t;
        frame_basis(d, s, t);
        vec2 disk = warp_square_to_disk(u1.xy) * R;
        em.origin = photon_params.scene_center + R * d + disk.x * s + disk.y * t;
        em.dir = -d;
        em.power = emitter_env_radiance(e, d) * (PI * R * R / (pdf_dir * pmf));
    } else if (EMITTER_HAS(EMITTER_DIRECTIONAL_AREA) && e.kind == EMITTER_DIRECTIONAL_AREA) {
        // A uniform point of the shape (density 1/A), along the normal there: power
        // radiance A / P(emitter) (Mitsuba's directionalarea sample_ray).
        DirectionalAreaRay r = emitter_directionalarea_ray(e, u0.yz);
        em.dir = r.dir;
        em.origin = r.origin;
        em.power = r.weight / pmf;
    } else if (EMITTER_HAS_ANY(EMITTER_AREA_BITS) && e.kind == EMITTER_AREA) {
        // A point uniform over the shape (density 1/A; emitter_area_point) and a
        // cosine-weighted direction around its normal (density cos θ / π):
        // power = L π A / P(emitter).
        Surface ls = emitter_area_point(e, u0.yz);
        em.dir = frame_to_world(ls.ng, warp_cosine_hemisphere(u1.xy));
        em.origin = surface_spawn_origin(ls, ls.ng);
        em.power = emitter_area_radiance(e, ls.ng, -em.dir, ls.uv) * (PI * e.area / pmf);
    }
    return em;
}

#endif
