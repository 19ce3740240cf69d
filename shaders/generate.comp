#version 460
#extension GL_GOOGLE_include_directive : require
// generate: one camera ray per path slot of the batch. Path p is sample
// (pixel_base + p) of the film's sampled pixels, sample after sample
// (film/film.glsl). Writes: paths[p], ray queue 0 item p. The host sets
// ray_count[0] = path_count.

#include "wavefront.glsl"
// The sampler kind (SAMPLER_*): the other kinds compile away.
layout(constant_id = 0) const uint SCENE_SAMPLER_KIND = 0u;
#define SAMPLER_KIND SCENE_SAMPLER_KIND
#include "film/film.glsl"
#include "camera.glsl"

void main() {
    uint p = thread_index();
    if (p >= push.path_count) return;
    uint pixels = film.region_width * film.region_height;
    uvec2 qr = divide(push.pixel_base + p, pixels);
    ivec2 pixel = film_region_pixel(qr.y);
    uint sample_index = push.sample_base + qr.x;
    uint key = film_pixel_key(pixel);

    vec3 origin, dir;
    float tmax;
    camera_ray(vec2(pixel) + film_sample_position(key, sample_index), origin, dir, tmax);

    uint flags = PATH_DELTA | (film.coverage != 0u ? PATH_COVERED : 0u);
    path_store(p, PathState(vec3(1.0), key, vec3(0.0), sample_index, 0.0, flags, 1.0, frame.camera_medium));
    ray_store(ray_slot_at(0u, p), RayItem(origin, p, dir, tmax));
}
