// The film (descriptor set 3, mirrored in src/render/film.rs): the per-pixel sums of
// the crop window and the ring of samples they are gathered from.
//
// accumulate puts every finished path's sample into a slot of the ring: its value,
// its position in its pixel and its flags, in one 16-byte texel. film_gather then
// sums, for each kept pixel, the filter-weighted samples of the pixels around it,
// once all of them are in the ring. The ring keeps the samples of the previous batch
// that a later pixel still needs (the filter's reach in rows), so a pixel's sums
// never depend on where batches begin and end.
//
// Needs wavefront.glsl (push constants).
#ifndef FILM_GLSL
#define FILM_GLSL

#include "scene/layout.glsl"
#include "film/divide.glsl"
#include "film/sample_offset.glsl"

layout(std140, set = 3, binding = 0) uniform FilmBlock { FilmParams film; };
// Per crop pixel, row-major: (Σ w r, Σ w g, Σ w b, Σ w) over the samples w weighs.
layout(std430, set = 3, binding = 1) buffer FilmSumBuffer { vec4 film_sums[]; };
// Per crop pixel: Σ w over the covered samples (the alpha channel's numerator).
layout(std430, set = 3, binding = 2) buffer FilmAlphaBuffer { float film_alpha_sums[]; };
// The sample ring, one texel a slot: (r, g, b, position and flags, film_sample_pack).
// Written here, read through the texel view (one gather per neighbour on llvmpipe).
layout(std430, set = 3, binding = 3) writeonly buffer FilmSampleBuffer { uvec4 film_sample_words[]; };
layout(set = 3, binding = 4, rgba32ui) uniform readonly uimageBuffer film_sample_texels;

// The ring slot of path p of this batch.
uint film_slot(uint p) { return (push.sample_slot + p) % film.slots; }

// Pixel i of the sampled region (row-major), in film coordinates.
ivec2 film_region_pixel(uint i) {
    uvec2 qr = divide(i, film.region_width);
    return ivec2(film.region_x + int(qr.y), film.region_y + int(qr.x));
}

// The key a pixel's random numbers are drawn with: its index in the full film (with
// its sampled border), whatever part of it is rendered, so that a crop window draws
// the numbers of the full render.
uint film_pixel_key(ivec2 pixel) {
    return uint(pixel.y - film.key_y) * film.key_width + uint(pixel.x - film.key_x);
}

// A sample's fourth word: its position cells (film_position_cells) in bits 0-14 and
// 15-29, its FILM_SAMPLE_* flags in bits 30-31.
uint film_sample_pack(uvec2 cells, uint flags) {
    return cells.x | (cells.y << FILM_POSITION_BITS) | (flags << (2u * FILM_POSITION_BITS));
}

void film_store_sample(uint slot, vec3 value, uvec2 cells, uint flags) {
    film_sample_words[slot] = uvec4(floatBitsToUint(value), film_sample_pack(cells, flags));
}

struct FilmSample {
    vec3 value;
    uint flags;
    vec2 offset; // position inside its pixel, in (0, 1)²
};

FilmSample film_sample_load(uint slot) {
    uvec4 t = imageLoad(film_sample_texels, int(slot));
    uint mask = (1u << FILM_POSITION_BITS) - 1u;
    uvec2 cells = uvec2(t.w & mask, (t.w >> FILM_POSITION_BITS) & mask);
    return FilmSample(uintBitsToFloat(t.xyz), t.w >> (2u * FILM_POSITION_BITS),
                      film_position_from_cells(cells));
}

#endif
