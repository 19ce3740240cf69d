// The particle tracer (Mitsuba 3's `ptracer`): a vertex of a light path connected to
// the pinhole camera (or a point of a thin lens's aperture) and splatted into the film.
//
// One sample index of a ptracer render is P = width x height light paths (the full
// film's pixel count, as Mitsuba's AdjointIntegrator traces spp x P in all). A path
// vertex y with throughput β adds to the pixel its camera connection meets
//     β f(y) / (d² cos³θc A),
// f(y) the BSDF towards the camera times |cos θy| (or, at a point on an emitter, its
// radiance times cos θy), d the distance to the camera, θc the angle to the camera's
// axis and A the image plane's area at z = 1 ((2 tan(fov_x/2)) (2 tan(fov_y/2))): the
// pinhole's importance 1 / (A_pixel cos³θc) (Mitsuba's PerspectiveCamera::importance,
// per pixel) averaged over the P paths. So the sum of one sample index's splats is an
// estimate of each pixel (film sums then average the sample indices).
//
// Splats are added as 64-bit fixed point (2^-24 units) with 32-bit atomics and an
// explicit carry: integer sums do not depend on the order the atomics land in, so a
// sample index's pixel values are the same bits on any device or batching, and
// `ptracer_fold.comp` adds them to the film sums in sample order as film_gather adds
// camera samples (partial renders merge and resume as for the path tracers).
//
// An irradiancemeter (PTRACER_SENSOR_SHAPE) takes each connection to a uniform point x
// of its shape instead, importance cos θx / d² (sensor/irradiancemeter.glsl), and splats
// at the film position its 2-D sample stands for, as its camera rays are placed.
//
// Needs wavefront.glsl, scene_bindings.glsl, bvh.glsl, surface.glsl, emitter.glsl,
// photon/bindings.glsl, photon/random.glsl, film/film.glsl and film/filter.glsl
// (FILM_FILTER).
#ifndef PTRACER_GLSL
#define PTRACER_GLSL

#include "sensor/camera.glsl"
#include "sensor/irradiancemeter.glsl"

// Fixed-point units per unit of radiance (2^24), and its inverse.
#define PTRACER_FIXED_SCALE 16777216.0
#define PTRACER_FIXED_UNIT (1.0 / 16777216.0)
// Splats above this (in fixed point) are dropped: 2^62 units keep the high word of a
// pixel far from overflowing.
#define PTRACER_FIXED_MAX 4.611686e18
// Random dimensions of the visible-emitter connection: after every bounce's (the
// photon paths' PHOTON_RNG_DIM_BOUNCE + depth, depth < 2^16).
#define PTRACER_RNG_DIM_VISIBLE 0x10000000u
// Random dimensions of the sensor's point of a camera connection (a thin lens's
// aperture, an irradiancemeter's shape): the visible-emitter connection's, then the
// bounce's (+ 1 + depth).
#define PTRACER_RNG_DIM_SENSOR 0x20000000u

// A thin-lens camera (Mitsuba's ThinLensCamera::sample_direction): connections go to
// a uniform point of the aperture (a specialization constant, PTRACER_THIN_LENS;
// false: the pinhole, whose code is then unchanged).
#ifndef PTRACER_THIN_LENS
#define PTRACER_THIN_LENS false
#endif
// The sensor is an irradiancemeter on a shape (a specialization constant, the scene's
// SCENE_SENSOR_SHAPE; false: its code compiles away).
#ifndef PTRACER_SENSOR_SHAPE
#define PTRACER_SENSOR_SHAPE false
#endif
// Whether a connection draws a 2-D sample for the sensor's point.
#define PTRACER_SENSOR_SAMPLED (PTRACER_THIN_LENS || PTRACER_SENSOR_SHAPE)

// The 2-D sample of the sensor's point of a connection at dimension `dim`: photon_rng's
// key hashed by two rounds of pcg4d. With one round, the first numbers of dimensions
// 2^28 apart are correlated where the other key words are constant (a 1 x 1 film's
// light paths all have index 0; correlation 0.018 over 10^6 sample indices, seed 0),
// which put an irradiancemeter's point in step with the emitter's choice and the
// light path's numbers (its estimate 0.15-1% low; tests/ptracer.rs). Two rounds show
// no correlation with any dimension the paths draw (none beyond 4/sqrt(n)).
vec2 ptracer_sensor_rng(uint index, uint iteration, uint dim) {
    uvec4 h = rng_pcg4d(rng_pcg4d(uvec4(index, iteration, PHOTON_RNG_DIM_BASE + dim, frame.seed)));
    return vec2(rng_to_float(h.x), rng_to_float(h.y));
}

// Where a point connects to the camera.
struct CameraLink {
    bool ok;        // in front of the camera, within the clip range and the film
    vec3 dir;       // unit, from the point towards the camera
    float dist;     // to the camera
    vec2 film_pos;  // where it lands on the film, in pixels (origin top-left)
    float importance; // 1 / (d² cos³θc A); an irradiancemeter's: cos θx / d²
    vec3 eye;       // the point of the sensor it goes to (the pinhole, of the aperture,
                    // or, just off it, of the irradiancemeter's shape)
};

// The thin lens's aperture point for the sample u_lens, in camera space (z = 0).
vec3 ptracer_lens_point(vec2 u_lens) {
    return vec3(frame.aperture_radius * camera_thinlens_aperture(u_lens), 0.0);
}

// The link of point p to the camera; u_lens: the sensor's sample (a thin lens's
// aperture point, an irradiancemeter's point).
CameraLink ptracer_camera(vec3 p, vec2 u_lens) {
    CameraLink c;
    c.ok = false;
    c.dir = vec3(0.0, 0.0, 1.0);
    c.dist = 0.0;
    c.film_pos = vec2(0.0);
    c.importance = 0.0;
    if (PTRACER_SENSOR_SHAPE) {
        Surface x;
        c.importance = irradiancemeter_importance(p, u_lens, x);
        c.eye = surface_spawn_origin(x, x.ng);
        c.dist = length(c.eye - p);
        c.dir = (c.eye - p) / c.dist;
        c.film_pos = u_lens * vec2(frame.width, frame.height);
        c.ok = c.importance > 0.0 && !isinf(c.importance) && c.dist > 0.0;
        return c;
    }
    vec3 eye = frame.camera_to_world[3].xyz;
    c.eye = eye;
    vec3 local = inverse(mat3(frame.camera_to_world)) * (p - eye);
    // Mitsuba's clip range is on the camera-space depth.
    if (!(local.z >= frame.near_clip && local.z <= frame.far_clip)) return c;
    if (PTRACER_THIN_LENS) {
        // Mitsuba's ThinLensCamera::sample_direction: from a uniform point a of the
        // aperture, the point is seen where the line through a meets the focal plane;
        // its importance is the pinhole's, 1 / (d² cos³θc A), of the direction from a.
        vec3 a = ptracer_lens_point(u_lens);
        vec3 ld = local - a;
        float d2 = dot(ld, ld);
        float cos_c = ld.z / sqrt(d2);
        if (!(cos_c > 0.0)) return c;
        vec2 plane = (a.xy + ld.xy * (frame.focus_distance / ld.z)) / frame.focus_distance;
        vec2 ndc = 0.5 * (1.0 - plane / frame.tan_half_fov);
        if (!(ndc.x >= 0.0 && ndc.x < 1.0 && ndc.y >= 0.0 && ndc.y < 1.0)) return c;
        float area = 4.0 * frame.tan_half_fov.x * frame.tan_half_fov.y;
        c.eye = (frame.camera_to_world * vec4(a, 1.0)).xyz;
        c.dist = length(c.eye - p);
        c.dir = (c.eye - p) / c.dist;
        c.film_pos = ndc * vec2(frame.width, frame.height);
        c.importance = 1.0 / (d2 * cos_c * cos_c * cos_c * area);
        c.ok = c.importance > 0.0 && !isinf(c.importance);
        return c;
    }
    vec2 plane = local.xy / local.z;
    // camera_ray's film position, inverted.
    vec2 ndc = 0.5 * (1.0 - plane / frame.tan_half_fov);
    if (!(ndc.x >= 0.0 && ndc.x < 1.0 && ndc.y >= 0.0 && ndc.y < 1.0)) return c;
    float d2 = dot(local, local);
    float d = sqrt(d2);
    float cos_c = local.z / d;
    float area = 4.0 * frame.tan_half_fov.x * frame.tan_half_fov.y;
    c.dist = length(eye - p);
    c.dir = (eye - p) / c.dist;
    c.film_pos = ndc * vec2(frame.width, frame.height);
    c.importance = 1.0 / (d2 * cos_c * cos_c * cos_c * area);
    c.ok = c.importance > 0.0 && !isinf(c.importance);
    return c;
}

// Whether nothing blocks the segment from surface s to the camera of link c.
bool ptracer_camera_visible(Surface s, CameraLink c) {
    vec3 o = surface_spawn_origin(s, dot(c.dir, s.ng) > 0.0 ? s.ng : -s.ng);
    vec3 eye = c.eye;
    float tmax = length(eye - o) * (1.0 - 1e-4);
    return !bvh_any(o, normalize(eye - o), 0.0, tmax);
}

// Adds v (one channel) to the 64-bit two's complement word pair at `word`: negative
// values (the negative lobes of Mitchell's and Lanczos's filters) wrap around, and
// the sums stay exact modulo 2^64.
void ptracer_add(uint word, float v) {
    float x = floor(abs(v) * PTRACER_FIXED_SCALE + 0.5);
    if (!(x >= 1.0) || !(x < PTRACER_FIXED_MAX)) return;
    float hi_f = floor(x * (1.0 / 4294967296.0));
    uint hi = uint(hi_f);
    uint lo = uint(x - hi_f * 4294967296.0);
    if (v < 0.0) {
        // -x = ~x + 1
        lo = ~lo + 1u;
        hi = ~hi + (lo == 0u ? 1u : 0u);
    }
    uint old = atomicAdd(splat_words[word], lo);
    if (old + lo < old) hi += 1u;
    if (hi != 0u) atomicAdd(splat_words[word + 1u], hi);
}

// Adds `value` to film pixel `px`, if the crop window keeps it.
void ptracer_splat_pixel(ivec2 px, vec3 value) {
    ivec2 c = px - ivec2(film.crop_x, film.crop_y);
    if (any(lessThan(c, ivec2(0))) || c.x >= int(film.crop_width) || c.y >= int(film.crop_height)) return;
    uint w = 6u * (uint(c.y) * film.crop_width + uint(c.x));
    ptracer_add(w, value.x);
    ptracer_add(w + 2u, value.y);
    ptracer_add(w + 4u, value.z);
}

// Splats `value` at film position `pos` through the reconstruction filter, as
// Mitsuba's ImageBlock::put with normalization: the weights of the pixels within the
// filter's reach, over their sum (pixels outside the film count in the sum but are not
// written). The box: the pixel `pos` lies in.
void ptracer_splat(vec2 pos, vec3 value) {
    if (any(isnan(value)) || any(isinf(value)) || all(equal(value, vec3(0.0)))) return;
    ivec2 p = ivec2(floor(pos));
    if (FILM_FILTER == FILTER_BOX) {
        ptracer_splat_pixel(p, value);
        return;
    }
    int n = int(film.reach);
    float sum = 0.0;
    for (int y = -n; y <= n; y++) {
        for (int x = -n; x <= n; x++) {
            sum += filter_weight(vec2(p + ivec2(x, y)) + 0.5 - pos);
        }
    }
    if (!(sum != 0.0)) return;
    for (int y = -n; y <= n; y++) {
        for (int x = -n; x <= n; x++) {
            ivec2 q = p + ivec2(x, y);
            if (q.x < 0 || q.y < 0 || q.x >= int(frame.width) || q.y >= int(frame.height)) continue;
            float w = filter_weight(vec2(q) + 0.5 - pos) / sum;
            if (w != 0.0) ptracer_splat_pixel(q, w * value);
        }
    }
}

#endif
