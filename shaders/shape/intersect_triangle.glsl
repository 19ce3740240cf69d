// Watertight ray/triangle intersection (Woop, Benthin, Wald 2013, "Watertight
// Ray/Triangle Intersection", JCGT 2(1), listings 1 and 2, no backface culling).
// Mirrors src/accel/triangle.rs line for line (but for the division-free first test of
// tr.division_last, which admits every hit of the exact test and changes no answer);
// see there for the departures from the paper (no fp64 fallback: a zero edge function
// counts as a hit; t by one division and tested against the open range (tmin, tmax)).
#ifndef INTERSECT_TRIANGLE_GLSL
#define INTERSECT_TRIANGLE_GLSL

// γ(n) = n ε / (1 - n ε), ε = 2^-24, rounded up (accel::triangle::GAMMA*).
#define TRIANGLE_GAMMA2 1.192093e-7
#define TRIANGLE_GAMMA3 1.7881396e-7
#define TRIANGLE_GAMMA5 2.9802326e-7
// 1 -+ 2^-20: intersect_triangle's division-free first test.
#define TRIANGLE_LOOSE_BELOW 0.99999905
#define TRIANGLE_LOOSE_ABOVE 1.00000095

// Per-ray part: axis permutation k = (kx, ky, kz), kz the largest |d| component, and
// shear s = (d[kx] / d[kz], d[ky] / d[kz], 1 / d[kz]) making the ray the +z axis.
struct TriangleRay {
    ivec3 k;
    vec3 s;
    // Test without a division first (bvh_trace's division_last; a constant).
    bool division_last;
};

TriangleRay triangle_ray_make(vec3 d) {
    vec3 a = abs(d);
    int kz = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    if (d[kz] < 0.0) { // swap to keep the winding
        int tmp = kx;
        kx = ky;
        ky = tmp;
    }
    TriangleRay tr;
    tr.k = ivec3(kx, ky, kz);
    tr.s = vec3(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]);
    tr.division_last = false;
    return tr;
}

// Hit of o + t d (tr = triangle_ray_make(d)) with triangle p0 p1 p2 for tmin < t < tmax;
// barycentrics u, v with p = (1-u-v) p0 + u p1 + v p2. t, u, v are only set on a hit.
// One value returned, no early return: llvmpipe computes the whole function for every
// lane whatever it returns early, and spirv-opt's merge-return (which gpu::specialize
// runs before inlining) turns early returns into a loop around the body, which costs
// llvmpipe more (callgrind, Cornell box: intersect +7%). With tr.division_last, the
// division and the error bound wait for a division-free first test (below).
bool intersect_triangle(TriangleRay tr, vec3 o, vec3 p0, vec3 p1, vec3 p2, float tmin,
                        float tmax, out float t, out float u, out float v) {
    int kx = tr.k.x, ky = tr.k.y, kz = tr.k.z;
    vec3 a = p0 - o;
    vec3 b = p1 - o;
    vec3 c = p2 - o;
    // `precise` forbids fused multiply-adds: the edge function of an edge shared by two
    // triangles must come out exactly negated in the other one, or rays leak.
    precise float ax = a[kx] - tr.s.x * a[kz];
    precise float ay = a[ky] - tr.s.y * a[kz];
    precise float bx = b[kx] - tr.s.x * b[kz];
    precise float by = b[ky] - tr.s.y * b[kz];
    precise float cx = c[kx] - tr.s.x * c[kz];
    precise float cy = c[ky] - tr.s.y * c[kz];
    // Scaled barycentrics: edge functions of the sheared 2D triangle at the origin.
    precise float eu = cx * by - cy * bx;
    precise float ev = ax * cy - ay * cx;
    precise float ew = bx * ay - by * ax;
    // Outside if the signs differ; zeros (edges, vertices) count as inside.
    bool inside = !((eu < 0.0 || ev < 0.0 || ew < 0.0) && (eu > 0.0 || ev > 0.0 || ew > 0.0));
    // det == 0: the ray parallel to the plane, or a degenerate triangle.
    float det = eu + ev + ew;
    float az = tr.s.z * a[kz];
    float bz = tr.s.z * b[kz];
    float cz = tr.s.z * c[kz];
    float t_scaled = eu * az + ev * bz + ew * cz;
    // First without the division (a SIMD division costs a dozen other instructions on
    // a CPU): t = t_scaled / det within (tmin, tmax), each bound loosened by 2^-20 of
    // itself so that this admits every hit the exact test below admits (t's roundings
    // are a few 2^-24). Only where some lane passes does the exact test run: the same
    // hits as it alone, bit for bit.
    float t_signed = det < 0.0 ? -t_scaled : t_scaled;
    float abs_det = abs(det);
    bool candidate = inside && det != 0.0
        && (!tr.division_last || (t_signed > tmin * abs_det * TRIANGLE_LOOSE_BELOW
                                  && t_signed < tmax * abs_det * TRIANGLE_LOOSE_ABOVE));
    bool hit = false;
    if (!tr.division_last || candidate) {
        float rcp_det = 1.0 / det;
        float th = t_scaled * rcp_det;
        // Reject hits whose t is within its own rounding error of zero, which a ray
        // leaving this very surface produces (PBR 4th ed., sec. 6.8.7).
        float max_zt = max(max(abs(az), abs(bz)), abs(cz));
        float max_xt = max(max(abs(ax), abs(bx)), abs(cx));
        float max_yt = max(max(abs(ay), abs(by)), abs(cy));
        float delta_z = TRIANGLE_GAMMA3 * max_zt;
        // Unscaled z in the shear's error, as in accel::triangle.
        float max_z = max(max(abs(a[kz]), abs(b[kz])), abs(c[kz]));
        float delta_x = TRIANGLE_GAMMA5 * (max_xt + max_z);
        float delta_y = TRIANGLE_GAMMA5 * (max_yt + max_z);
        float delta_e = 2.0 * (TRIANGLE_GAMMA2 * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
        float max_e = max(max(abs(eu), abs(ev)), abs(ew));
        float delta_t = 3.0 * (TRIANGLE_GAMMA3 * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * abs(rcp_det);
        hit = candidate && th > tmin && th < tmax && th > delta_t;
        if (hit) {
            t = th;
            u = ev * rcp_det;
            v = ew * rcp_det;
        }
    }
    return hit;
}

#endif
