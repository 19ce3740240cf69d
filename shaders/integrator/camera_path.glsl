// The start of a batch's camera path: path p is sample (pixel_base + p) of the film's
// sampled pixels, sample after sample (film/film.glsl). Used by generate and
// first_bounce. Needs wavefront.glsl, film/film.glsl and camera.glsl, and where
// SENSOR_ON_SHAPE may be true (a specialization constant: a scene with an
// irradiancemeter) emitter.glsl.
#ifndef CAMERA_PATH_GLSL
#define CAMERA_PATH_GLSL

#ifndef SENSOR_BATCH
#define SENSOR_BATCH 0u
#endif

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
    // A batch sensor (SENSOR_BATCH children side by side): the child of the film
    // column, at its own film position (Mitsuba's BatchSensor::sample_ray).
    vec2 film_pos = vec2(pixel) + film_sample_position(key, sample_index);
    uint child = 0u;
    uint child_kind = frame.camera_kind;
    float child_x = 0.0;
    if (SENSOR_BATCH > 1u) {
        // x n / width = idx_f; child min(uint(idx_f), n - 1) at idx_f - uint(idx_f), as
        // Mitsuba's (a filter's border samples right of the film wrap to the last
        // child's left edge there too; left of it, idx_f < 0 stays in child 0).
        float idx_f = film_pos.x * float(SENSOR_BATCH) / float(frame.width);
        uint idx_u = uint(max(idx_f, 0.0));
        child = min(idx_u, SENSOR_BATCH - 1u);
        child_kind = frame.batch_lens[child].x;
        child_x = idx_f - float(idx_u);
    }
    vec2 u_lens = (child_kind == CAMERA_THINLENS || frame.camera_kind == CAMERA_DISTANT
                   || (SENSOR_ON_SHAPE && frame.camera_kind == CAMERA_IRRADIANCEMETER))
        ? sample_2d(key, sample_index, RNG_DIM_APERTURE) : vec2(0.0);
    float weight = 1.0;
    if (SENSOR_BATCH > 1u) {
        float w = float(frame.width / SENSOR_BATCH);
        vec2 ndc = vec2(child_x, film_pos.y / float(frame.height));
        camera_ray_projective(mat4(frame.batch_to_world[4u * child], frame.batch_to_world[4u * child + 1u],
                                   frame.batch_to_world[4u * child + 2u], frame.batch_to_world[4u * child + 3u]),
                              frame.batch_view[child].xy, frame.batch_view[child].z, frame.batch_view[child].w,
                              child_kind, uintBitsToFloat(frame.batch_lens[child].y),
                              uintBitsToFloat(frame.batch_lens[child].z), float(frame.height) / w,
                              ndc, u_lens, origin, dir, tmax);
    } else
#ifdef SENSOR_IRRADIANCEMETER_GLSL
    if (SENSOR_ON_SHAPE && frame.camera_kind == CAMERA_IRRADIANCEMETER) {
        vec2 u_pos = clamp(film_pos / vec2(frame.width, frame.height), vec2(0.0), vec2(0.99999994));
        irradiancemeter_ray(u_pos, u_lens, origin, dir, tmax);
        weight = PI;
    } else {
        camera_ray(film_pos, u_lens, origin, dir, tmax);
    }
#else
    {
        camera_ray(film_pos, u_lens, origin, dir, tmax);
    }
#endif

    uint flags = PATH_DELTA | (film.coverage != 0u ? PATH_COVERED : 0u);
    path = PathState(vec3(weight), key, vec3(0.0), sample_index, 0.0, flags, 1.0, frame.camera_medium);
    r = RayItem(origin, p, dir, tmax);
}

#endif
