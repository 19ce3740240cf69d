// Ray against one ellipsoid of Mitsuba's `ellipsoids` shape (src/scene/shape/ellipsoids.rs):
// the ray is taken to the unit sphere by the ellipsoid's map M = diag(1 / semi-axes) Rᵀ
// and met there in closed form (Mitsuba's improved quadratic: the discriminant from the
// closest point). Back faces are culled as Mitsuba culls them: the nearer crossing is
// the hit, or nothing when it lies behind the origin (a ray starting inside misses).
// Ellipsoid::intersect in the Rust source is the same arithmetic.
// Needs scene_bindings.glsl (grid_value): an ellipsoid's 12 numbers (centre, M's rows)
// are at its primitive's offset in the grid buffer (PRIM_ELLIPSOID).
#ifndef INTERSECT_ELLIPSOID_GLSL
#define INTERSECT_ELLIPSOID_GLSL

// The centre c and the map m (m * x = M x) of the ellipsoid at word `offset`.
void ellipsoid_load(uint offset, out vec3 c, out mat3 m) {
    c = vec3(grid_value(offset), grid_value(offset + 1u), grid_value(offset + 2u));
    vec3 r0 = vec3(grid_value(offset + 3u), grid_value(offset + 4u), grid_value(offset + 5u));
    vec3 r1 = vec3(grid_value(offset + 6u), grid_value(offset + 7u), grid_value(offset + 8u));
    vec3 r2 = vec3(grid_value(offset + 9u), grid_value(offset + 10u), grid_value(offset + 11u));
    m = transpose(mat3(r0, r1, r2));
}

// The entry t in (tmin, tmax) of ray (o, d) into the ellipsoid at word `offset`; t is
// only set on a hit. One return (see intersect_triangle.glsl).
bool intersect_ellipsoid(vec3 o, vec3 d, uint offset, float tmin, float tmax, out float t) {
    vec3 c;
    mat3 m;
    ellipsoid_load(offset, c, m);
    vec3 lo = m * (o - c);
    vec3 ld = m * d;
    float a = dot(ld, ld);
    float b = -dot(lo, ld);
    float cc = dot(lo, lo) - 1.0;
    vec3 l = lo + (b / a) * ld;
    float disc = 1.0 - dot(l, l);
    float q = b + (b >= 0.0 ? sqrt(a * disc) : -sqrt(a * disc));
    float tn = min(cc / q, q / a);
    bool hit = !(disc < 0.0) && q != 0.0 && tn > tmin && tn < tmax;
    if (hit) t = tn;
    return hit;
}

// The unit outward normal at point p of the ellipsoid at word `offset`: Mᵀ M (p - c).
vec3 ellipsoid_normal(uint offset, vec3 p) {
    vec3 c;
    mat3 m;
    ellipsoid_load(offset, c, m);
    return normalize(transpose(m) * (m * (p - c)));
}

#endif
