// Ray against a round cubic B-spline curve segment (Mitsuba's bsplinecurve, Embree's
// round B-spline curves): the tube swept by the circle of centre c(u), radius r(u),
// normal to c'(u); the entry only (back faces culled), no end caps.
// src/accel/bspline.rs derives it and is the same arithmetic, operation for operation.
// Needs scene_bindings.glsl (grid_value): a segment's four control points (x y z
// radius) are at its primitive's offset in the grid buffer (PRIM_BSPLINE_CURVE).
#ifndef INTERSECT_BSPLINE_GLSL
#define INTERSECT_BSPLINE_GLSL

#include "shape/intersect_curve.glsl"

#define BSPLINE_PIECES 8
#define BSPLINE_NEWTON_STEPS 8

// The four control points at word `offset` of the grid buffer.
void bspline_points(uint offset, out vec4 cp[4]) {
    for (uint k = 0u; k < 4u; k++) {
        cp[k] = vec4(grid_value(offset + 4u * k), grid_value(offset + 4u * k + 1u),
                     grid_value(offset + 4u * k + 2u), grid_value(offset + 4u * k + 3u));
    }
}

// Centre c, c', c'', radius r and r' at u (Mitsuba's cubic_interpolation).
void bspline_eval(vec4 cp[4], float u, out vec3 c, out vec3 dc, out vec3 ddc, out float r,
                  out float dr) {
    float u2 = u * u;
    float u3 = u2 * u;
    vec4 b = vec4((-u3 + 3.0 * u2 - 3.0 * u + 1.0) / 6.0, (3.0 * u3 - 6.0 * u2 + 4.0) / 6.0,
                  (-3.0 * u3 + 3.0 * u2 + 3.0 * u + 1.0) / 6.0, u3 / 6.0);
    vec4 db = vec4((-3.0 * u2 + 6.0 * u - 3.0) / 6.0, (9.0 * u2 - 12.0 * u) / 6.0,
                   (-9.0 * u2 + 6.0 * u + 3.0) / 6.0, 3.0 * u2 / 6.0);
    vec4 ddb = vec4(1.0 - u, 3.0 * u - 2.0, 1.0 - 3.0 * u, u);
    vec4 cc = vec4(0.0), dcc = vec4(0.0), ddcc = vec4(0.0);
    for (int k = 0; k < 4; k++) {
        cc += b[k] * cp[k];
        dcc += db[k] * cp[k];
        ddcc += ddb[k] * cp[k];
    }
    c = cc.xyz;
    dc = dcc.xyz;
    ddc = ddcc.xyz;
    r = cc.w;
    dr = dcc.w;
}

// Mitsuba's normal, unnormalized: (|c'|^2 - q.c'') q - r r' c', q from the centre.
vec3 bspline_normal(vec3 q, vec3 dc, vec3 ddc, float r, float dr) {
    return (dot(dc, dc) - dot(q, ddc)) * q - (r * dr) * dc;
}

// The entry t in (tmin, tmax) and the segment parameter u of the segment of control
// points cp. One return.
bool intersect_bspline_curve(vec3 o, vec3 d, vec4 cp_world[4], float tmin, float tmax,
                             out float t_out, out float u_out) {
    float len = length(d);
    vec3 dn = d / len;
    vec3 mid = (cp_world[1].xyz + cp_world[2].xyz) * 0.5;
    float shift = dot(mid - o, dn);
    vec3 ol = o + shift * dn - mid;
    vec4 l[4];
    for (int k = 0; k < 4; k++) l[k] = cp_world[k] - vec4(mid, 0.0);
    // The size of the moved coordinates, whose rounding bounds the residuals.
    float ext = 0.0;
    for (int k = 0; k < 4; k++) {
        vec3 m = abs(l[k].xyz);
        ext = max(ext, max(m.x, max(m.y, m.z)));
    }
    vec4 a = l[0] - 2.0 * l[1] + l[2];
    vec4 b = l[1] - 2.0 * l[2] + l[3];
    float h = 1.0 / float(BSPLINE_PIECES);
    float grow = (max(length(a.xyz), length(b.xyz)) + max(abs(a.w), abs(b.w)))
        * (h * h * 0.125) * 1.01;
    float lo = tmin * len - shift;
    float hi = tmax * len - shift;
    float inf = uintBitsToFloat(0x7f800000u);
    float best_t = inf;
    float best_u = 0.0;
    vec3 c0, c1, dc, ddc;
    float r0, r1, r, dr;
    bspline_eval(l, 0.0, c0, dc, ddc, r0, dr);
    for (int i = 0; i < BSPLINE_PIECES; i++) {
        float u1 = float(i + 1) * h;
        bspline_eval(l, u1, c1, dc, ddc, r1, dr);
        float te = 0.0, v = 0.0;
        bool cone = intersect_linear_curve(ol, dn, c0, c1, max(r0, 0.0) + grow,
                                           max(r1, 0.0) + grow, true, -inf, inf, te, v);
        c0 = c1;
        r0 = r1;
        float t = max(te, lo);
        if (cone && t < best_t) {
            float u = (float(i) + v) * h;
            for (int s = 0; s < BSPLINE_NEWTON_STEPS; s++) {
                vec3 c;
                bspline_eval(l, u, c, dc, ddc, r, dr);
                vec3 q = ol + t * dn - c;
                float f1 = dot(q, dc);
                float f2 = dot(q, q) - r * r;
                float j00 = dot(dn, dc);
                float j01 = dot(q, ddc) - dot(dc, dc);
                float j10 = 2.0 * dot(q, dn);
                float j11 = -2.0 * (dot(q, dc) + r * dr);
                float det = j00 * j11 - j01 * j10;
                if (det != 0.0) {
                    t -= (f1 * j11 - f2 * j01) / det;
                    u -= (j00 * f2 - j10 * f1) / det;
                }
                u = clamp(u, -0.5, 1.5);
            }
            vec3 c;
            bspline_eval(l, u, c, dc, ddc, r, dr);
            vec3 q = ol + t * dn - c;
            float ql = length(q);
            // On the circle's radius to 1e-4 of it, in its plane to 1e-3 (which only
            // moves u), both above the rounding of coordinates of size ext + |t|.
            float scale = 1e-6 * (ext + abs(t));
            bool converged = abs(ql - r) <= 1e-4 * abs(r) + scale
                && abs(dot(q, dc)) <= (1e-3 * (ql + abs(r)) + scale) * length(dc);
            bool front = dot(bspline_normal(q, dc, ddc, r, dr), dn) < 0.0;
            if (converged && front && u >= 0.0 && u <= 1.0 && t > lo && t < hi && t < best_t) {
                best_t = t;
                best_u = u;
            }
        }
    }
    bool hit = !isinf(best_t);
    if (hit) {
        t_out = (shift + best_t) / len;
        u_out = best_u;
    }
    return hit;
}

#endif
