#version 460
#extension GL_GOOGLE_include_directive : require
// generate: one camera ray per path slot of the batch.
// Writes: paths[p], ray queue 0 item p. The host sets ray_count[0] = path_count.

#include "wavefront.glsl"
// The sampler kind (SAMPLER_*): the other kinds compile away.
layout(constant_id = 0) const uint SCENE_SAMPLER_KIND = 0u;
#define SAMPLER_KIND SCENE_SAMPLER_KIND
#include "sampler/sampler_frame.glsl"
#include "camera.glsl"

void main() {
    uint p = thread_index();
    if (p >= push.path_count) return;
    uint pixels = frame.width * frame.height;
    uint g = push.pixel_base + p;
    uint pixel = g % pixels;
    uint sample_index = push.sample_base + g / pixels;

    // Box filter: a uniform position inside the pixel.
    vec2 jitter = sample_2d(pixel, sample_index, RNG_DIM_CAMERA);
    vec2 film_pos = vec2(pixel % frame.width, pixel / frame.width) + jitter;
    vec3 origin, dir;
    float tmax;
    camera_ray(film_pos, origin, dir, tmax);

    path_store(p, PathState(vec3(1.0), pixel, vec3(0.0), sample_index, 0.0, PATH_DELTA, 1.0, frame.camera_medium));
    ray_store(ray_slot(0u, p), RayItem(origin, p, dir, tmax));
}
