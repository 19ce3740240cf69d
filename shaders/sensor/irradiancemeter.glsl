// Mitsuba's irradiancemeter (scene::sensor::irradiancemeter): a ray from a uniform
// point of the shape the sensor is nested in, in a cosine-weighted direction about the
// normal there; the sample's weight is π (the caller's). The shape's record sits after
// the emitters' (render::scene_buffers: sensor_shape), at frame.emitter_count, and its
// points are drawn as an area emitter's on it are (emitter_area_point).
// Needs emitter.glsl (EMITTER_KINDS with the shape's bit: SceneRecords::emitter_kinds).
#ifndef SENSOR_IRRADIANCEMETER_GLSL
#define SENSOR_IRRADIANCEMETER_GLSL

// The uniform point of the meter's shape for the 2-D sample u (area density 1 / A).
Surface irradiancemeter_point(vec2 u) {
    return emitter_area_point(emitter_load(frame.emitter_count), u);
}

// u_pos: the position sample (Mitsuba's sample2: the film position over the film's
// size, in [0, 1)²), u_dir: the direction sample (Mitsuba's aperture sample3).
void irradiancemeter_ray(vec2 u_pos, vec2 u_dir, out vec3 origin, out vec3 dir, out float tmax) {
    Surface s = irradiancemeter_point(u_pos);
    dir = frame_to_world(s.ng, warp_cosine_hemisphere(u_dir));
    origin = surface_spawn_origin(s, s.ng);
    tmax = EMITTER_INFINITY;
}

// The particle tracer's connection of a light-path point p to the meter (Mitsuba's
// IrradianceMeter::sample_direction): x, the point irradiancemeter_point draws from u
// (area density 1 / A), as irradiancemeter_ray draws its origins. The meter measures
// (1/A) ∫∫ L cos θx dω dA, an importance W = 1 / A per unit area and projected solid
// angle, so p's light reaches it weighted by W cos θx / (d² p_A(x)) = cos θx / d²
// (d = |p - x|, θx from x's normal, on the side irradiancemeter_ray's hemisphere
// faces; 0 behind), which this returns. Mitsuba 3.9.1 weighs every connection by π
// whatever d and θx, so its ptracer's irradiancemeter is not the irradiance its path
// tracer measures (7.4 times it in tests/ptracer.rs); this is that irradiance.
float irradiancemeter_importance(vec3 p, vec2 u, out Surface x) {
    x = irradiancemeter_point(u);
    vec3 v = p - x.p;
    float d2 = dot(v, v);
    float cos_x = dot(x.ng, v) * inversesqrt(d2);
    return cos_x > 0.0 ? cos_x / d2 : 0.0;
}

// The same for light arriving along -d from infinitely far (an environment): per unit
// solid angle, W cos θx / p_A(x) = cos θx (0 behind).
float irradiancemeter_direction_importance(vec3 d, vec2 u, out Surface x) {
    x = irradiancemeter_point(u);
    return max(dot(x.ng, d), 0.0);
}

#endif
