// Ray/sphere intersection robust to large distances and small radii (Haines, Günther,
// Akenine-Möller 2019, "Precision Improvements for Ray/Sphere Intersection", Ray Tracing
// Gems ch. 7: discriminant from the closest-point vector l, eq. 7.5; stable roots
// q = b' + sign(b') sqrt(disc), t0 = c / q, t1 = q / a, eq. 7.8).
// The tests of src/accel/sphere.rs, in one expression.
#ifndef INTERSECT_SPHERE_GLSL
#define INTERSECT_SPHERE_GLSL

// Nearest t in (tmin, tmax) where o + t d meets the sphere (center c, radius r); the far
// root when the near one is out of range. t is only set on a hit.
// One return (every test made, as llvmpipe computes them all anyway): see
// intersect_triangle.glsl.
bool intersect_sphere(vec3 o, vec3 d, vec3 c, float r, float tmin, float tmax,
                      out float t) {
    vec3 f = o - c;
    float a = dot(d, d);
    float bp = -dot(f, d);
    vec3 l = f + (bp / a) * d;
    float disc = a * (r * r - dot(l, l));
    float cc = dot(f, f) - r * r;
    float q = bp + (bp >= 0.0 ? sqrt(disc) : -sqrt(disc));
    float t0 = cc / q;
    float t1 = q / a;
    float tn = min(t0, t1);
    float tf = max(t0, t1);
    bool near = tn > tmin && tn < tmax;
    // No hit where disc < 0, or q == 0 (the origin on the sphere, the ray tangent to it).
    bool hit = !(disc < 0.0) && q != 0.0 && (near || (tf > tmin && tf < tmax));
    if (hit) t = near ? tn : tf;
    return hit;
}

#endif
