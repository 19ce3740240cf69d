// Where inside its pixel a camera sample lies. Needs wavefront.glsl (`frame`).
#ifndef FILM_SAMPLE_OFFSET_GLSL
#define FILM_SAMPLE_OFFSET_GLSL

#include "numeric/convert.glsl"
#include "sampling/rng.glsl"
#include "sampler/sampler_frame.glsl"

// The film position of sample `sample_index` of the pixel with key `pixel` (see
// film_pixel_key in film/film.glsl), relative to the pixel's top-left corner, in
// [0, 1)², as the sampler draws it: the camera's sampler dimension, RNG_DIM_CAMERA
// (rng.glsl). Use film_sample_position, which both the camera (generate) and the film
// (accumulate) call; both define SAMPLER_KIND alike (sampler/sampler.glsl).
vec2 film_sample_offset(uint pixel, uint sample_index) {
    return sample_2d(pixel, sample_index, RNG_DIM_CAMERA);
}

// Film positions are kept to 1/32768 of a pixel: two 15-bit cells fit beside a
// sample's flags in the word the film stores it with, so the gather reads one texel
// per sample. The camera ray goes through the centre of that cell, exactly where the
// filter weighs the sample.
#define FILM_POSITION_BITS 15u
#define FILM_POSITION_CELLS 32768.0

uvec2 film_position_cells(vec2 offset) {
    uvec2 cells = uvec2(floor_to_uint(offset.x * FILM_POSITION_CELLS),
                        floor_to_uint(offset.y * FILM_POSITION_CELLS));
    return min(cells, uvec2((1u << FILM_POSITION_BITS) - 1u));
}

vec2 film_position_from_cells(uvec2 cells) {
    return (vec2(cells) + 0.5) / FILM_POSITION_CELLS;
}

// The cells of sample `sample_index` of the pixel with key `pixel`.
uvec2 film_sample_cells(uint pixel, uint sample_index) {
    return film_position_cells(film_sample_offset(pixel, sample_index));
}

// Where sample `sample_index` of the pixel with key `pixel` lies in it, in (0, 1)².
vec2 film_sample_position(uint pixel, uint sample_index) {
    return film_position_from_cells(film_sample_cells(pixel, sample_index));
}

#endif
