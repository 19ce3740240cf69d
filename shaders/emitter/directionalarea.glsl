// Mitsuba's directionalarea light paths (its sample_ray; emitter::directionalarea):
// a point of the shape from emitter_area_point (uniform over the shape: a mesh's
// triangle by area through its alias table, then a uniform point of it), leaving along
// the geometric normal there, with weight radiance / p(point). p is
// emitter_directionalarea_pdf, per unit area of the shape in world space: the weight
// divides by it, and `wavetrace warptest directionalarea` tests the points against it.
// Needs emitter.glsl (emitter_area_point) and surface.glsl.
#ifndef EMITTER_DIRECTIONALAREA_GLSL
#define EMITTER_DIRECTIONALAREA_GLSL

struct DirectionalAreaRay {
    vec3 point;  // on the shape
    vec3 origin; // point, offset off the surface along the normal
    vec3 dir;    // the geometric normal at point
    vec3 weight; // radiance / p(point)
};

// The density per unit area of emitter_area_point's points on e's shape: uniform, 1 /
// area (the record's world-space area, summed over a mesh's triangles by the host).
float emitter_directionalarea_pdf(EmitterRecord e) { return 1.0 / e.area; }

DirectionalAreaRay emitter_directionalarea_ray(EmitterRecord e, vec2 u) {
    Surface ls = emitter_area_point(e, u);
    DirectionalAreaRay r;
    r.point = ls.p;
    r.dir = ls.ng;
    r.origin = surface_spawn_origin(ls, ls.ng);
    r.weight = e.radiance / emitter_directionalarea_pdf(e);
    return r;
}

#endif
