// The local geometry at a ray hit. Needs scene_bindings.glsl.
#ifndef SURFACE_GLSL
#define SURFACE_GLSL

#include "warp.glsl"
#include "ray_offset.glsl"

// The primitive and vertex features of the scene (SURFACE_FEATURE_* bits of
// layout.glsl); a kernel may define it as a specialization constant so that the code
// of absent ones compiles away (llvmpipe runs a branch's code whatever its lanes
// decide: without this, every hit paid the sphere's trigonometry and ten fetches of
// vertex normals and uvs).
#ifndef SURFACE_FEATURES
#define SURFACE_FEATURES 0xffffffffu
#endif
#define SURFACE_HAS(f) ((SURFACE_FEATURES & (f)) != 0u)

// γ(n) = n ε / (1 - n ε) with ε = 2^-24 (PBR 4th ed., sec. 6.8.1), rounded up.
#define SURFACE_GAMMA5 2.9802326e-7
#define SURFACE_GAMMA7 4.1723283e-7

struct Surface {
    vec3 p;       // position, interpolated on the primitive (not o + t d)
    vec3 p_error; // bound on the absolute rounding error of p, per axis
    vec3 ng;      // geometric normal, unit
    vec3 ns;      // shading normal, unit, same hemisphere as ng
    vec2 uv;
    uint shape;
    vec3 dpdu;    // tangent ∂p/∂u (unnormalized direction); zero where unknown
};

// Mitsuba's sphere coordinates of the outward unit normal n (object frame = world
// here): u = φ / 2π in [0, 1), v = θ / π.
vec2 surface_sphere_uv(vec3 n) {
    float u = atan(n.y, n.x) * (0.5 * INV_PI);
    if (u < 0.0) u += 1.0;
    return vec2(u, acos(clamp(n.z, -1.0, 1.0)) * INV_PI);
}

// Surface at barycentrics (u, v) of primitive `prim`: p = (1-u-v) p0 + u p1 + v p2.
// Spheres are re-projected onto their surface. Normals follow the primitive's
// orientation (counter-clockwise front, or outwards), flipped by SHAPE_FLIP_NORMALS.
Surface surface_at(uint prim_index, float u, float v, vec3 ray_o, vec3 ray_d, float t) {
    Prim prim = prim_load(prim_index);
    ShapeRecord shape = shape_load(prim.shape);
    Surface s;
    s.shape = prim.shape;
    if (SURFACE_HAS(SURFACE_FEATURE_SPHERES) && prim.kind == PRIM_SPHERE) {
        vec3 local = ray_o + t * ray_d - prim.p0;
        s.ng = normalize(local);
        s.p = prim.p0 + prim.p1.x * s.ng;
        s.p_error = SURFACE_GAMMA5 * abs(s.p);
        s.ns = s.ng;
        s.uv = surface_sphere_uv(s.ng);
        s.dpdu = vec3(-s.ng.y, s.ng.x, 0.0); // ∂p/∂φ direction
    } else {
        float w = 1.0 - u - v;
        s.p = w * prim.p0 + u * prim.p1 + v * prim.p2;
        // Pharr, Jakob, Humphreys, PBR 4th ed., sec. 6.8.5: error of barycentric
        // interpolation. It also bounds how far a re-intersection test against this
        // triangle (whose arithmetic works at the scale of its vertices) can err.
        s.p_error = SURFACE_GAMMA7 * (abs(w * prim.p0) + abs(u * prim.p1) + abs(v * prim.p2));
        vec3 n = cross(prim.p1 - prim.p0, prim.p2 - prim.p0);
        float len = length(n);
        // Degenerate triangles are dropped at load time; guard anyway.
        s.ng = len > 0.0 ? n / len : vec3(0.0, 0.0, 1.0);
        s.ns = s.ng;
        s.uv = vec2(u, v);
        s.dpdu = vec3(0.0);
        if (SURFACE_HAS(SURFACE_FEATURE_NORMALS | SURFACE_FEATURE_UVS)
            && (shape.flags & (SHAPE_HAS_NORMALS | SHAPE_HAS_UVS)) != 0u) {
            TriangleRecord tri = triangle_load(prim.index);
            // Each half of a vertex is fetched only where it is used (vertex_texel).
            if (SURFACE_HAS(SURFACE_FEATURE_NORMALS) && (shape.flags & SHAPE_HAS_NORMALS) != 0u) {
                vec3 ns = w * vertex_texel(tri.v0, 0u).xyz + u * vertex_texel(tri.v1, 0u).xyz
                    + v * vertex_texel(tri.v2, 0u).xyz;
                float l = length(ns);
                if (l > 0.0) s.ns = ns / l;
                // Keep the shading normal on the side of the geometric one.
                if (dot(s.ns, s.ng) < 0.0) s.ng = -s.ng;
            }
            if (SURFACE_HAS(SURFACE_FEATURE_UVS) && (shape.flags & SHAPE_HAS_UVS) != 0u) {
                Vertex a = vertex_load(tri.v0), b = vertex_load(tri.v1), c = vertex_load(tri.v2);
                s.uv = w * vec2(a.u, a.v) + u * vec2(b.u, b.v) + v * vec2(c.u, c.v);
                s.dpdu = w * vec3(a.tx, a.ty, a.tz) + u * vec3(b.tx, b.ty, b.tz) + v * vec3(c.tx, c.ty, c.tz);
            }
        }
    }
    if ((shape.flags & SHAPE_FLIP_NORMALS) != 0u) {
        s.ng = -s.ng;
        s.ns = -s.ns;
    }
    return s;
}

// Turns both normals to face direction w (usually towards the viewer), keeping their
// relative orientation: for two-sided shading of one-sided geometry.
void surface_face(inout Surface s, vec3 w) {
    if (dot(s.ng, w) < 0.0) {
        s.ng = -s.ng;
        s.ns = -s.ns;
    }
}

// Origin for a ray leaving surface s on the side of normal n (n = s.ng or -s.ng):
// pushed past the error bounds of p along n (PBR 4th ed., sec. 6.8.6), then by a few
// ulps (Wächter and Binder 2019) so that rounding cannot bring it back.
vec3 surface_spawn_origin(Surface s, vec3 n) {
    float d = dot(abs(n), s.p_error);
    return ray_offset(s.p + d * n, n);
}

#endif
