// Mitsuba 3.9's `normalmap` BSDF wrapper (src/bsdfs/normalmap.cpp and
// normalmap_helpers.h): the shading normal a normal map gives, which light directions
// it lets through, and the shadowing term that softens its terminator. Directions are
// world-space and named as in pbrt (wo towards the viewer, wi towards the light);
// Mitsuba calls them si.wi and wo. Needs texture.glsl, surface.glsl, frame.glsl.
#ifndef NORMAL_MAP_GLSL
#define NORMAL_MAP_GLSL

struct NormalMapFrame {
    vec3 n0;      // the surface's shading normal (Mitsuba's si.sh_frame.n), unit
    vec3 n;       // the mapped shading normal, unit
    float alpha2; // roughness² of the shadowing term (0: no term)
};

// tan²θ of a unit direction whose cosine to the normal is c (Mitsuba's
// Frame3f::tan_theta_2; infinite at c = 0).
float normal_map_tan2(float c) {
    float c2 = c * c;
    return c2 > 0.0 ? max(1.0 - c2, 0.0) / c2 : uintBitsToFloat(0x7f800000u);
}

// The frame the normal map of record b gives at s, seen from wo. The texture's RGB
// c in [0, 1]³ is the normal 2c − 1 in the shading frame (s.ss, n0 × s.ss, n0), s.ss
// being ∂p/∂u made orthogonal to n0 (Mitsuba's si.sh_frame). With BSDF_NORMALMAP_FLIP (Mitsuba's
// flip_invalid_normals, after Schüssler et al. 2017, "Microfacet-based Normal
// Mapping for Robust Monte Carlo Path Tracing"), a mapped normal that faces away from
// wo has its tangential part negated, which turns it towards wo. A twosided record
// seen from behind mirrors n0 first, as Mitsuba's twosided does around a normalmap.
// normal_map_frame with the map's texel at s.uv already looked up (bsdf_textured_point).
NormalMapFrame normal_map_frame_texel(BsdfRecord b, Surface s, vec3 wo, vec3 texel) {
    NormalMapFrame f;
    vec3 bx = s.ss;
    vec3 by = cross(s.ns, bx);
    f.n0 = ((b.flags & BSDF_TWOSIDED) != 0u && dot(wo, s.ns) < 0.0) ? -s.ns : s.ns;
    vec3 c = 2.0 * texel - 1.0;
    vec3 n = c.x * bx + c.y * by + c.z * f.n0;
    if ((b.flags & BSDF_NORMALMAP_FLIP) != 0u && dot(wo, f.n0) * dot(wo, n) <= 0.0) {
        n = -c.x * bx - c.y * by + c.z * f.n0;
    }
    float l = length(n);
    f.n = l > 0.0 ? n / l : f.n0;
    // Estevez et al. 2019, "A Microfacet-Based Shadowing Function to Solve the Bump
    // Terminator Problem" (Ray Tracing Gems, ch. 12): the tilt's roughness
    // α² = min(tan²θ_n / 8, 1), θ_n the angle between n and n0.
    f.alpha2 = (b.flags & BSDF_NORMALMAP_SHADOWING) != 0u ? min(0.125 * normal_map_tan2(dot(f.n, f.n0)), 1.0) : 0.0;
    return f;
}

NormalMapFrame normal_map_frame(BsdfRecord b, Surface s, vec3 wo) {
    return normal_map_frame_texel(b, s, wo, texture_eval(b.normal_map, s.uv));
}

// The factor by which the normal map scales the nested BSDF's value for light from
// wi (unit): 0 where wi lies on different sides of n0 and of the mapped normal (the
// map never lets light through the surface), else the shadowing term of Estevez et
// al. 2019, G1 = 2 / (1 + sqrt(1 + α² tan²θ_i)), θ_i the angle of wi to n0 (1
// without it). The pdf of the nested BSDF is unchanged.
float normal_map_weight(NormalMapFrame f, vec3 wi) {
    float c0 = dot(wi, f.n0);
    if (!(c0 * dot(wi, f.n) > 0.0)) return 0.0;
    if (f.alpha2 == 0.0) return 1.0;
    return 2.0 / (1.0 + sqrt(1.0 + f.alpha2 * normal_map_tan2(c0)));
}

#endif
