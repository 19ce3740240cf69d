// The local geometry at a ray hit. Needs scene_bindings.glsl.
#ifndef SURFACE_GLSL
#define SURFACE_GLSL

#include "sampling/warp.glsl"
#include "sampling/frame.glsl"
#include "shape/ray_offset.glsl"
#include "accel/instance.glsl"
#include "shape/intersect_sdfgrid.glsl"
#include "shape/intersect_bspline.glsl"
#include "shape/intersect_ellipsoid.glsl"
#include "texture/texture_hit.glsl"

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
    vec3 ss;      // shading tangent, unit, orthogonal to ns: Mitsuba's sh_frame.s, ∂p/∂u
                  // made orthogonal to ns; the shading frame is (ss, ns × ss, ns)
};

#ifdef SURFACE_PARTIALS
// Mitsuba's si.dp_du and si.dp_dv of the last surface_at (only for the kernel that
// defines SURFACE_PARTIALS: aov.comp's dp_du, dp_dv, duv_dx and duv_dy AOVs). Zero on
// curves and SDF grids, as Mitsuba leaves them.
vec3 surface_dp_du;
vec3 surface_dp_dv;
#endif

// u = φ / 2π in [0, 1) of the object-space direction (x, y) (Mitsuba's sphere,
// disk and cylinder).
float surface_phi_u(float x, float y) {
    float u = atan(y, x) * (0.5 * INV_PI);
    return u < 0.0 ? u + 1.0 : u;
}

// Mitsuba's shading tangent (SurfaceInteraction::initialize_sh_frame): dpdu made
// orthogonal to n by Gram-Schmidt, unit; where that leaves nothing, the first axis
// of frame_basis(n) (Mitsuba's coordinate_system).
vec3 surface_tangent(vec3 dpdu, vec3 n) {
    vec3 t = dpdu - n * dot(n, dpdu);
    float len = length(t);
    // One return (kernels inlined by gpu::specialize: see medium.glsl).
    vec3 s, b;
    frame_basis(n, s, b);
    return len > 0.0 ? t / len : s;
}

// The geometry of quadric `prim` (layout.glsl) at the hit point `hit`; `xy`: a
// disk's object-space (x, y) from intersect_disk. As Mitsuba 3.9's sphere, disk and
// cylinder compute it: uv and ∂p/∂u from the object-space point, outward normals
// (a disk's: the inverse transpose of +z; both fixed up by SHAPE_FLIP_NORMALS after).
void surface_quadric(inout Surface s, Prim prim, ShapeRecord shape, vec3 hit, vec2 xy, out vec3 dpdu) {
    float mirror = (shape.flags & SHAPE_MIRRORED) != 0u ? -1.0 : 1.0;
    if (SURFACE_HAS(SURFACE_FEATURE_SPHERES) && prim.kind == PRIM_SPHERE) {
        float r = length(prim.p1);
        vec3 a3 = mirror * cross(prim.p1, prim.p2) / r;
        s.ng = normalize(hit - prim.p0);
        s.p = prim.p0 + r * s.ng; // re-projected onto the sphere, as Mitsuba does
        s.p_error = SURFACE_GAMMA5 * abs(s.p);
        // The unit object-space point; uv = (φ / 2π, θ / π).
        vec3 l = vec3(dot(s.ng, prim.p1), dot(s.ng, prim.p2), dot(s.ng, a3)) / r;
        // θ by atan2: llvmpipe's acos is off by up to 1.5e-4 rad.
        s.uv = vec2(surface_phi_u(l.x, l.y), atan(length(l.xy), l.z) * INV_PI);
        dpdu = 2.0 * PI * (l.x * prim.p2 - l.y * prim.p1);
#ifdef SURFACE_PARTIALS
        // π to_world (z cos φ, z sin φ, -sin θ); π to_world x at the poles.
        float rd = length(l.xy);
        surface_dp_dv = rd > 0.0
            ? PI * ((l.z * l.x / rd) * prim.p1 + (l.z * l.y / rd) * prim.p2 - rd * a3)
            : PI * prim.p1;
#endif
    } else if (SURFACE_HAS(SURFACE_FEATURE_DISKS) && prim.kind == PRIM_DISK) {
        s.p = prim.p0 + xy.x * prim.p1 + xy.y * prim.p2;
        s.p_error = SURFACE_GAMMA7 * (abs(prim.p0) + abs(xy.x * prim.p1) + abs(xy.y * prim.p2));
        s.ng = normalize(cross(prim.p1, prim.p2));
        float r = length(xy);
        s.uv = vec2(r, surface_phi_u(xy.x, xy.y));
        dpdu = r > 0.0 ? (xy.x * prim.p1 + xy.y * prim.p2) / r : vec3(0.0);
#ifdef SURFACE_PARTIALS
        // 2π r to_world (-sin φ, cos φ, 0).
        surface_dp_dv = 2.0 * PI * (xy.x * prim.p2 - xy.y * prim.p1);
#endif
    } else {
        // Cylinder: p1 = M x (radius r), p2 = the axis M z, M y = ±(axis/|axis|) × M x.
        float r = length(prim.p1);
        vec3 a2 = mirror * cross(normalize(prim.p2), prim.p1);
        vec3 q = hit - prim.p0;
        float z = dot(q, prim.p2) / dot(prim.p2, prim.p2);
        vec3 radial = q - z * prim.p2;
        float len = length(radial);
        s.ng = len > 0.0 ? radial / len : normalize(prim.p1);
        s.p = prim.p0 + z * prim.p2 + r * s.ng; // onto the tube, as Mitsuba nudges it
        s.p_error = SURFACE_GAMMA7 * (abs(prim.p0) + abs(z * prim.p2) + abs(r * s.ng));
        vec2 l = vec2(dot(s.ng, prim.p1), dot(s.ng, a2)) / r;
        s.uv = vec2(surface_phi_u(l.x, l.y), z);
        dpdu = 2.0 * PI * (l.x * a2 - l.y * prim.p1);
#ifdef SURFACE_PARTIALS
        surface_dp_dv = prim.p2;
#endif
    }
    s.ns = s.ng;
}

// The geometry of linear curve segment `prim` (layout.glsl) at the hit point `hit`,
// `v_local` the parameter of the touching sphere's centre (intersect_curve.glsl), as
// Mitsuba 3.9's linearcurve reports it: the normal from that centre to the hit (the
// point re-projected onto the sphere), u = the angle around the axis / 2π from
// Mitsuba's frame (+z made orthogonal to the axis, or +y where the axis is ±z),
// v = (v_local + the segment's number) / the shape's segment count, and no ∂p/∂u
// (its shading frame is coordinate_system(n)).
void surface_linear_curve(inout Surface s, Prim prim, vec3 hit, float v_local, out vec3 dpdu) {
    vec3 a = prim.p1 - prim.p0;
    vec3 c = prim.p0 + v_local * a;
    float r = mix(prim.p2.x, prim.p2.y, v_local);
    vec3 axis = normalize(a);
    vec3 rot = abs(axis.z) == 1.0 ? vec3(0.0, 1.0, 0.0) : normalize(vec3(0.0, 0.0, 1.0) - axis * axis.z);
    vec3 radial = cross(rot, axis);
    vec3 q = hit - c;
    float len = length(q);
    s.ng = len > 0.0 ? q / len : radial;
    s.p = c + r * s.ng;
    s.p_error = SURFACE_GAMMA7 * (abs(prim.p0) + abs(v_local * a) + abs(r * s.ng));
    s.ns = s.ng;
    s.uv = vec2(surface_phi_u(dot(radial, s.ng), dot(rot, s.ng)),
                (v_local + float(prim.index)) / abs(prim.p2.z));
    dpdu = vec3(0.0);
#ifdef SURFACE_PARTIALS
    surface_dp_dv = vec3(0.0);
#endif
}

// The geometry of B-spline curve segment `prim` (layout.glsl) at the hit point `hit`,
// `u` the segment's parameter there (intersect_bspline.glsl), as Mitsuba 3.9.1's
// bsplinecurve reports it: p = o + t d, the curvature-corrected normal, uv = (the angle
// around the tangent / 2π from Mitsuba's frame (+z made normal to the tangent, or +y
// where the tangent is ±z), (u + the segment's number) / the shape's segment count),
// ∂p/∂u around the curve.
void surface_bspline_curve(inout Surface s, Prim prim, vec3 hit, float u, out vec3 dpdu) {
    vec4 cp[4];
    bspline_points(floatBitsToUint(prim.p2.x), cp);
    vec3 c, dc, ddc;
    float r, dr;
    bspline_eval(cp, u, c, dc, ddc, r, dr);
    vec3 q = hit - c;
    vec3 tangent = normalize(dc);
    vec3 rot = abs(tangent.z) == 1.0 ? vec3(0.0, 1.0, 0.0)
                                     : normalize(vec3(0.0, 0.0, 1.0) - tangent * tangent.z);
    vec3 radial = cross(rot, tangent);
    vec3 n = bspline_normal(q, dc, ddc, r, dr);
    float ln = length(n);
    s.ng = ln > 0.0 ? n / ln : radial;
    s.ns = s.ng;
    s.p = hit;
    // The Newton iteration's residual (1e-4 r, intersect_bspline.glsl) besides rounding.
    s.p_error = 4.0 * SURFACE_GAMMA7 * (abs(hit) + abs(c)) + vec3(1e-4 * abs(r));
    vec3 qn = normalize(q);
    s.uv = vec2(surface_phi_u(dot(radial, qn), dot(rot, qn)), (u + float(prim.index)) / prim.p2.y);
    dpdu = cross(tangent, qn);
}

// Surface at barycentrics (u, v) of primitive `prim`: p = (1-u-v) p0 + u p1 + v p2;
// for a disk (u, v) is the object-space point, for a curve u its segment's parameter,
// and other quadrics and curves take the point
// o + t d and re-project it. Normals follow the primitive's orientation
// (counter-clockwise front, or outwards), flipped by SHAPE_FLIP_NORMALS. The tangent
// is Mitsuba's: a triangle's ∂p/∂u from its own vertices and uvs (p1 - p0 without
// uvs), a quadric's from its parameterization.
// `shading` (a constant): false where only the point, its error bound, the geometric
// normal (on the side of the shading normal, as below) and the shape are read, as a
// null crossing reads them (vol_path.glsl, transmittance.glsl): a triangle's uvs, its
// tangent and its texture lookup's hit are then left out (uv = (u, v), ss = 0), and
// its vertex normals where they cannot turn the geometric normal (SHAPE_NORMALS_AGREE;
// ns = ng); what is read comes out as with them, the same bits.
Surface surface_at_as(uint prim_index, float u, float v, vec3 ray_o, vec3 ray_d, float t, bool shading) {
    // In world space (an instance's primitive mapped by its to_world).
    Prim prim = instance_prim_load(prim_index);
    ShapeRecord shape = shape_load(prim.shape);
    bool sdf = SURFACE_HAS(SURFACE_FEATURE_SDFGRIDS) && prim.kind == PRIM_SDFGRID;
    if (shading) texture_hit_set(prim.shape, prim.index, sdf ? vec2(0.0) : vec2(u, v));
    Surface s;
    s.shape = prim.shape;
    vec3 dpdu;
#ifdef SURFACE_PARTIALS
    surface_dp_dv = vec3(0.0);
#endif
    if (sdf) {
        // In the group's space (the record as stored), u the voxel hit; no uv, no
        // ∂p/∂u (Mitsuba's sdfgrid: the frame is the normal's coordinate system).
        vec3 o = ray_o, d = ray_d;
        uint k1 = instance_of(prim_index);
        if (INSTANCED && k1 != 0u) {
            InstanceMap m = instance_to_object(k1 - 1u);
            o = instance_point(m, ray_o);
            d = instance_vector(m, ray_d);
        }
        vec3 ng, ns;
        sdf_surface(prim_load(instance_prim(prim_index)), o + t * d, u, ng, ns);
        s.ng = normalize(instance_normal(prim_index, ng));
        s.ns = normalize(instance_normal(prim_index, ns));
        s.p = ray_o + t * ray_d;
        // The root is found to SDF_SOLVE_EPSILON in t (Mitsuba adds |n.d| of it).
        s.p_error = 4.0 * SURFACE_GAMMA7 * abs(s.p)
            + vec3(4.0 * SDF_SOLVE_EPSILON * abs(dot(s.ng, ray_d)));
        s.uv = vec2(0.0);
        dpdu = vec3(0.0);
#ifdef SURFACE_PARTIALS
        surface_dp_dv = vec3(0.0);
#endif
    } else if (SURFACE_HAS(SURFACE_FEATURE_LINEAR_CURVES) && prim.kind == PRIM_LINEAR_CURVE) {
        surface_linear_curve(s, prim, ray_o + t * ray_d, u, dpdu);
    } else if (SURFACE_HAS(SURFACE_FEATURE_BSPLINE_CURVES) && prim.kind == PRIM_BSPLINE_CURVE) {
        surface_bspline_curve(s, prim, ray_o + t * ray_d, u, dpdu);
    } else if (SURFACE_HAS(SURFACE_FEATURE_ELLIPSOIDS) && prim.kind == PRIM_ELLIPSOID) {
        // Mitsuba's ellipsoids: the normal, uv = 0, no ∂p/∂u (the frame is the
        // normal's); p rounds as the unit-sphere root mapped back (the box's size).
        s.p = ray_o + t * ray_d;
        s.ng = ellipsoid_normal(floatBitsToUint(prim.p2.x), s.p);
        s.ns = s.ng;
        s.p_error = 8.0 * SURFACE_GAMMA7 * (abs(s.p) + 0.5 * (prim.p1 - prim.p0));
        s.uv = vec2(0.0);
        dpdu = vec3(0.0);
    } else if (SURFACE_HAS(SURFACE_FEATURE_SPHERES | SURFACE_FEATURE_DISKS | SURFACE_FEATURE_CYLINDERS)
        && prim.kind != PRIM_TRIANGLE) {
        uint k1 = instance_of(prim_index);
        if (INSTANCED && k1 != 0u && prim.kind != PRIM_DISK) {
            // A sphere or cylinder of an instance, in the group's space (the record as
            // stored, the ray mapped there), then to the world as Mitsuba's instance
            // maps its object's interaction: the point and tangents by to_world, the
            // normal by its inverse transpose. An instance that stretches unevenly
            // makes the sphere an ellipsoid (the cylinder elliptic), whose normal is
            // not the mapped record's radial direction.
            InstanceMap m = instance_to_object(k1 - 1u);
            vec3 o = instance_point(m, ray_o), d = instance_vector(m, ray_d);
            surface_quadric(s, prim_load(instance_prim(prim_index)), shape, o + t * d,
                            vec2(u, v), dpdu);
            mat3 to_world = instance_to_world_linear(m);
            s.p = to_world * s.p - to_world * m.b;
            s.p_error = mat3(abs(to_world[0]), abs(to_world[1]), abs(to_world[2])) * s.p_error
                + SURFACE_GAMMA5 * abs(s.p);
            s.ng = normalize(s.ng.x * m.r0 + s.ng.y * m.r1 + s.ng.z * m.r2);
            s.ns = s.ng;
            dpdu = to_world * dpdu;
#ifdef SURFACE_PARTIALS
            surface_dp_dv = to_world * surface_dp_dv;
#endif
        } else {
            surface_quadric(s, prim, shape, ray_o + t * ray_d, vec2(u, v), dpdu);
        }
        if (INSTANCED && prim.kind == PRIM_DISK && instance_mirrors(prim_index)) {
            s.ng = -s.ng;
            s.ns = s.ng;
        }
    } else {
        float w = 1.0 - u - v;
        s.p = w * prim.p0 + u * prim.p1 + v * prim.p2;
        // Pharr, Jakob, Humphreys, PBR 4th ed., sec. 6.8.5: error of barycentric
        // interpolation. It also bounds how far a re-intersection test against this
        // triangle (whose arithmetic works at the scale of its vertices) can err.
        s.p_error = SURFACE_GAMMA7 * (abs(w * prim.p0) + abs(u * prim.p1) + abs(v * prim.p2));
        vec3 dp0 = prim.p1 - prim.p0, dp1 = prim.p2 - prim.p0;
        vec3 n = cross(dp0, dp1);
        float len = length(n);
        // Degenerate triangles are dropped at load time; guard anyway.
        s.ng = len > 0.0 ? n / len : vec3(0.0, 0.0, 1.0);
        if (INSTANCED && instance_mirrors(prim_index)) s.ng = -s.ng;
        s.ns = s.ng;
        s.uv = vec2(u, v);
        // Without uvs the parameterization is barycentric (Mitsuba's mesh.cpp).
        dpdu = dp0;
#ifdef SURFACE_PARTIALS
        surface_dp_dv = dp1;
#endif
        // A crossing (!shading) of a mesh whose vertex normals agree with its faces
        // (SHAPE_NORMALS_AGREE, not instanced) reads no vertex: the geometric normal
        // stays as it is, and ns = ng.
        bool agree = (shape.flags & SHAPE_NORMALS_AGREE) != 0u && !(INSTANCED && instance_of(prim_index) != 0u);
        if (SURFACE_HAS(SURFACE_FEATURE_NORMALS | SURFACE_FEATURE_UVS)
            && (shape.flags & (SHAPE_HAS_NORMALS | SHAPE_HAS_UVS)) != 0u && (shading || !agree)) {
            TriangleRecord tri = triangle_load(prim.index);
            if (shading && SURFACE_HAS(SURFACE_FEATURE_UVS) && (shape.flags & SHAPE_HAS_UVS) != 0u) {
                vec2 uv0 = vec2(vertex_texel(tri.v0, 0u).w, vertex_texel(tri.v0, 1u).x);
                vec2 uv1 = vec2(vertex_texel(tri.v1, 0u).w, vertex_texel(tri.v1, 1u).x);
                vec2 uv2 = vec2(vertex_texel(tri.v2, 0u).w, vertex_texel(tri.v2, 1u).x);
                s.uv = w * uv0 + u * uv1 + v * uv2;
                // ∂p/∂u of the affine map from uv to the triangle (PBR 4th ed., sec.
                // 6.5.3); a degenerate uv triangle gets an arbitrary tangent of the face.
                vec2 duv0 = uv1 - uv0, duv1 = uv2 - uv0;
                float det = duv0.x * duv1.y - duv0.y * duv1.x;
                if (det != 0.0) {
                    dpdu = (duv1.y * dp0 - duv0.y * dp1) / det;
#ifdef SURFACE_PARTIALS
                    surface_dp_dv = (duv0.x * dp1 - duv1.x * dp0) / det;
#endif
                } else {
                    vec3 b;
                    frame_basis(s.ng, dpdu, b);
#ifdef SURFACE_PARTIALS
                    surface_dp_dv = b;
#endif
                }
            }
            if (SURFACE_HAS(SURFACE_FEATURE_NORMALS) && (shape.flags & SHAPE_HAS_NORMALS) != 0u) {
                vec3 ns = instance_normal(prim_index,
                    w * vertex_texel(tri.v0, 0u).xyz + u * vertex_texel(tri.v1, 0u).xyz
                    + v * vertex_texel(tri.v2, 0u).xyz);
                float l = length(ns);
                if (l > 0.0) s.ns = ns / l;
                // Keep the shading normal on the side of the geometric one.
                if (dot(s.ns, s.ng) < 0.0) s.ng = -s.ng;
            }
        }
    }
    if (INSTANCED) s.p_error += instance_point_error(prim_index, s.p);
    if ((shape.flags & SHAPE_FLIP_NORMALS) != 0u) {
        s.ng = -s.ng;
        s.ns = -s.ns;
    }
    s.ss = shading ? surface_tangent(dpdu, s.ns) : vec3(0.0);
#ifdef SURFACE_PARTIALS
    surface_dp_du = dpdu;
#endif
    return s;
}

Surface surface_at(uint prim_index, float u, float v, vec3 ray_o, vec3 ray_d, float t) {
    return surface_at_as(prim_index, u, v, ray_o, ray_d, t, true);
}

// A direction in the shading frame (ss, ns × ss, ns) of s, and back.
vec3 surface_to_local(Surface s, vec3 v) {
    return vec3(dot(v, s.ss), dot(v, cross(s.ns, s.ss)), dot(v, s.ns));
}

vec3 surface_to_world(Surface s, vec3 l) {
    return l.x * s.ss + l.y * cross(s.ns, s.ss) + l.z * s.ns;
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
