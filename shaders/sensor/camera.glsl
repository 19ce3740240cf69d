// The pinhole perspective camera. Needs wavefront.glsl (for `frame`).
#ifndef CAMERA_GLSL
#define CAMERA_GLSL

// Primary ray through film position `film_pos` (pixels, origin top-left). Camera space
// as in Mitsuba and Nori: looking down +z, +y up, +x to the left of the image. The ray
// starts on the near plane and ends on the far plane (Mitsuba's near_clip/far_clip).
void camera_ray(vec2 film_pos, out vec3 origin, out vec3 dir, out float tmax) {
    vec2 ndc = film_pos / vec2(frame.width, frame.height);
    vec3 d = vec3((1.0 - 2.0 * ndc.x) * frame.tan_half_fov.x,
                  (1.0 - 2.0 * ndc.y) * frame.tan_half_fov.y,
                  1.0);
    vec3 p_near = (frame.camera_to_world * vec4(d * frame.near_clip, 1.0)).xyz;
    vec3 p_far = (frame.camera_to_world * vec4(d * frame.far_clip, 1.0)).xyz;
    vec3 span = p_far - p_near;
    tmax = length(span);
    origin = p_near;
    dir = span / tmax;
}

#endif
