// The surface where a path of the photon mappers (a photon path, or a camera path
// before its visible point) meets the scene: its geometry, its textured BSDF and the
// frame of its normal map, as path.glsl finds them for the path tracers. Needs
// scene_bindings.glsl, surface.glsl, texture.glsl, bsdf.glsl, bsdf_textured.glsl.
#ifndef PHOTON_SCATTER_GLSL
#define PHOTON_SCATTER_GLSL

#include "sampling/frame.glsl"
#include "bsdf/normal_map.glsl"
#include "bsdf/composite.glsl"
#include "sampling/rng.glsl"

struct ScatterSurface {
    Surface s;         // s.ns replaced by the normal map's normal where there is one
    uint emitter;      // the shape's emitter, or NONE
    uint bsdf_index;
    BsdfRecord bsdf;   // textured at s.uv; BSDF_TWOSIDED cleared under a normal map
    bool mapped;       // a normal map applies (nm)
    bool composite;    // the shape's BSDF is a composite, resolved to bsdf here
    NormalMapFrame nm;
};

// The surface of hit h of ray r (h.prim != NONE). A composite BSDF resolves to one
// model as in path_shade (composite.glsl), by a number hashed from the ray and the
// hit (these kernels draw their lobe numbers after this): a mask's pass-through is
// then a delta transmission the path goes on through. A visible point keeps the
// leaf's record index, without what a twosided node or a bump map added.
ScatterSurface scatter_surface_u(RayItem r, HitItem h, float u_lobe);

ScatterSurface scatter_surface(RayItem r, HitItem h) {
    uvec4 k = rng_pcg4d(uvec4(floatBitsToUint(r.dir.x) ^ r.path, floatBitsToUint(r.dir.y),
                              floatBitsToUint(r.dir.z), h.prim ^ floatBitsToUint(h.t)));
    return scatter_surface_u(r, h, rng_to_float(k.x));
}

// scatter_surface with the number u_lobe resolving a composite (a camera path's lobe
// number, as path_shade drew it for the same vertex).
ScatterSurface scatter_surface_u(RayItem r, HitItem h, float u_lobe) {
    ScatterSurface x;
    x.s = surface_at(h.prim, h.u, h.v, r.origin, r.dir, h.t);
    ShapeRecord shape = shape_load(x.s.shape);
    x.emitter = shape.emitter;
    x.bsdf_index = shape.bsdf;
    uint leaf_flags = 0u;
    x.mapped = false;
    x.composite = false;
    if (BSDF_HAS(BSDF_COMPOSITE)) {
        CompositeLeaf leaf = bsdf_composite_resolve(shape.bsdf, x.s, h.prim, vec2(h.u, h.v), -r.dir, u_lobe);
        x.bsdf_index = leaf.index;
        leaf_flags = leaf.flags;
        x.mapped = leaf.bumped;
        x.nm = leaf.nm;
        x.composite = leaf.index != shape.bsdf;
    }
    x.bsdf = bsdf_textured(bsdf_load(x.bsdf_index), x.s.uv);
    x.bsdf.flags |= leaf_flags;
    // As path_shade: the mapped normal shades, and the nested model is one-sided.
    if (TEXTURE_USES(TEXTURE_FEATURE_NORMALMAP) && x.bsdf.normal_map != 0u) {
        x.mapped = true;
        x.nm = normal_map_frame(x.bsdf, x.s, -r.dir);
        x.s.ns = x.nm.n;
        // Mitsuba's perturbed frame keeps the old tangent, made orthogonal to n.
        x.s.ss = surface_tangent(x.s.ss, x.s.ns);
        x.bsdf.flags &= ~BSDF_TWOSIDED;
    }
    return x;
}

// Samples the surface's BSDF from wo_world (world, away from the surface, where the
// path came from): the next direction wi (world) and its weight f |cos θi| / pdf,
// times the normal map's factor. With `importance` (photon paths) refraction keeps
// the flux a photon carries instead of scaling it by (η_i/η_t)² as radiance is (the
// adjoint BSDF; Veach 1997, thesis, sec. 5.2). `eta_scale` is multiplied by the
// factor refraction scaled radiance by, undone (Russian roulette of camera paths).
struct ScatterSample {
    vec3 wi;
    vec3 weight;
    float pdf;
    uint flags; // BSDF_FLAG_*; 0: none
};

ScatterSample scatter_sample(ScatterSurface x, vec3 wo_world, vec3 u, bool importance, inout float eta_scale) {
    // The shading frame (ss, ns × ss, ns), as path.glsl: Mitsuba's sh_frame.
    vec3 wo = surface_to_local(x.s, wo_world);
    BsdfSample bs = bsdf_sample(x.bsdf, wo, u, x.s.uv);
    ScatterSample ss;
    ss.wi = surface_to_world(x.s, bs.wi);
    ss.weight = bs.weight * (x.mapped ? normal_map_weight(x.nm, ss.wi) : 1.0);
    ss.pdf = bs.pdf;
    ss.flags = bs.flags;
    if ((bs.flags & (BSDF_FLAG_TRANSMISSION | BSDF_FLAG_NULL)) == BSDF_FLAG_TRANSMISSION) {
        float eta2 = x.bsdf.eta * x.bsdf.eta;
        float undo = wo.z > 0.0 ? eta2 : 1.0 / eta2;
        eta_scale *= undo;
        if (importance) ss.weight *= undo;
    }
    return ss;
}

// Origin of a ray leaving the surface along wi.
vec3 scatter_origin(ScatterSurface x, vec3 wi) {
    return surface_spawn_origin(x.s, dot(wi, x.s.ng) > 0.0 ? x.s.ng : -x.s.ng);
}

#endif
