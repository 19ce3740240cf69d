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

#endif
