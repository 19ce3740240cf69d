// Textured BSDF parameters: what the BSDF record holds at one surface point (normal
// maps: normal_map.glsl). Needs scene_bindings.glsl, texture.glsl.
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

#endif
