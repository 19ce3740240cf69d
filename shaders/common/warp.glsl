// Warps of the unit square to sampling domains, with their densities.
#ifndef WARP_GLSL
#define WARP_GLSL

#define PI 3.14159265358979323846
#define INV_PI 0.31830988618379067154

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

// Uniform sphere. Density 1/(4π) per unit solid angle.
vec3 warp_uniform_sphere(vec2 u) {
    float z = 1.0 - 2.0 * u.x;
    float r = sqrt(max(0.0, 1.0 - z * z));
    float phi = 2.0 * PI * u.y;
    return vec3(r * cos(phi), r * sin(phi), z);
}
float warp_uniform_sphere_pdf() { return 0.25 * INV_PI; }

// Uniform cone of directions around +z with 1 - cos θmax = one_minus_cos_max (passed
// in that form so tiny cones keep their precision). Density 1 / (2π (1 - cos θmax)).
vec3 warp_uniform_cone(vec2 u, float one_minus_cos_max) {
    float one_minus_cos = u.x * one_minus_cos_max;
    float cos_theta = 1.0 - one_minus_cos;
    float sin_theta = sqrt(max(0.0, one_minus_cos * (2.0 - one_minus_cos)));
    float phi = 2.0 * PI * u.y;
    return vec3(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta);
}
float warp_uniform_cone_pdf(float one_minus_cos_max) { return 1.0 / (2.0 * PI * one_minus_cos_max); }

// Uniform point on a triangle as barycentrics (b1, b2), p = (1-b1-b2) p0 + b1 p1 + b2 p2
// (Turk 1990, "Generating Random Points in Triangles", Graphics Gems). Density
// 1/area per unit area.
vec2 warp_uniform_triangle(vec2 u) {
    float s = sqrt(u.x);
    return vec2(1.0 - s, u.y * s);
}

#endif
