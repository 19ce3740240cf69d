// Ray/disk intersection under any affine map: the unit disk at c + x a1 + y a2, hit
// where the ray meets the plane of normal m = a1 x a2; (x, y) from the dual basis
// b1 = (a2 x m) / |m|^2, b2 = (m x a1) / |m|^2. The tests of src/accel/disk.rs, in one expression.
#ifndef INTERSECT_DISK_GLSL
#define INTERSECT_DISK_GLSL

// t in (tmin, tmax) where o + t d meets the disk, and the object-space (x, y) there;
// set only on a hit.
// One return (every test made, as llvmpipe computes them all anyway): see
// intersect_triangle.glsl.
bool intersect_disk(vec3 o, vec3 d, vec3 c, vec3 a1, vec3 a2, float tmin, float tmax,
                    out float t, out vec2 xy) {
    vec3 m = cross(a1, a2);
    // denom == 0: parallel to the plane (or a degenerate disk).
    float denom = dot(d, m);
    float th = dot(c - o, m) / denom;
    vec3 q = o + th * d - c;
    float inv = 1.0 / dot(m, m);
    float x = dot(q, cross(a2, m)) * inv;
    float y = dot(q, cross(m, a1)) * inv;
    bool hit = denom != 0.0 && th > tmin && th < tmax && !(x * x + y * y > 1.0);
    if (hit) {
        t = th;
        xy = vec2(x, y);
    }
    return hit;
}

#endif
