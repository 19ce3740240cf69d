// Mitsuba's irradiancemeter (scene::sensor::irradiancemeter): a ray from a uniform
// point of the shape the sensor is nested in, in a cosine-weighted direction about the
// normal there; the sample's weight is π (the caller's). The shape's record sits after
// the emitters' (render::scene_buffers: sensor_shape), at frame.emitter_count, and its
// points are drawn as an area emitter's on it are (emitter_area_point).
// Needs emitter.glsl (EMITTER_KINDS with the shape's bit: SceneRecords::emitter_kinds).
#ifndef SENSOR_IRRADIANCEMETER_GLSL
#define SENSOR_IRRADIANCEMETER_GLSL

// u_pos: the position sample (Mitsuba's sample2: the film position over the film's
// size, in [0, 1)²), u_dir: the direction sample (Mitsuba's aperture sample3).
void irradiancemeter_ray(vec2 u_pos, vec2 u_dir, out vec3 origin, out vec3 dir, out float tmax) {
    Surface s = emitter_area_point(emitter_load(frame.emitter_count), u_pos);
    dir = frame_to_world(s.ng, warp_cosine_hemisphere(u_dir));
    origin = surface_spawn_origin(s, s.ng);
    tmax = EMITTER_INFINITY;
}

#endif
