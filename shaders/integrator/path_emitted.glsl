// The last bounce of a path integrator against the emitters alone, where the scene has
// few emitter primitives (EMITTER_PRIMS > 0, a constant defined before including this
// file: how many of frame.emitter_prims there are), no environment and no media.
//
// A ray of a bounce whose vertices end their paths (depth + 2 > max_depth, shade.comp's
// SHADE_LAST) is only traced for the emission it finds. Instead of a closest hit
// through the whole BVH and then shading it, this finds the closest emitter primitive
// along the ray (a loop over a few primitives, much cheaper than a traversal on
// llvmpipe), weighs its emission as path_shade_to does (path_emission_found), and
// sends it as a shadow ray that the `shadow` kernel adds if nothing blocks the way
// there. A ray
// that finds no emitter costs no traversal at all. (With an environment every such
// ray would need a shadow ray to infinity: callgrind on scenes/textures/normalmap.xml
// +5% instructions, so the renderer keeps intersect and shade there.) The estimate
// is the one of path_shade_to; only a surface within the shadow epsilon (1e-4 of the
// distance) in front of an emitter no longer blocks it, as for emitter sampling.
// Needs path.glsl (and what it needs), bvh.glsl, texture.glsl.
#ifndef PATH_EMITTED_GLSL
#define PATH_EMITTED_GLSL

#ifndef EMITTER_PRIMS
#define EMITTER_PRIMS 0u
#endif
// The kinds of those primitives (BVH_KIND_BIT of each, a constant likewise): the
// others' tests compile away.
#ifndef EMITTER_PRIM_KINDS
#define EMITTER_PRIM_KINDS BVH_KINDS
#endif

// The emitted light that ray r (of `path`, at bounce PATH_DEPTH >= 1) finds, as a
// shadow ray.
void path_shade_emitted(uint integrator, RayItem r, PathState path) {
    // Emission counts after BSDF sampling (not for direct_ems, which has none).
    if (integrator == INTEGRATOR_DIRECT_EMS) return;
    bool weigh = integrator_uses_mis(integrator) && (path.flags & PATH_DELTA) == 0u;

    // Closest emitter primitive, with the tests and the order of arguments of the
    // BVH's leaves (bvh_prim_hit_of): the same distance and (u, v) as a traversal
    // finds.
    TriangleRay tr = triangle_ray_make(r.dir);
    Hit h = Hit(r.tmax, 0.0, 0.0, HIT_NONE);
    for (uint k = 0u; k < EMITTER_PRIMS; k++) {
        uint slot = frame.emitter_prims[k >> 2u][k & 3u];
        float t, u, v;
        if (bvh_prim_hit_of(EMITTER_PRIM_KINDS, prim_load(slot), tr, r.origin, r.dir, 0.0, h.t, t, u, v)) {
            h = Hit(t, u, v, slot);
        }
    }

    vec3 contribution = vec3(0.0);
    float tmax = 0.0;
    if (h.prim != HIT_NONE) {
        Surface s = surface_at(h.prim, h.u, h.v, r.origin, r.dir, h.t);
        ShapeRecord shape = shape_load(s.shape);
        EmitterRecord light = emitter_load(shape.emitter);
        vec3 texel = vec3(0.0);
        if (TEXTURE_USES(TEXTURE_FEATURE_AREA) && light.texture != 0u) {
            texel = texture_eval(light.texture, s.uv);
        }
        contribution = path_emission_found(path, r, h.t, s, shape.emitter, light, texel, weigh);
        // Stop short of the emitter's own surface (PBR's shadow epsilon).
        tmax = h.t * (1.0 - 1e-4);
    }
    if (any(greaterThan(contribution, vec3(0.0)))) {
        path_push_shadow(NONE, r.origin, r.path, r.dir, tmax, contribution);
    }
}

#endif
