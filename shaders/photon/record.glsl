// Loading and storing the photon mappers' records: photons (photon buffer and the
// grid's sorted copy), photon paths (in the wavefront's path-state buffer) and visible
// points. Needs wavefront.glsl and bindings.glsl.
#ifndef PHOTON_RECORD_GLSL
#define PHOTON_RECORD_GLSL

// A unit vector in 32 bits: octahedral map to two snorm16 (Cigolle, Donow, Evangelakos,
// Mara, McGuire, Meyer 2014, "A Survey of Efficient Representations for Independent
// Unit Vectors", JCGT 3(2), listings 1-2); angular error below 1e-4 radians.
vec2 photon_sign_not_zero(vec2 v) { return vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0); }

uint photon_dir_encode(vec3 d) {
    vec2 p = d.xy / (abs(d.x) + abs(d.y) + abs(d.z));
    if (d.z < 0.0) p = (1.0 - abs(p.yx)) * photon_sign_not_zero(p);
    return packSnorm2x16(p);
}

vec3 photon_dir_decode(uint e) {
    vec2 p = unpackSnorm2x16(e);
    vec3 d = vec3(p, 1.0 - abs(p.x) - abs(p.y));
    if (d.z < 0.0) d.xy = (1.0 - abs(d.yx)) * photon_sign_not_zero(d.xy);
    return normalize(d);
}

// Loads through the texel views, stores through the word buffers, a texel of the
// record at a time (generated: generated/records.glsl). A photon path takes 2 words of
// path slot i (the slot of a camera path's 3).
uvec4 photon_texel(uint k) { return imageLoad(photon_texels, int(k)); }
uvec4 grid_photon_texel(uint k) { return imageLoad(grid_photon_texels, int(k)); }
uvec4 vp_texel(uint k) { return imageLoad(vp_texels, int(k)); }
void photon_word_store(uint k, uvec4 w) { photon_words[k] = w; }
void grid_photon_word_store(uint k, uvec4 w) { grid_photon_words[k] = w; }
void vp_word_store(uint k, uvec4 w) { vp_words[k] = w; }
Photon_LOAD(photon_load, photon_texel)
Photon_STORE(photon_store, photon_word_store)
Photon_LOAD(grid_photon_load, grid_photon_texel)
Photon_STORE(grid_photon_store, grid_photon_word_store)
PhotonPath_LOAD(photon_path_load, path_texel)
PhotonPath_STORE(photon_path_store, path_word_store)
VisiblePoint_LOAD(vp_load, vp_texel)
VisiblePoint_STORE(vp_store, vp_word_store)

// Only the first word: whether slot i holds a visible point (bsdf != NONE).
uint vp_bsdf(uint i) { return vp_texel(VisiblePoint_TEXELS * i).w; }

#endif
