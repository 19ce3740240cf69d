// Textured BSDF parameters and normal maps: what the BSDF record holds at one
// surface point. Needs scene_bindings.glsl, texture.glsl, surface.glsl, frame.glsl.
#ifndef BSDF_TEXTURED_GLSL
#define BSDF_TEXTURED_GLSL

// The record with every textured parameter replaced by its texture at uv (colors as
// they are, roughness from the texture's luminance, at least 1e-4 as Mitsuba's).
BsdfRecord bsdf_textured(BsdfRecord b, vec2 uv) {
    if (!TEXTURE_USES(TEXTURE_FEATURE_BSDF)) return b;
    if (b.tex_reflectance != 0u) {
        b.reflectance = texture_eval(b.tex_reflectance, uv);
        // Nori's microfacet: ks = 1 - max(kd).
        if (b.kind == BSDF_NORI_MICROFACET) b.specular_weight = 1.0 - max(b.reflectance.x, max(b.reflectance.y, b.reflectance.z));
    }
    if (b.tex_specular != 0u) b.specular = texture_eval(b.tex_specular, uv);
    if (b.tex_transmittance != 0u) b.transmittance = texture_eval(b.tex_transmittance, uv);
    if (b.tex_alpha_u != 0u) b.alpha_u = max(texture_luminance(texture_eval(b.tex_alpha_u, uv)), 1e-4);
    if (b.tex_alpha_v != 0u) b.alpha_v = max(texture_luminance(texture_eval(b.tex_alpha_v, uv)), 1e-4);
    return b;
}

// The shading normal a normal map gives at s (Mitsuba's normalmap.cpp): the texture's
// RGB c in [0, 1]³ is the tangent-space normal 2c − 1 in the frame
// (t, n × t, n), n = s.ns and t = ∂p/∂u made orthogonal to n (Gram-Schmidt).
vec3 bsdf_normal_mapped(uint map, Surface s) {
    vec3 c = 2.0 * texture_eval(map, s.uv) - 1.0;
    vec3 t = s.dpdu - s.ns * dot(s.ns, s.dpdu);
    float len = length(t);
    vec3 bx, by;
    if (len > 1e-12) {
        bx = t / len;
        by = cross(s.ns, bx);
    } else {
        frame_basis(s.ns, bx, by);
    }
    vec3 n = c.x * bx + c.y * by + c.z * s.ns;
    float l = length(n);
    return l > 0.0 ? n / l : s.ns;
}

#endif
