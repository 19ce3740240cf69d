// The camera: a pinhole (perspective), orthographic, thin-lens camera or radiance meter, by
// frame.camera_kind (scene::Projection). Needs wavefront.glsl (for `frame`).
#ifndef CAMERA_GLSL
#define CAMERA_GLSL

#include "sensor/thinlens.glsl"

// Primary ray through film position `film_pos` (pixels, origin top-left); u_lens, the
// aperture sample, is read by the thin lens only. Camera space as in Mitsuba and Nori:
// looking down +z, +y up, +x to the left of the image. The ray starts on the near
// plane and ends on the far plane (Mitsuba's near_clip/far_clip).
// A projective camera (perspective, orthographic or thin lens: `kind`; or a
// radiancemeter, which reads only to_world and far_clip) with the given parameters, at `ndc` in [0, 1]^2 of its film of height / width `aspect`: camera_ray's
// code for these kinds, for the children of a batch sensor (camera_path.glsl).
void camera_ray_projective(mat4 to_world, vec2 tan_half_fov, float near_clip, float far_clip,
                           uint kind, float aperture_radius, float focus_distance, float aspect,
                           vec2 ndc, vec2 u_lens, out vec3 origin, out vec3 dir, out float tmax) {
    if (kind == CAMERA_RADIANCEMETER) {
        // A radiancemeter child: camera_ray's, whatever the film position.
        vec3 d = mat3(to_world) * vec3(0.0, 0.0, 1.0);
        origin = to_world[3].xyz + 1e-4 * d;
        dir = normalize(d);
        tmax = far_clip;
        return;
    }
    if (kind == CAMERA_ORTHOGRAPHIC) {
        vec3 p = vec3(1.0 - 2.0 * ndc.x, (1.0 - 2.0 * ndc.y) * aspect, near_clip);
        origin = (to_world * vec4(p, 1.0)).xyz;
        dir = normalize(mat3(to_world) * vec3(0.0, 0.0, 1.0));
        tmax = far_clip - near_clip;
        return;
    }
    vec3 d = vec3((1.0 - 2.0 * ndc.x) * tan_half_fov.x, (1.0 - 2.0 * ndc.y) * tan_half_fov.y, 1.0);
    if (kind == CAMERA_THINLENS) {
        vec3 a = vec3(aperture_radius * camera_thinlens_aperture(u_lens), 0.0);
        vec3 dl = normalize(d * focus_distance - a);
        float near_t = near_clip / dl.z;
        float far_t = far_clip / dl.z;
        origin = (to_world * vec4(a + dl * near_t, 1.0)).xyz;
        dir = normalize(mat3(to_world) * dl);
        tmax = far_t - near_t;
        return;
    }
    vec3 p_near = (to_world * vec4(d * near_clip, 1.0)).xyz;
    vec3 p_far = (to_world * vec4(d * far_clip, 1.0)).xyz;
    vec3 span = p_far - p_near;
    tmax = length(span);
    origin = p_near;
    dir = span / tmax;
}

void camera_ray(vec2 film_pos, vec2 u_lens, out vec3 origin, out vec3 dir, out float tmax) {
    vec2 ndc = film_pos / vec2(frame.width, frame.height);
    if (frame.camera_kind == CAMERA_ORTHOGRAPHIC) {
        // Mitsuba's orthographic: the film spans x in [-1, 1], y in [-1/a, 1/a] (a the
        // aspect ratio) on the near plane, before to_world; rays along its +z.
        vec3 p = vec3(1.0 - 2.0 * ndc.x, (1.0 - 2.0 * ndc.y) * float(frame.height) / float(frame.width),
                      frame.near_clip);
        origin = (frame.camera_to_world * vec4(p, 1.0)).xyz;
        dir = normalize(mat3(frame.camera_to_world) * vec3(0.0, 0.0, 1.0));
        tmax = frame.far_clip - frame.near_clip;
        return;
    }
    if (frame.camera_kind == CAMERA_RADIANCEMETER) {
        // Mitsuba's radiancemeter: one unbounded ray along to_world's +z, its origin
        // moved by Mitsuba's ray epsilon along it.
        vec3 d = mat3(frame.camera_to_world) * vec3(0.0, 0.0, 1.0);
        origin = frame.camera_to_world[3].xyz + 1e-4 * d;
        dir = normalize(d);
        tmax = frame.far_clip;
        return;
    }
    if (frame.camera_kind == CAMERA_DISTANT) {
        // Mitsuba's distant: from a uniform point of the bounding sphere's cross-section
        // (or the target), a sphere radius behind it; camera_to_world holds both
        // (scene::Projection::distant_frame).
        origin = (frame.camera_to_world * vec4(warp_square_to_disk(u_lens), -1.0, 1.0)).xyz;
        dir = normalize(mat3(frame.camera_to_world) * vec3(0.0, 0.0, 1.0));
        tmax = frame.far_clip;
        return;
    }
    vec3 d = vec3((1.0 - 2.0 * ndc.x) * frame.tan_half_fov.x,
                  (1.0 - 2.0 * ndc.y) * frame.tan_half_fov.y,
                  1.0);
    if (frame.camera_kind == CAMERA_THINLENS) {
        // Mitsuba's thinlens sample_ray: from a point of the aperture through the point
        // the pinhole ray meets at the focus distance; the interval cut at the planes
        // z = near and z = far.
        vec3 a = vec3(frame.aperture_radius * camera_thinlens_aperture(u_lens), 0.0);
        vec3 dl = normalize(d * frame.focus_distance - a);
        float near_t = frame.near_clip / dl.z;
        float far_t = frame.far_clip / dl.z;
        origin = (frame.camera_to_world * vec4(a + dl * near_t, 1.0)).xyz;
        dir = normalize(mat3(frame.camera_to_world) * dl);
        tmax = far_t - near_t;
        return;
    }
    vec3 p_near = (frame.camera_to_world * vec4(d * frame.near_clip, 1.0)).xyz;
    vec3 p_far = (frame.camera_to_world * vec4(d * frame.far_clip, 1.0)).xyz;
    vec3 span = p_far - p_near;
    tmax = length(span);
    origin = p_near;
    dir = span / tmax;
}

// Mitsuba's ray differentials of the camera ray (o, d) through `film_pos` (its
// sensor's sample_ray_differential, scaled by `scale` as Mitsuba's render_sample scales
// them by 1/√spp): the rays one pixel to the right (o_x, d_x) and one below (o_y, d_y),
// with the same aperture sample. The perspective keeps the origin and turns the
// direction (its m_dx, m_dy on the near plane), the orthographic keeps the direction
// and moves the origin; the thin lens, which has no sample_ray_differential of its own
// in Mitsuba 3.9.1, takes Sensor's default: both of the neighbouring rays. The
// radiancemeter and distant have none (false: has_differentials = false in Mitsuba).
bool camera_ray_differentials(vec2 film_pos, vec2 u_lens, vec3 o, vec3 d, float scale,
                              out vec3 o_x, out vec3 d_x, out vec3 o_y, out vec3 d_y) {
    o_x = o;
    o_y = o;
    d_x = d;
    d_y = d;
    uint kind = frame.camera_kind;
    if (kind != CAMERA_PERSPECTIVE && kind != CAMERA_THINLENS && kind != CAMERA_ORTHOGRAPHIC) {
        return false;
    }
    vec3 ox, dx, oy, dy;
    float t;
    camera_ray(film_pos + vec2(1.0, 0.0), u_lens, ox, dx, t);
    camera_ray(film_pos + vec2(0.0, 1.0), u_lens, oy, dy, t);
    if (kind != CAMERA_PERSPECTIVE) {
        o_x = o + (ox - o) * scale;
        o_y = o + (oy - o) * scale;
    }
    if (kind != CAMERA_ORTHOGRAPHIC) {
        d_x = d + (dx - d) * scale;
        d_y = d + (dy - d) * scale;
    }
    return true;
}

#endif
