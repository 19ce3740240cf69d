// The scene's sensor's ray for a film position: a batch sensor's child of the film
// column (SENSOR_BATCH children side by side), an irradiancemeter's ray from its
// shape (SENSOR_ON_SHAPE), else the one camera's (camera.glsl). What a camera path
// starts with (integrator/camera_path.glsl) and what the AOVs are traced along
// (kernels/aov.comp), so both see the same rays. Needs frame (scene_bindings.glsl),
// camera.glsl, sampling (sample_2d) and, where SENSOR_ON_SHAPE may be true (a
// specialization constant: a scene with an irradiancemeter), emitter.glsl.
#ifndef SENSOR_RAY_GLSL
#define SENSOR_RAY_GLSL

#ifndef SENSOR_BATCH
#define SENSOR_BATCH 0u
#endif

#ifndef SENSOR_ON_SHAPE
#define SENSOR_ON_SHAPE false
#else
#include "sensor/irradiancemeter.glsl"
#endif
#include "numeric/convert.glsl"

// The aperture sample of sample `sample_index` of the pixel with key `key` through a
// camera of kind `kind` (a batch child's, else frame.camera_kind): a thin lens's and
// a distant sensor's (its point on the target), an irradiancemeter's direction; none
// for the others.
vec2 sensor_lens_sample(uint kind, uint key, uint sample_index) {
    bool lens = kind == CAMERA_THINLENS || frame.camera_kind == CAMERA_DISTANT
        || (SENSOR_ON_SHAPE && frame.camera_kind == CAMERA_IRRADIANCEMETER);
    return lens ? sample_2d(key, sample_index, RNG_DIM_APERTURE) : vec2(0.0);
}

// The ray of sample `sample_index` of the pixel with key `key` at film position
// `film_pos` (pixels); returns the sample's weight (π for an irradiancemeter, else 1).
float sensor_ray(vec2 film_pos, uint key, uint sample_index, out vec3 origin, out vec3 dir,
                 out float tmax) {
    // A batch sensor: the child of the film column, at its own film position
    // (Mitsuba's BatchSensor::sample_ray).
    uint child = 0u;
    uint child_kind = frame.camera_kind;
    float child_x = 0.0;
    if (SENSOR_BATCH > 1u) {
        // x n / width = idx_f; child min(uint(idx_f), n - 1) at idx_f - uint(idx_f), as
        // Mitsuba's (a filter's border samples right of the film wrap to the last
        // child's left edge there too; left of it, idx_f < 0 stays in child 0).
        float idx_f = film_pos.x * float(SENSOR_BATCH) / float(frame.width);
        uint idx_u = floor_to_uint(max(idx_f, 0.0));
        child = min(idx_u, SENSOR_BATCH - 1u);
        child_kind = frame.batch_lens[child].x;
        child_x = idx_f - float(idx_u);
    }
    vec2 u_lens = sensor_lens_sample(child_kind, key, sample_index);
    if (SENSOR_BATCH > 1u) {
        float w = float(frame.width / SENSOR_BATCH);
        vec2 ndc = vec2(child_x, film_pos.y / float(frame.height));
        camera_ray_projective(mat4(frame.batch_to_world[4u * child], frame.batch_to_world[4u * child + 1u],
                                   frame.batch_to_world[4u * child + 2u], frame.batch_to_world[4u * child + 3u]),
                              frame.batch_view[child].xy, frame.batch_view[child].z, frame.batch_view[child].w,
                              child_kind, uintBitsToFloat(frame.batch_lens[child].y),
                              uintBitsToFloat(frame.batch_lens[child].z), float(frame.height) / w,
                              ndc, u_lens, origin, dir, tmax);
        return 1.0;
    }
#ifdef SENSOR_IRRADIANCEMETER_GLSL
    if (SENSOR_ON_SHAPE && frame.camera_kind == CAMERA_IRRADIANCEMETER) {
        vec2 u_pos = clamp(film_pos / vec2(frame.width, frame.height), vec2(0.0), vec2(0.99999994));
        irradiancemeter_ray(u_pos, u_lens, origin, dir, tmax);
        return PI;
    }
#endif
    camera_ray(film_pos, u_lens, origin, dir, tmax);
    return 1.0;
}

#endif
