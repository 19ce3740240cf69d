// Textured BSDF parameters: what the BSDF record holds at one surface point (normal
// maps: normal_map.glsl). Needs scene_bindings.glsl, texture.glsl.
#ifndef BSDF_TEXTURED_GLSL
#define BSDF_TEXTURED_GLSL

// Texels of a surface point that are not BSDF parameters, looked up by
// bsdf_textured_point with them.
struct SurfaceTexels {
    vec3 normal;   // the normal map's texel (normal_map_frame_texel)
    vec3 emission; // the area emitter's texture (emitter_area_radiance_texel)
};

// Slots of the texture lookups at one surface point (bits of the pending mask).
#define SURFACE_TEX_REFLECTANCE 0u
#define SURFACE_TEX_SPECULAR 1u
#define SURFACE_TEX_TRANSMITTANCE 2u
#define SURFACE_TEX_ALPHA_U 3u
#define SURFACE_TEX_ALPHA_V 4u
#define SURFACE_TEX_EMISSION 5u
#define SURFACE_TEX_COND_ETA 6u
#define SURFACE_TEX_COND_K 7u
#define SURFACE_TEX_ETA 8u
// Whether the scene textures some record's eta (surface_tex_used(SURFACE_TEX_ETA)):
// where not, the code of that slot compiles out, even in the lookup loop.
#define SURFACE_TEX_ETA_USED TEXTURE_USES(1u << (TEXTURE_FEATURE_PARAM_SHIFT + SURFACE_TEX_ETA))

// Texture id of lookup slot k (SURFACE_TEX_*) of record b.
uint surface_tex_id(BsdfRecord b, uint emission_texture, uint k) {
    return k == SURFACE_TEX_REFLECTANCE ? b.tex_reflectance
        : k == SURFACE_TEX_SPECULAR ? b.tex_specular
        : k == SURFACE_TEX_TRANSMITTANCE ? b.tex_transmittance
        : k == SURFACE_TEX_ALPHA_U ? b.tex_alpha_u
        : k == SURFACE_TEX_ALPHA_V ? b.tex_alpha_v
        : k == SURFACE_TEX_COND_ETA ? b.tex_cond_eta
        : k == SURFACE_TEX_COND_K ? b.tex_cond_k
        : SURFACE_TEX_ETA_USED && k == SURFACE_TEX_ETA ? b.tex_eta
        : emission_texture;
}

// Record b with the value c of lookup slot k, texture `id` (colors, a conductor's eta
// and k among them, as they are,
// roughness as Mitsuba's BSDFs read it, eval_1: texture_eval_1_color's luminance, at
// least 1e-4); the emission texel in `texels`.
BsdfRecord surface_tex_store(BsdfRecord b, inout SurfaceTexels texels, uint k, uint id, vec3 c) {
    bool roughness = k == SURFACE_TEX_ALPHA_U || k == SURFACE_TEX_ALPHA_V;
    float alpha = max(texture_luminance(roughness ? texture_eval_1_color(id, c) : c), 1e-4);
    if (k == SURFACE_TEX_REFLECTANCE) b.reflectance = c;
    if (k == SURFACE_TEX_SPECULAR) b.specular = c;
    if (k == SURFACE_TEX_TRANSMITTANCE) b.transmittance = c;
    if (k == SURFACE_TEX_ALPHA_U) b.alpha_u = alpha;
    if (k == SURFACE_TEX_ALPHA_V) b.alpha_v = alpha;
    if (k == SURFACE_TEX_EMISSION) texels.emission = c;
    if (k == SURFACE_TEX_COND_ETA) b.cond_eta = c;
    if (k == SURFACE_TEX_COND_K) b.cond_k = c;
    // eta (pplastic's) as Mitsuba's eval_1, as roughness: the luminance (a scene without
    // such a texture compiles this out).
    if (SURFACE_TEX_ETA_USED && k == SURFACE_TEX_ETA) b.eta = texture_luminance(texture_eval_1_color(id, c));
    return b;
}

// Whether the scene has lookups of slot k (TEXTURE_FEATURE_PARAM_SHIFT bits for the
// BSDF's parameters).
bool surface_tex_used(uint k) {
    return k == SURFACE_TEX_EMISSION ? TEXTURE_USES(TEXTURE_FEATURE_AREA)
                                     : TEXTURE_USES(1u << (TEXTURE_FEATURE_PARAM_SHIFT + k));
}

// Row r (0..7) of b.table by selects between constant rows (a dynamic index would put
// the record in per-lane scratch memory on llvmpipe: roughplastic.glsl says more).
uvec4 bsdf_table_row(BsdfRecord b, uint r) {
    uvec4 row = b.table[0];
    row = r == 1u ? b.table[1] : row;
    row = r == 2u ? b.table[2] : row;
    row = r == 3u ? b.table[3] : row;
    row = r == 4u ? b.table[4] : row;
    row = r == 5u ? b.table[5] : row;
    row = r == 6u ? b.table[6] : row;
    row = r == 7u ? b.table[7] : row;
    return row;
}

// Entry i (0..31) of b.table (its 32 bits; principled's scalars are f32 bits).
uint bsdf_table_entry(BsdfRecord b, uint i) {
    uvec4 row = bsdf_table_row(b, i >> 2u);
    uint c = i & 3u;
    return c == 0u ? row.x : c == 1u ? row.y : c == 2u ? row.z : row.w;
}

// Textured table entries (BSDF_TABLE_TEXTURES; principled's scalars, layout in
// src/scene/bsdf/principled.rs): for each bit k of the mask in entry 28, entry k < 16
// of b.table becomes texture id (entry 16 + k, bits) at uv read as a float
// (texture_eval_1, Mitsuba's eval_1). One lookup in a loop; the entry is written
// through constant-indexed selects.
BsdfRecord bsdf_table_textured(BsdfRecord b, vec2 uv) {
    uint pending = b.table[7].x;
    if (pending != 0u) do {
        uint k = uint(findLSB(pending));
        pending &= pending - 1u;
        uint v = floatBitsToUint(texture_eval_1(bsdf_table_entry(b, 16u + k), uv));
        uvec4 row = bsdf_table_row(b, k >> 2u);
        uint c = k & 3u;
        row = uvec4(c == 0u ? v : row.x, c == 1u ? v : row.y, c == 2u ? v : row.z, c == 3u ? v : row.w);
        if (k >> 2u == 0u) b.table[0] = row;
        if (k >> 2u == 1u) b.table[1] = row;
        if (k >> 2u == 2u) b.table[2] = row;
        if (k >> 2u == 3u) b.table[3] = row;
    } while (pending != 0u);
    return b;
}

// Lookup slot K of pending (a constant K: the selects fold away).
#define SURFACE_TEX_ONE(K)                                                               \
    if (surface_tex_used(K) && (pending & (1u << (K))) != 0u) {                          \
        uint id = surface_tex_id(b, emission_texture, K);                                \
        b = surface_tex_store(b, texels, K, id, texture_eval(id, uv));                   \
    }

// The record with every textured parameter replaced by its texture at uv; with
// normal_map, also the texel of the record's normal map, and with emission_texture !=
// 0 (an area emitter's texture id) its texel, in `texels` (left as they were when not
// asked for).
//
// llvmpipe (Mesa 22.3) runs the code of every branch for every SIMD lane, so a call
// per textured parameter costs every lane each parameter's lookup, textured or not.
// Where the scene's points need fewer lookups than it has textured parameters
// (TEXTURE_FEATURE_LOOKUP_LOOP, render::scene_buffers::texture_mask: a floor with a
// textured color beside a metal with a textured roughness and a textured light), the
// lookups run as one texture_eval in a loop, as often as the busiest lane of a SIMD
// group needs; a do-while, since llvmpipe also runs the body of the pass in which a
// while loop finds no lane left. Otherwise (one textured parameter, or every point
// needing all of them) a call per parameter costs less than the loop's bookkeeping.
// A second roughness that names the first one's texture takes its value. Either way
// the values are those of one call per parameter, bit for bit.
BsdfRecord bsdf_textured_point(BsdfRecord b, vec2 uv, bool normal_map, uint emission_texture,
                               inout SurfaceTexels texels) {
    bool bsdf = TEXTURE_USES(TEXTURE_FEATURE_BSDF);
    bool alpha_v_own = b.tex_alpha_v != b.tex_alpha_u;
    uint pending = 0u;
    if (bsdf) {
        pending = (b.tex_reflectance != 0u ? 1u << SURFACE_TEX_REFLECTANCE : 0u)
            | (b.tex_specular != 0u ? 1u << SURFACE_TEX_SPECULAR : 0u)
            | (b.tex_transmittance != 0u ? 1u << SURFACE_TEX_TRANSMITTANCE : 0u)
            | (b.tex_alpha_u != 0u ? 1u << SURFACE_TEX_ALPHA_U : 0u)
            | (b.tex_alpha_v != 0u && alpha_v_own ? 1u << SURFACE_TEX_ALPHA_V : 0u)
            | (b.tex_cond_eta != 0u ? 1u << SURFACE_TEX_COND_ETA : 0u)
            | (b.tex_cond_k != 0u ? 1u << SURFACE_TEX_COND_K : 0u);
        if (SURFACE_TEX_ETA_USED && b.tex_eta != 0u) pending |= 1u << SURFACE_TEX_ETA;
    }
    if (TEXTURE_USES(TEXTURE_FEATURE_AREA) && emission_texture != 0u) {
        pending |= 1u << SURFACE_TEX_EMISSION;
    }
    if (TEXTURE_USES(TEXTURE_FEATURE_LOOKUP_LOOP)) {
        if (pending != 0u) do {
            uint k = uint(findLSB(pending));
            pending &= pending - 1u;
            uint id = surface_tex_id(b, emission_texture, k);
            b = surface_tex_store(b, texels, k, id, texture_eval(id, uv));
        } while (pending != 0u);
    } else {
        SURFACE_TEX_ONE(SURFACE_TEX_REFLECTANCE)
        SURFACE_TEX_ONE(SURFACE_TEX_SPECULAR)
        SURFACE_TEX_ONE(SURFACE_TEX_TRANSMITTANCE)
        SURFACE_TEX_ONE(SURFACE_TEX_ALPHA_U)
        SURFACE_TEX_ONE(SURFACE_TEX_ALPHA_V)
        SURFACE_TEX_ONE(SURFACE_TEX_EMISSION)
        SURFACE_TEX_ONE(SURFACE_TEX_COND_ETA)
        SURFACE_TEX_ONE(SURFACE_TEX_COND_K)
        SURFACE_TEX_ONE(SURFACE_TEX_ETA)
    }
    if (bsdf) {
        if (b.tex_alpha_v != 0u && !alpha_v_own) b.alpha_v = b.alpha_u;
        if (TEXTURE_USES(TEXTURE_FEATURE_TABLE) && (b.flags & BSDF_TABLE_TEXTURES) != 0u) {
            b = bsdf_table_textured(b, uv);
        }
#ifdef BSDF_DISPATCH_GLSL
        // What models derive from textured parameters (their `textured` hooks). A
        // kernel without bsdf.glsl (shadow) evaluates no model, so needs none.
        b = bsdf_kind_textured(b);
#endif
    }
    if (normal_map && TEXTURE_USES(TEXTURE_FEATURE_NORMALMAP) && b.normal_map != 0u) {
        texels.normal = texture_eval(b.normal_map, uv);
    }
    return b;
}

// The record with every textured parameter replaced by its texture at uv.
BsdfRecord bsdf_textured(BsdfRecord b, vec2 uv) {
    if (!TEXTURE_USES(TEXTURE_FEATURE_BSDF)) return b;
    SurfaceTexels unused = SurfaceTexels(vec3(0.0), vec3(0.0));
    return bsdf_textured_point(b, uv, false, 0u, unused);
}

#endif
