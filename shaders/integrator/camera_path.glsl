// The start of a batch's camera path: path p is sample (pixel_base + p) of the film's
// sampled pixels, sample after sample (film/film.glsl). Used by generate and
// first_bounce. Needs wavefront.glsl, film/film.glsl and camera.glsl, and where
// SENSOR_ON_SHAPE may be true (a specialization constant: a scene with an
// irradiancemeter) emitter.glsl.
#ifndef CAMERA_PATH_GLSL
#define CAMERA_PATH_GLSL

#ifndef SENSOR_ON_SHAPE
#define SENSOR_ON_SHAPE false
#else
#include "sensor/irradiancemeter.glsl"
#endif

// Path p's state before its first vertex, and its camera ray.
void camera_path_start(uint p, out PathState path, out RayItem r) {
    uint pixels = film.region_width * film.region_height;
    uvec2 qr = divide(push.pixel_base + p, pixels);
    ivec2 pixel = film_region_pixel(qr.y);
    uint sample_index = push.sample_base + qr.x;
    uint key = film_pixel_key(pixel);

    vec3 origin, dir;
    float tmax;
    vec2 u_lens = (frame.camera_kind == CAMERA_THINLENS || frame.camera_kind == CAMERA_DISTANT
                   || (SENSOR_ON_SHAPE && frame.camera_kind == CAMERA_IRRADIANCEMETER))
        ? sample_2d(key, sample_index, RNG_DIM_APERTURE) : vec2(0.0);
    vec2 film_pos = vec2(pixel) + film_sample_position(key, sample_index);
    float weight = 1.0;
#ifdef SENSOR_IRRADIANCEMETER_GLSL
    if (SENSOR_ON_SHAPE && frame.camera_kind == CAMERA_IRRADIANCEMETER) {
        vec2 u_pos = clamp(film_pos / vec2(frame.width, frame.height), vec2(0.0), vec2(0.99999994));
        irradiancemeter_ray(u_pos, u_lens, origin, dir, tmax);
        weight = PI;
    } else {
        camera_ray(film_pos, u_lens, origin, dir, tmax);
    }
#else
    camera_ray(film_pos, u_lens, origin, dir, tmax);
#endif

    uint flags = PATH_DELTA | (film.coverage != 0u ? PATH_COVERED : 0u);
    path = PathState(vec3(weight), key, vec3(0.0), sample_index, 0.0, flags, 1.0, frame.camera_medium);
    r = RayItem(origin, p, dir, tmax);
}

#endif
