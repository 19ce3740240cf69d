#version 460
#extension GL_GOOGLE_include_directive : require
// generate: one camera ray per path slot of the batch (camera_path.glsl).
// Writes: paths[p], ray queue 0 item p. The host sets ray_count[0] = path_count.

#include "generated/spec_constants.glsl"
#include "queue/wavefront.glsl"
// The sampler kind (SAMPLER_*): the other kinds compile away.
SPEC(SCENE_SAMPLER_KIND);
#define SAMPLER_KIND SCENE_SAMPLER_KIND
#include "film/film.glsl"
#include "sensor/camera.glsl"
// An irradiancemeter draws its rays' origins on its shape (SCENE_SENSOR_SHAPE; false
// compiles the scene's bindings and emitter.glsl's code away again).
#include "scene/scene_bindings.glsl"
SPEC(SCENE_INSTANCES);
SPEC(SCENE_INSTANCE_SLOTS);
#define BVH_INSTANCES SCENE_INSTANCES
#define BVH_INSTANCE_SLOTS SCENE_INSTANCE_SLOTS
SPEC(SCENE_SURFACE_FEATURES);
#define SURFACE_FEATURES SCENE_SURFACE_FEATURES
SPEC(SCENE_TEXTURES);
#define TEXTURE_KINDS SCENE_TEXTURES
SPEC(SCENE_EMITTER_KINDS);
#define EMITTER_KINDS SCENE_EMITTER_KINDS
#include "emitter/emitter.glsl"
SPEC(SCENE_SENSOR_SHAPE);
#define SENSOR_ON_SHAPE SCENE_SENSOR_SHAPE
// A batch sensor's children side by side (camera_path.glsl; 0: one camera).
SPEC(SCENE_SENSOR_BATCH);
#define SENSOR_BATCH SCENE_SENSOR_BATCH
#include "integrator/camera_path.glsl"

void main() {
    uint p = thread_index();
    if (p >= push.path_count) return;
    PathState path;
    RayItem r;
    camera_path_start(p, path, r);
    path_store(p, path);
    ray_store(ray_slot_at(0u, p), r);
}
