// The photon density estimate at a visible point (Jensen 1996; Hachisuka and Jensen
// 2009, eq. 5 without the 1 / (π r² N)): over the grid photons within radius r of the
// point, Σ f(wo, wi_p) Φ_p, f the BSDF without the cosine (the photons' flux already
// holds it), and how many photons took part. A photon that arrives from the other
// side of the surface than the camera sees it from is skipped (unless the BSDF
// transmits): it lit the back of a thin wall, not this side. Needs scene_bindings.glsl,
// texture.glsl, bsdf.glsl, bsdf_textured.glsl, normal_map.glsl, bindings.glsl,
// record.glsl, grid.glsl.
#ifndef PHOTON_DENSITY_GLSL
#define PHOTON_DENSITY_GLSL

#include "sampling/frame.glsl"

struct PhotonGather {
    vec3 sum;   // Σ f(wo, wi_p) Φ_p
    uint count; // photons within the radius on the side seen
};

PhotonGather photon_gather(VisiblePoint v, float r) {
    PhotonGather g = PhotonGather(vec3(0.0), 0u);
    vec2 uv = vec2(v.u, v.v);
    BsdfRecord b = bsdf_textured(bsdf_load(v.bsdf), uv);
    bool mapped = (v.flags & VISIBLE_POINT_NORMAL_MAP) != 0u;
    if (mapped) b.flags &= ~BSDF_TWOSIDED;
    NormalMapFrame nm = NormalMapFrame(v.n0, v.n, v.alpha2);
    bool transmits = (bsdf_lobes(b) & BSDF_LOBE_TRANSMISSION) != 0u;
    vec3 bx, by;
    frame_basis(v.n, bx, by);
    vec3 wo = vec3(dot(v.wo, bx), dot(v.wo, by), dot(v.wo, v.n));
    float r2 = r * r;
    uint buckets[GRID_MAX_BUCKETS];
    uint n = grid_buckets_near(v.p, r, buckets);
    for (uint k = 0u; k < n; k++) {
        uvec2 range = grid_bucket_range(buckets[k]);
        for (uint j = range.x; j < range.y; j++) {
            Photon p = grid_photon_load(j);
            if (!photon_in_radius(p, v.p, r2)) continue;
            vec3 wi_world = photon_dir_decode(p.wi);
            vec3 wi = vec3(dot(wi_world, bx), dot(wi_world, by), dot(wi_world, v.n));
            if (!transmits && !(wi.z * wo.z > 0.0)) continue;
            if (wi.z == 0.0) continue;
            vec3 f = bsdf_eval(b, wo, wi, uv) / abs(wi.z);
            if (mapped) f *= normal_map_weight(nm, wi_world);
            g.sum += f * p.power;
            g.count += 1u;
        }
    }
    return g;
}

#endif
