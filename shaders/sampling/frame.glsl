// Orthonormal frames around a normal.
#ifndef FRAME_GLSL
#define FRAME_GLSL

// Duff et al. 2017, "Building an Orthonormal Basis, Revisited", JCGT 6(1), listing 3:
// branchless, no singularity at n = -z.
void frame_basis(vec3 n, out vec3 s, out vec3 t) {
    float sign = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (sign + n.z);
    float b = n.x * n.y * a;
    s = vec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    t = vec3(b, sign + n.y * n.y * a, -n.y);
}

// Local direction (z along n) to world.
vec3 frame_to_world(vec3 n, vec3 local) {
    vec3 s, t;
    frame_basis(n, s, t);
    return local.x * s + local.y * t + local.z * n;
}

// World direction to the local frame around n (z along n).
vec3 frame_to_local(vec3 n, vec3 v) {
    vec3 s, t;
    frame_basis(n, s, t);
    return vec3(dot(v, s), dot(v, t), dot(v, n));
}

#endif
