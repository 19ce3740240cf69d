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

// Photon: 2 words.
Photon photon_from_words(uvec4 w0, uvec4 w1) {
    return Photon(uintBitsToFloat(w0.xyz), w0.w, uintBitsToFloat(w1.xyz), w1.w);
}

Photon photon_load(uint i) {
    return photon_from_words(imageLoad(photon_texels, int(2u * i)), imageLoad(photon_texels, int(2u * i + 1u)));
}

void photon_store(uint i, Photon p) {
    photon_words[2u * i] = uvec4(floatBitsToUint(p.position), p.path);
    photon_words[2u * i + 1u] = uvec4(floatBitsToUint(p.power), p.wi);
}

Photon grid_photon_load(uint i) {
    return photon_from_words(imageLoad(grid_photon_texels, int(2u * i)),
                             imageLoad(grid_photon_texels, int(2u * i + 1u)));
}

void grid_photon_store(uint i, Photon p) {
    grid_photon_words[2u * i] = uvec4(floatBitsToUint(p.position), p.path);
    grid_photon_words[2u * i + 1u] = uvec4(floatBitsToUint(p.power), p.wi);
}

// PhotonPath: 2 words of path slot i (the slot of a camera path's 3).
PhotonPath photon_path_load(uint i) {
    uvec4 w0 = imageLoad(path_texels, int(2u * i));
    uvec4 w1 = imageLoad(path_texels, int(2u * i + 1u));
    return PhotonPath(uintBitsToFloat(w0.xyz), w0.w, uintBitsToFloat(w1.x), w1.y, w1.z, w1.w);
}

void photon_path_store(uint i, PhotonPath p) {
    path_words[2u * i] = wavefront_word(uvec4(floatBitsToUint(p.power), p.index));
    path_words[2u * i + 1u] = wavefront_word(uvec4(floatBitsToUint(p.start_power), p.stored, p.pad0, p.pad1));
}

// VisiblePoint: 5 words.
VisiblePoint vp_load(uint i) {
    int b = int(5u * i);
    uvec4 w0 = imageLoad(vp_texels, b);
    uvec4 w1 = imageLoad(vp_texels, b + 1);
    uvec4 w2 = imageLoad(vp_texels, b + 2);
    uvec4 w3 = imageLoad(vp_texels, b + 3);
    uvec4 w4 = imageLoad(vp_texels, b + 4);
    return VisiblePoint(uintBitsToFloat(w0.xyz), w0.w, uintBitsToFloat(w1.xyz), uintBitsToFloat(w1.w),
                        uintBitsToFloat(w2.xyz), uintBitsToFloat(w2.w), uintBitsToFloat(w3.xyz),
                        uintBitsToFloat(w3.w), uintBitsToFloat(w4.xyz), w4.w);
}

// Only the first word: whether slot i holds a visible point (bsdf != NONE).
uint vp_bsdf(uint i) { return imageLoad(vp_texels, int(5u * i)).w; }

void vp_store(uint i, VisiblePoint v) {
    vp_words[5u * i] = uvec4(floatBitsToUint(v.p), v.bsdf);
    vp_words[5u * i + 1u] = uvec4(floatBitsToUint(v.wo), floatBitsToUint(v.u));
    vp_words[5u * i + 2u] = uvec4(floatBitsToUint(v.n), floatBitsToUint(v.v));
    vp_words[5u * i + 3u] = uvec4(floatBitsToUint(v.beta), floatBitsToUint(v.alpha2));
    vp_words[5u * i + 4u] = uvec4(floatBitsToUint(v.n0), v.flags);
}

#endif
