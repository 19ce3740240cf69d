// Visible points: where the camera paths of the photon mappers end, and what the
// photon density estimate there needs. Needs scatter.glsl.
#ifndef PHOTON_VISIBLE_POINT_GLSL
#define PHOTON_VISIBLE_POINT_GLSL

// The visible point of a camera path with throughput beta that reached surface x
// from direction wo (world, towards the camera).
VisiblePoint visible_point_at(ScatterSurface x, vec3 wo, vec3 beta) {
    VisiblePoint v;
    v.p = x.s.p;
    v.bsdf = x.bsdf_index;
    v.wo = wo;
    v.u = x.s.uv.x;
    v.n = x.s.ns;
    v.v = x.s.uv.y;
    v.beta = beta;
    v.alpha2 = x.mapped ? x.nm.alpha2 : 0.0;
    v.n0 = x.mapped ? x.nm.n0 : x.s.ns;
    v.flags = x.mapped ? VISIBLE_POINT_NORMAL_MAP : 0u;
    return v;
}

// Whether an SPPM camera path makes its visible point at a surface with BSDF b: where
// the BSDF has a diffuse part, or at the last vertex (`last`) where it is at least
// glossy, as pbrt-v4's SPPMIntegrator does (elsewhere the path goes on by sampling,
// so a glossy reflection shows the visible points it reflects, sharp, rather than a
// blur of photons).
bool sppm_visible_point_here(BsdfRecord b, bool last) {
    if (bsdf_is_delta(b)) return false;
    bool diffuse = (bsdf_lobes(b) & BSDF_LOBE_DIFFUSE) != 0u;
    return diffuse || last;
}

#endif
