// Ray/disk intersection under any affine map: the unit disk at c + x a1 + y a2, hit
// where the ray meets the plane of normal m = a1 x a2; (x, y) from the dual basis
// b1 = (a2 x m) / |m|^2, b2 = (m x a1) / |m|^2. Mirrors src/accel/disk.rs line for line.
#ifndef INTERSECT_DISK_GLSL
#define INTERSECT_DISK_GLSL

// t in (tmin, tmax) where o + t d meets the disk, and the object-space (x, y) there;
// set only on a hit.
bool intersect_disk(vec3 o, vec3 d, vec3 c, vec3 a1, vec3 a2, float tmin, float tmax,
                    out float t, out vec2 xy) {
    vec3 m = cross(a1, a2);
    float denom = dot(d, m);
    if (denom == 0.0) {
        return false; // parallel to the plane (or a degenerate disk)
    }
    float th = dot(c - o, m) / denom;
    if (!(th > tmin && th < tmax)) {
        return false;
    }
    vec3 q = o + th * d - c;
    float inv = 1.0 / dot(m, m);
    float x = dot(q, cross(a2, m)) * inv;
    float y = dot(q, cross(m, a1)) * inv;
    if (x * x + y * y > 1.0) {
        return false;
    }
    t = th;
    xy = vec2(x, y);
    return true;
}

#endif
