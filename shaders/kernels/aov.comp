#version 460
#extension GL_GOOGLE_include_directive : require
// aov: adds to each crop pixel the filter-weighted AOVs (Mitsuba's `aov` integrator;
// integrator/aov.glsl) and second moments (Mitsuba's `moment`) of the samples that
// film_gather adds to it after the same batch, in the same order and with the same
// weights (the same samples skipped as invalid), so that Σ w v / Σ w uses the film's
// weight sums and splits, crops and batches agree as the film's sums do. A sample's
// AOVs are those of its camera ray, traced again here (the ray generate made: its
// position in its pixel and its lens sample are functions of pixel and sample), so
// the radiance kernels do not change; made only for renders that write AOVs or
// moments. One thread per pixel of crop rows film_row .. film_row + film_rows; with
// a filter wider than the box, a first dispatch (FILM_AOV_SAMPLES) traces each path's
// ray once and keeps its AOVs in the ring slot of its sample, which the gather reads.
// Reads: the film's sample ring (or paths), the scene. Writes: the film's AOV and
// moment sums.

#include "generated/spec_constants.glsl"
// surface_at (shape/surface.glsl, included by several of the files below) keeps ∂p/∂u
// and ∂p/∂v for the dp_du, dp_dv, duv_dx and duv_dy AOVs.
#define SURFACE_PARTIALS
#include "queue/wavefront.glsl"
#include "scene/scene_bindings.glsl"
SPEC(SCENE_INSTANCES);
SPEC(SCENE_INSTANCE_SLOTS);
#define BVH_INSTANCES SCENE_INSTANCES
#define BVH_INSTANCE_SLOTS SCENE_INSTANCE_SLOTS
#include "queue/queue.glsl"
SPEC(SCENE_SAMPLER_KIND);
#define SAMPLER_KIND SCENE_SAMPLER_KIND
SPEC(SCENE_SURFACE_FEATURES);
#define SURFACE_FEATURES SCENE_SURFACE_FEATURES
SPEC(SCENE_TEXTURES);
#define TEXTURE_KINDS SCENE_TEXTURES
SPEC(SCENE_EMITTER_KINDS);
#define EMITTER_KINDS SCENE_EMITTER_KINDS
#define EMITTER_STRATA (SCENE_SAMPLER_KIND != SAMPLER_INDEPENDENT)
#include "emitter/emitter.glsl"
SPEC(SCENE_BSDF_KINDS);
#define BSDF_KINDS SCENE_BSDF_KINDS
#include "bsdf/bsdf.glsl"
#include "bsdf/bsdf_textured.glsl"
#include "film/film.glsl"
#include "sensor/camera.glsl"
// The sensor's rays as the camera paths' (sensor_ray.glsl): a batch sensor's children,
// an irradiancemeter's shape.
SPEC(SCENE_SENSOR_SHAPE);
#define SENSOR_ON_SHAPE SCENE_SENSOR_SHAPE
SPEC(SCENE_SENSOR_BATCH);
#define SENSOR_BATCH SCENE_SENSOR_BATCH
#include "sensor/sensor_ray.glsl"
SPEC(SCENE_PRIM_KINDS);
#define BVH_PRIM_KINDS SCENE_PRIM_KINDS
SPEC(SCENE_BVH_DEPTH);
#define BVH_STACK_DEPTH SCENE_BVH_DEPTH
SPEC(SCENE_FLAT_PRIMS);
SPEC(SCENE_FLAT_KINDS);
#define BVH_FLAT_PRIMS SCENE_FLAT_PRIMS
#define BVH_FLAT_KINDS SCENE_FLAT_KINDS
#include "accel/bvh.glsl"
#include "shape/surface.glsl"

SPEC(FILM_FILTER);
SPEC(FILM_FROM_PATHS);
// The AOV kinds (4 bits each, 0 ends the list) and whether second moments are kept.
SPEC(FILM_AOVS_LO);
SPEC(FILM_AOVS_HI);
SPEC(FILM_MOMENT);
// This dispatch writes each path's AOVs into the ring (one thread a path of the
// batch) for the gather of a filter wider than the box, which then reads them there.
SPEC(FILM_AOV_SAMPLES);
#include "film/filter.glsl"

// Per crop pixel, row-major, its AOV channels in order: Σ w v.
layout(std430, set = 3, binding = 5) buffer FilmAovBuffer { float film_aov_sums[]; };
// Per crop pixel: (Σ w X², Σ w Y², Σ w Z², 0) of the samples' CIE XYZ.
layout(std430, set = 3, binding = 6) buffer FilmMomentBuffer { vec4 film_moment_sums[]; };
// Per shape: the global number of its first triangle (prim_index AOVs).
layout(std430, set = 3, binding = 7) readonly buffer FilmAovShapeBuffer { uint film_aov_shape_first[]; };
// Per ring slot (film_slot), the AOV channels of its sample, in order.
layout(std430, set = 3, binding = 8) buffer FilmAovRingBuffer { float film_aov_ring[]; };

#include "integrator/aov.glsl"

// Whether any AOV is an albedo (the BSDF is then evaluated).
bool aov_needs_albedo() {
    for (uint i = 0u; i < 16u; i++) {
        if (aov_kind(i) == AOV_ALBEDO) return true;
    }
    return false;
}

// Whether any AOV is a uv partial (duv_dx, duv_dy).
bool aov_needs_uv_partials() {
    for (uint i = 0u; i < 16u; i++) {
        if (aov_kind(i) == AOV_DUV_DX || aov_kind(i) == AOV_DUV_DY) return true;
    }
    return false;
}

// The AOVs of the camera ray of sample `sample_index` of region pixel `q`.
AovHit aov_sample(ivec2 q, uint sample_index) {
    ivec2 pixel = ivec2(film.region_x, film.region_y) + q;
    uint key = film_pixel_key(pixel);
    AovRay r;
    vec2 film_pos = vec2(pixel) + film_sample_position(key, sample_index);
    sensor_ray(film_pos, key, sample_index, r.o, r.d, r.tmax);
    r.has_differentials = false;
    r.o_x = r.o;
    r.o_y = r.o;
    r.d_x = r.d;
    r.d_y = r.d;
    bool partials = aov_needs_uv_partials();
    // One camera's differentials (render::plan refuses uv partials of a batch; an
    // irradiancemeter has none, as Mitsuba's: duv 0).
    if (partials && SENSOR_BATCH <= 1u && !(SENSOR_ON_SHAPE && frame.camera_kind == CAMERA_IRRADIANCEMETER)) {
        vec2 u_lens = sensor_lens_sample(frame.camera_kind, key, sample_index);
        // Mitsuba's render_sample scales the differentials by 1/√spp.
        r.has_differentials = camera_ray_differentials(film_pos, u_lens, r.o, r.d,
            inversesqrt(float(frame.sample_count)), r.o_x, r.d_x, r.o_y, r.d_y);
    }
    return aov_trace(r, aov_needs_albedo(), partials);
}

// Adds w times the AOVs of sample `sample_index` of region pixel `q` to pixel i
// (the box filter: traced here), or those the ring holds in `slot` (other filters).
void aov_add(uint i, ivec2 q, uint sample_index, float w, uint floats, uint slot) {
    AovHit a;
    if (FILM_FROM_PATHS) a = aov_sample(q, sample_index);
    uint at = i * floats;
    uint from = slot * floats;
    for (uint j = 0u; j < 16u; j++) {
        uint kind = aov_kind(j);
        if (kind == 0u) break;
        uint n = aov_channels(kind);
        for (uint c = 0u; c < n; c++) {
            float v = FILM_FROM_PATHS ? aov_value(a, kind, c) : film_aov_ring[from];
            film_aov_sums[at] += w * v;
            at++;
            from++;
        }
    }
}

// Writes path p's AOVs into its ring slot.
void aov_store(uint p, uint floats) {
    uint pixels = film.region_width * film.region_height;
    uvec2 qr = divide(push.pixel_base + p, pixels);
    ivec2 q = film_region_pixel(qr.y) - ivec2(film.region_x, film.region_y);
    AovHit a = aov_sample(q, push.sample_base + qr.x);
    uint at = film_slot(p) * floats;
    for (uint j = 0u; j < 16u; j++) {
        uint kind = aov_kind(j);
        if (kind == 0u) break;
        uint n = aov_channels(kind);
        for (uint c = 0u; c < n; c++) {
            film_aov_ring[at] = aov_value(a, kind, c);
            at++;
        }
    }
}

// Mitsuba's srgb_to_xyz (linear sRGB, D65), squared per channel.
vec3 aov_xyz_squared(vec3 rgb) {
    vec3 xyz = vec3(dot(vec3(0.412453, 0.357580, 0.180423), rgb),
                    dot(vec3(0.212671, 0.715160, 0.072169), rgb),
                    dot(vec3(0.019334, 0.119193, 0.950227), rgb));
    return xyz * xyz;
}

// The floats of one pixel's AOVs.
uint aov_floats() {
    uint n = 0u;
    for (uint j = 0u; j < 16u; j++) {
        uint kind = aov_kind(j);
        if (kind == 0u) break;
        n += aov_channels(kind);
    }
    return n;
}

void main() {
    uint t = thread_index();
    if (FILM_AOV_SAMPLES) {
        if (t < push.path_count) aov_store(t, aov_floats());
        return;
    }
    uint cw = film.crop_width;
    if (t >= push.film_rows * cw) return;
    uvec2 qr = divide(t, cw);
    uvec2 c = uvec2(qr.y, push.film_row + qr.x);
    // As film_gather: this pixel, its neighbourhood and the samples the batch
    // completes.
    int W = int(film.region_width);
    int P = W * int(film.region_height);
    ivec2 s = ivec2(film.crop_x + c.x, film.crop_y + c.y) - ivec2(film.region_x, film.region_y);
    int n = int(film.reach);
    ivec2 lo = max(s - n, ivec2(0));
    ivec2 hi = min(s + n, ivec2(W, int(film.region_height)) - 1);
    int last = hi.y * W + hi.x - int(push.pixel_base);
    int count = int(push.path_count);
    if (last >= count) return;
    int k_first = last >= 0 ? 0 : 1;
    int k_last = int(divide(uint(count - 1 - last), uint(P)).x);
    if (k_first > k_last) return;

    uint i = c.y * cw + c.x;
    uint floats = aov_floats();
    vec4 m2 = FILM_MOMENT ? film_moment_sums[i] : vec4(0.0);
    if (FILM_FROM_PATHS) {
        int p = k_first * P + last;
        for (int k = k_first; k <= k_last; k++) {
            vec3 L = path_load(uint(p)).radiance;
            if (!(any(isnan(L)) || any(isinf(L)))) {
                if (FILM_MOMENT) m2 += vec4(aov_xyz_squared(L), 0.0);
                if (floats > 0u) aov_add(i, s, push.sample_base + uint(k), 1.0, floats, 0u);
            }
            p += P;
        }
        if (FILM_MOMENT) film_moment_sums[i] = m2;
        return;
    }
    for (int k = k_first; k <= k_last; k++) {
        uint row_slot = uint(k * P - int(push.pixel_base) + lo.y * W + lo.x
                             + int(push.sample_slot) + int(film.slots)) % film.slots;
        vec4 acc = vec4(0.0);
        for (int y = lo.y; y <= hi.y; y++) {
            uint slot = row_slot;
            for (int x = lo.x; x <= hi.x; x++) {
                FilmSample fs = film_sample_load(slot);
                if ((fs.flags & FILM_SAMPLE_VALID) != 0u) {
                    float w = filter_weight(vec2(s - ivec2(x, y)) + 0.5 - fs.offset);
                    if (FILM_MOMENT) acc += w * vec4(aov_xyz_squared(fs.value), 0.0);
                    if (floats > 0u) aov_add(i, ivec2(x, y), push.sample_base + uint(k), w, floats, slot);
                }
                slot = slot + 1u == film.slots ? 0u : slot + 1u;
            }
            row_slot += uint(W);
            if (row_slot >= film.slots) row_slot -= film.slots;
        }
        m2 += acc;
    }
    if (FILM_MOMENT) film_moment_sums[i] = m2;
}
