// The start of a batch's camera path: path p is sample (pixel_base + p) of the film's
// sampled pixels, sample after sample (film/film.glsl). Used by generate and
// first_bounce. Needs wavefront.glsl, film/film.glsl and what sensor/sensor_ray.glsl
// needs.
#ifndef CAMERA_PATH_GLSL
#define CAMERA_PATH_GLSL

#include "sensor/sensor_ray.glsl"

// Path p's state before its first vertex, and its camera ray.
void camera_path_start(uint p, out PathState path, out RayItem r) {
    uint pixels = film.region_width * film.region_height;
    uvec2 qr = divide(push.pixel_base + p, pixels);
    ivec2 pixel = film_region_pixel(qr.y);
    uint sample_index = push.sample_base + qr.x;
    uint key = film_pixel_key(pixel);

    vec3 origin, dir;
    float tmax;
    vec2 film_pos = vec2(pixel) + film_sample_position(key, sample_index);
    float weight = sensor_ray(film_pos, key, sample_index, origin, dir, tmax);

    uint flags = PATH_DELTA | (film.coverage != 0u ? PATH_COVERED : 0u);
    path = PathState(vec3(weight), key, vec3(0.0), sample_index, 0.0, flags, 1.0, frame.camera_medium);
    r = RayItem(origin, p, dir, tmax);
}

#endif
