// The local geometry at a ray hit. Needs scene_bindings.glsl.
#ifndef SURFACE_GLSL
#define SURFACE_GLSL

#include "warp.glsl"

struct Surface {
    vec3 p;       // position, interpolated on the primitive (not o + t d)
    vec3 ng;      // geometric normal, unit
    vec3 ns;      // shading normal, unit, same hemisphere as ng
    vec2 uv;
    uint shape;
};

// Surface at barycentrics (u, v) of primitive `prim`: p = (1-u-v) p0 + u p1 + v p2.
// Spheres are re-projected onto their surface. Normals follow the primitive's
// orientation (counter-clockwise front, or outwards), flipped by SHAPE_FLIP_NORMALS.
Surface surface_at(uint prim_index, float u, float v, vec3 ray_o, vec3 ray_d, float t) {
    Prim prim = prims[prim_index];
    ShapeRecord shape = shapes[prim.shape];
    Surface s;
    s.shape = prim.shape;
    if (prim.kind == PRIM_SPHERE) {
        vec3 local = ray_o + t * ray_d - prim.p0;
        s.ng = normalize(local);
        s.p = prim.p0 + prim.p1.x * s.ng;
        s.ns = s.ng;
        // Spherical coordinates as Mitsuba's sphere: u = φ / 2π, v = θ / π.
        s.uv = vec2(atan(s.ng.y, s.ng.x) * (0.5 * INV_PI) + 0.5, acos(clamp(s.ng.z, -1.0, 1.0)) * INV_PI);
    } else {
        float w = 1.0 - u - v;
        s.p = w * prim.p0 + u * prim.p1 + v * prim.p2;
        vec3 n = cross(prim.p1 - prim.p0, prim.p2 - prim.p0);
        float len = length(n);
        // Degenerate triangles are dropped at load time; guard anyway.
        s.ng = len > 0.0 ? n / len : vec3(0.0, 0.0, 1.0);
        s.ns = s.ng;
        s.uv = vec2(u, v);
        if ((shape.flags & (SHAPE_HAS_NORMALS | SHAPE_HAS_UVS)) != 0u) {
            TriangleRecord tri = triangles[prim.index];
            Vertex a = vertices[tri.v0], b = vertices[tri.v1], c = vertices[tri.v2];
            if ((shape.flags & SHAPE_HAS_NORMALS) != 0u) {
                vec3 ns = w * vec3(a.nx, a.ny, a.nz) + u * vec3(b.nx, b.ny, b.nz) + v * vec3(c.nx, c.ny, c.nz);
                float l = length(ns);
                if (l > 0.0) s.ns = ns / l;
                // Keep the shading normal on the side of the geometric one.
                if (dot(s.ns, s.ng) < 0.0) s.ng = -s.ng;
            }
            if ((shape.flags & SHAPE_HAS_UVS) != 0u) {
                s.uv = w * vec2(a.u, a.v) + u * vec2(b.u, b.v) + v * vec2(c.u, c.v);
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

#endif
