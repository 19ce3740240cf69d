// Ray/cylinder intersection: the capless tube of radius r around the axis from c to
// c + a, 0 <= (p - c).a / |a|^2 <= 1. The sphere's stable quadratic (Haines et al.
// 2019, Ray Tracing Gems ch. 7, eqs. 7.5 and 7.8) on the ray projected off the axis;
// the near root first, then the far one, each kept between the ends.
// The tests of src/accel/cylinder.rs, in one expression.
#ifndef INTERSECT_CYLINDER_GLSL
#define INTERSECT_CYLINDER_GLSL

// One return (every test made, as llvmpipe computes them all anyway): see
// intersect_triangle.glsl.
bool intersect_cylinder(vec3 o, vec3 d, vec3 c, vec3 a, float r, float tmin, float tmax,
                        out float t) {
    float inv_len2 = 1.0 / dot(a, a);
    vec3 f = o - c;
    float fz = dot(f, a) * inv_len2;
    float dz = dot(d, a) * inv_len2;
    vec3 fp = f - fz * a;
    vec3 dp = d - dz * a;
    // qa == 0: along the axis.
    float qa = dot(dp, dp);
    float bp = -dot(fp, dp);
    vec3 l = fp + (bp / qa) * dp;
    float disc = qa * (r * r - dot(l, l));
    float cc = dot(fp, fp) - r * r;
    float q = bp + (bp >= 0.0 ? sqrt(disc) : -sqrt(disc));
    float t0 = cc / q;
    float t1 = q / qa;
    float tn = min(t0, t1);
    float tf = max(t0, t1);
    float zn = fz + tn * dz;
    float zf = fz + tf * dz;
    bool near = tn > tmin && tn < tmax && zn >= 0.0 && zn <= 1.0;
    bool far = tf > tmin && tf < tmax && zf >= 0.0 && zf <= 1.0;
    bool hit = qa != 0.0 && !(disc < 0.0) && q != 0.0 && (near || far);
    if (hit) t = near ? tn : tf;
    return hit;
}

#endif
