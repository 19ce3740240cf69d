// Warps of the unit square to sampling domains, with their densities. Each pdf is
// stated with its measure; tests/chi2.rs checks every warp against its pdf.
#ifndef WARP_GLSL
#define WARP_GLSL

#define PI 3.14159265358979323846
#define INV_PI 0.31830988618379067154
#define INV_TWO_PI 0.15915494309189533577
#define INV_FOUR_PI 0.07957747154594766788

// Concentric map to the unit disk (Shirley and Chiu 1997, "A Low Distortion Map
// Between Disk and Square"). Density 1/π per unit area.
vec2 warp_square_to_disk(vec2 u) {
    vec2 o = 2.0 * u - 1.0;
    if (o.x == 0.0 && o.y == 0.0) return vec2(0.0);
    float r, theta;
    if (abs(o.x) > abs(o.y)) {
        r = o.x;
        theta = (PI / 4.0) * (o.y / o.x);
    } else {
        r = o.y;
        theta = PI / 2.0 - (PI / 4.0) * (o.x / o.y);
    }
    return r * vec2(cos(theta), sin(theta));
}
// Per unit area of the plane.
float warp_square_to_disk_pdf(vec2 p) { return dot(p, p) <= 1.0 ? INV_PI : 0.0; }

// Cosine-weighted hemisphere around +z (Malley's method: lift the disk).
// Density cos θ / π per unit solid angle.
vec3 warp_cosine_hemisphere(vec2 u) {
    vec2 d = warp_square_to_disk(u);
    float z = sqrt(max(0.0, 1.0 - dot(d, d)));
    return vec3(d, z);
}
float warp_cosine_hemisphere_pdf(vec3 v) { return v.z > 0.0 ? v.z * INV_PI : 0.0; }

// Uniform hemisphere around +z. Density 1/(2π) per unit solid angle.
vec3 warp_uniform_hemisphere(vec2 u) {
    float z = u.x;
    float r = sqrt(max(0.0, 1.0 - z * z));
    float phi = 2.0 * PI * u.y;
    return vec3(r * cos(phi), r * sin(phi), z);
}
float warp_uniform_hemisphere_pdf(vec3 v) { return v.z > 0.0 ? 0.5 * INV_PI : 0.0; }

// Uniform sphere (Archimedes: z uniform in [-1, 1]). Density 1/(4π) per unit solid angle.
vec3 warp_uniform_sphere(vec2 u) {
    float z = 1.0 - 2.0 * u.x;
    float r = sqrt(max(0.0, 1.0 - z * z));
    float phi = 2.0 * PI * u.y;
    return vec3(r * cos(phi), r * sin(phi), z);
}
float warp_uniform_sphere_pdf(vec3 v) { return INV_FOUR_PI; }

// Uniform cone of directions around +z with 1 - cos θmax = one_minus_cos_max, given in
// that form so that tiny cones (far, small sphere lights) keep their precision: the
// cap below with cos_max = 1 - one_minus_cos_max. Density 1 / (2π (1 - cos θmax)).
vec3 warp_uniform_cone(vec2 u, float one_minus_cos_max) {
    float one_minus_cos = u.x * one_minus_cos_max;
    float cos_theta = 1.0 - one_minus_cos;
    float sin_theta = sqrt(max(0.0, one_minus_cos * (2.0 - one_minus_cos)));
    float phi = 2.0 * PI * u.y;
    return vec3(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta);
}
float warp_uniform_cone_pdf(float one_minus_cos_max) { return INV_TWO_PI / one_minus_cos_max; }

// Uniform spherical cap around +z of all directions with cos θ >= cos_max (a cone of
// half-angle acos(cos_max)); z is uniform in [cos_max, 1]. Density 1/(2π(1 - cos_max))
// per unit solid angle inside the cap, 0 outside.
vec3 warp_uniform_cap(vec2 u, float cos_max) { return warp_uniform_cone(u, 1.0 - cos_max); }
float warp_uniform_cap_pdf(vec3 v, float cos_max) {
    // Through the cone's pdf (what sphere lights use), so the warp test checks that one.
    return v.z >= cos_max ? warp_uniform_cone_pdf(1.0 - cos_max) : 0.0;
}

// Uniform point on a triangle as barycentrics (b0, b1), b2 = 1 - b0 - b1 (PBR 4th ed.,
// sec. A.5.5, the square-root parameterization). Density 2 per unit area of the
// (b0, b1) plane inside the triangle b0, b1 >= 0, b0 + b1 <= 1 (whose area is 1/2):
// so 1/A per unit area of a triangle of area A.
vec2 warp_uniform_triangle(vec2 u) {
    float su = sqrt(u.x);
    return vec2(1.0 - su, u.y * su);
}
float warp_uniform_triangle_pdf(vec2 b) {
    return (b.x >= 0.0 && b.y >= 0.0 && b.x + b.y <= 1.0) ? 2.0 : 0.0;
}

// The tent density 1 - |t| on [-1, 1] in each coordinate, by inverting its CDF
// (Mitsuba's warp::square_to_tent): for x = 2u - 1 >= 0, t = 1 - sqrt(1 - x).
vec2 warp_square_to_tent(vec2 u) {
    vec2 x = 2.0 * u - 1.0;
    return sign(x) * (1.0 - sqrt(max(1.0 - abs(x), 0.0)));
}

#endif
