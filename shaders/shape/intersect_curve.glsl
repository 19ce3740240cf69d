// Ray against a round linear curve segment (Mitsuba's linearcurve, Embree's round
// linear curves): the union of the spheres of centre c0 + v (c1 - c0) and radius
// r0 + v (r1 - r0), 0 <= v <= 1; the entry only (Embree culls curves' back faces).
// src/accel/curve.rs derives it and is the same arithmetic, operation for operation.
#ifndef INTERSECT_CURVE_GLSL
#define INTERSECT_CURVE_GLSL

// The entry t in (tmin, tmax) and v, the parameter of the touching sphere's centre (0
// and 1 on the end caps); the start sphere only where start_cap (a curve's first
// segment: elsewhere it is the previous segment's end sphere, as in Embree). One
// return (see intersect_triangle.glsl).
bool intersect_linear_curve(vec3 o, vec3 d, vec3 c0, vec3 c1, float r0, float r1,
                            bool start_cap, float tmin, float tmax, out float t, out float v) {
    // The ray moved to its point nearest the segment's middle, with a unit direction:
    // thin curves far away keep their radius in the quadric's terms.
    float len = length(d);
    vec3 dn = d / len;
    float shift = dot((c0 + c1) * 0.5 - o, dn);
    vec3 os = o + shift * dn;
    vec3 a = c1 - c0;
    vec3 oa = os - c0;
    float dr = r0 - r1;
    float m0 = dot(a, a);
    float m1 = dot(a, oa);
    float m2 = dot(a, dn);
    float m3 = dot(dn, oa);
    float m5 = dot(oa, oa);
    // The envelope of the spheres: d2 (|p - c0|^2 - r0^2) - y^2 = 0, v = y / d2.
    float d2 = m0 - dr * dr;
    float y0 = m1 - r0 * dr;
    // Products along the axis cancel as cross products (see curve.rs).
    vec3 ad = cross(a, dn);
    vec3 ao = cross(a, oa);
    float k2 = dot(ad, ad) - dr * dr;
    float k1 = dot(ao, ad) - dr * dr * m3 + r0 * dr * m2;
    float k0 = dot(ao, ao) - dr * dr * m5 + 2.0 * m1 * r0 * dr - m0 * r0 * r0;
    float h = k1 * k1 - k0 * k2;
    float sq = sqrt(max(h, 0.0));
    float q = -(k1 + (k1 >= 0.0 ? sq : -sq));
    float ta = q / k2;
    float tb = k0 / q;
    float t_body = k2 > 0.0 ? min(ta, tb) : max(ta, tb);
    float y = y0 + t_body * m2;
    bool body = d2 > 0.0 && h >= 0.0 && q != 0.0 && y >= 0.0 && y <= d2
        && !isinf(t_body) && !isnan(t_body);
    float best = body ? t_body : uintBitsToFloat(0x7f800000u);
    float best_v = body ? y / d2 : 0.0;
    // The end spheres, from the ray's closest approach to each centre.
    vec3 oc = os - c0;
    float b = dot(oc, dn);
    vec3 perp = oc - b * dn;
    float hs = r0 * r0 - dot(perp, perp);
    float ts = -b - sqrt(max(hs, 0.0));
    if (start_cap && hs >= 0.0 && ts < best) {
        best = ts;
        best_v = 0.0;
    }
    oc = os - c1;
    b = dot(oc, dn);
    perp = oc - b * dn;
    hs = r1 * r1 - dot(perp, perp);
    ts = -b - sqrt(max(hs, 0.0));
    if (hs >= 0.0 && ts < best) {
        best = ts;
        best_v = 1.0;
    }
    float tw = (shift + best) / len;
    bool hit = !isinf(best) && tw > tmin && tw < tmax;
    if (hit) {
        t = tw;
        v = best_v;
    }
    return hit;
}

#endif
