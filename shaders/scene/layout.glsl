// GPU records shared with the host, and their constants. The records' structs and
// loaders are generated from src/gpu/records.rs by build.rs (generated/records.glsl in
// $OUT_DIR/glsl); each #define here mirrors a constant of src/gpu/layout.rs, whose
// tests check them.
#ifndef LAYOUT_GLSL
#define LAYOUT_GLSL

#include "generated/records.glsl"

// Prim.kind
#define PRIM_TRIANGLE 0u
#define PRIM_SPHERE 1u
#define PRIM_DISK 2u
#define PRIM_CYLINDER 3u
#define PRIM_INSTANCE 4u
#define PRIM_INSTANCE_DATA 5u
#define PRIM_SDFGRID 7u
#define PRIM_LINEAR_CURVE 8u
#define PRIM_BSPLINE_CURVE 9u
#define PRIM_ELLIPSOID 10u

#define NONE 0xffffffffu

// ShapeRecord.flags
#define SHAPE_HAS_NORMALS 1u
#define SHAPE_HAS_UVS 2u
#define SHAPE_FLIP_NORMALS 4u
#define SHAPE_NULL_BSDF 8u
#define SHAPE_MEDIUM_TRANSITION 16u
#define SHAPE_THIN_DIELECTRIC 32u
#define SHAPE_MIRRORED 64u
#define SHAPE_NORMALS_AGREE 128u
// No medium in one half of ShapeRecord.media.
#define MEDIUM_NONE16 0xffffu

// BsdfRecord.kind: BSDF_DIFFUSE, ... in generated/bsdf_dispatch.glsl, from
// src/scene/bsdf/kinds.rs.
// BsdfRecord.flags
#define BSDF_TWOSIDED 1u
#define BSDF_NONLINEAR 2u
#define BSDF_NORMALMAP_FLIP 4u
#define BSDF_NORMALMAP_SHADOWING 8u
#define BSDF_TABLE_TEXTURES 16u
// BsdfRecord.distribution
#define BSDF_BECKMANN 0u
#define BSDF_GGX 1u

// Frame.camera_kind (sensor/camera.glsl)
#define CAMERA_PERSPECTIVE 0u
#define CAMERA_ORTHOGRAPHIC 1u
#define CAMERA_THINLENS 2u
#define CAMERA_RADIANCEMETER 3u
#define CAMERA_DISTANT 4u
#define CAMERA_IRRADIANCEMETER 5u

// EmitterRecord.kind
#define EMITTER_POINT 0u
#define EMITTER_AREA 1u
#define EMITTER_CONSTANT 2u
#define EMITTER_SPOT 3u
#define EMITTER_ENVMAP 4u
// Mitsuba `directional` (axis: the direction light travels) and `projector`; kinds
// above the mask bits 5-8 below.
#define EMITTER_DIRECTIONAL 9u
#define EMITTER_PROJECTOR 10u
#define EMITTER_DIRECTIONAL_AREA 11u
// Bit of the emitter-kinds mask (EMITTER_KINDS, emitter.glsl) for area emitters on
// spheres; EMITTER_AREA's bit stands for area emitters on meshes.
#define EMITTER_KIND_BIT_SPHERE_AREA 5u
// ... and for area emitters on disks and cylinders.
#define EMITTER_KIND_BIT_QUADRIC_AREA 6u
// ... and for area emitters sampled by their texture (dist_width > 0), which set
// neither EMITTER_AREA's bit nor EMITTER_KIND_BIT_SPHERE_AREA.
#define EMITTER_KIND_BIT_TEXTURE_SAMPLED 7u
// ... and, beside it, for a texture-sampled emitter on a sphere.
#define EMITTER_KIND_BIT_TEXTURE_SPHERE 8u

// TextureRecord.kind, .flags
#define TEXTURE_BITMAP 0u
#define TEXTURE_CHECKERBOARD 1u
#define TEXTURE_NOISE 2u
#define TEXTURE_MARBLE 3u
#define TEXTURE_CONSTANT 4u
#define TEXTURE_MESH_ATTRIBUTE 5u
#define TEXTURE_ATTRIBUTE_FACE 1u
#define TEXTURE_NEAREST 1u
#define TEXTURE_WRAP_SHIFT 1u
#define TEXTURE_WRAP_REPEAT 0u
#define TEXTURE_WRAP_MIRROR 1u
#define TEXTURE_WRAP_CLAMP 2u
// Bits of the shade kernel's texture mask beside the kinds (1 << TEXTURE_*).
#define TEXTURE_FEATURE_BSDF 256u
#define TEXTURE_FEATURE_NORMALMAP 512u
#define TEXTURE_FEATURE_ENVMAP 1024u
#define TEXTURE_FEATURE_AREA 2048u
#define TEXTURE_FEATURE_LOOKUP_LOOP 4096u
#define TEXTURE_FEATURE_TABLE 8192u
// A spot light's `texture` or a projector's `irradiance` texture.
#define TEXTURE_FEATURE_EMITTER_PROFILE 16384u
#define TEXTURE_FEATURE_PARAM_SHIFT 16u

// Sampler kinds (Frame::sampler_kind) and flags (Frame::sampler_flags).
#define SAMPLER_INDEPENDENT 0u
#define SAMPLER_STRATIFIED 1u
#define SAMPLER_MULTIJITTER 2u
#define SAMPLER_ORTHOGONAL 3u
#define SAMPLER_LDSAMPLER 4u
#define SAMPLER_ZSOBOL 5u
#define SAMPLER_SOBOL 6u
#define SAMPLER_PMJ02BN 7u
// orthogonal of strength > 2 (Bush's construction; SAMPLER_ORTHOGONAL is Bose's).
#define SAMPLER_ORTHOGONAL_BUSH 8u
#define SAMPLER_JITTER 1u
#define SAMPLER_STRENGTH_SHIFT 8u
#define SAMPLER_SCRAMBLE_SHIFT 16u
#define SAMPLER_SCRAMBLE_NONE 0u
#define SAMPLER_SCRAMBLE_XOR 1u
#define SAMPLER_SCRAMBLE_FAST_OWEN 2u
#define SAMPLER_SCRAMBLE_OWEN 3u

// PathState.flags
#define PATH_DELTA 1u
#define PATH_THIN_REFLECT 2u
#define PATH_COVERED 4u

// MediumRecord.kind, .flags
#define MEDIUM_HOMOGENEOUS 0u
#define MEDIUM_GRID 1u
#define MEDIUM_SAMPLE_EMITTERS 1u
#define MEDIUM_ALBEDO_RGB 2u
#define MEDIUM_DENSITY_PACKED 4u
// Surface features of a scene (a specialization constant; see src/gpu/layout.rs).
#define SURFACE_FEATURE_SPHERES 1u
#define SURFACE_FEATURE_NORMALS 2u
#define SURFACE_FEATURE_UVS 4u
#define SURFACE_FEATURE_DISKS 8u
#define SURFACE_FEATURE_CYLINDERS 16u
#define SURFACE_FEATURE_SDFGRIDS 128u
#define SURFACE_FEATURE_LINEAR_CURVES 64u
#define SURFACE_FEATURE_BSPLINE_CURVES 256u
#define SURFACE_FEATURE_ELLIPSOIDS 512u
// Medium features of a scene (a specialization constant; see src/gpu/layout.rs).
#define MEDIUM_FEATURE_HOMOGENEOUS 1u
#define MEDIUM_FEATURE_PACKED1 2u
#define MEDIUM_FEATURE_PACKED3 4u
#define MEDIUM_FEATURE_DENSITY_WORDS 8u
#define MEDIUM_FEATURE_WORDS1 16u
#define MEDIUM_FEATURE_WORDS3 32u
#define MEDIUM_FEATURE_ALBEDO_GRID 64u
#define MEDIUM_FEATURE_GRIDS 14u

// The parts of a partitioned bounce's rays (partition.glsl).
#define PART_HITS 0
#define PART_MISSES 1
// Counters.deferred: shade's rays and shadow rays left to the full kernels.
#define DEFERRED_RAYS 0u
#define DEFERRED_SHADOWS 1u
// Words of Counters.tails: a queue segment's tails, COUNTER_TAIL_STRIDE words apart
// (queue.glsl), each the number of items the segment appended to one queue.
#define TAIL_RAYS 0 // + q: ray queue q
#define TAIL_SHADOWS 2
#define TAIL_PART 3 // + PART_HITS, PART_MISSES
#define TAIL_RAYS_TRACED 5 // not a queue: rays first_bounce traced (queue_count_rays)
#define COUNTER_TAIL_STRIDE 32

// Reconstruction filters (specialization constant FILM_FILTER of film_gather).
#define FILTER_BOX 0u
#define FILTER_TENT 1u
#define FILTER_GAUSSIAN 2u
#define FILTER_MITCHELL 3u
#define FILTER_LANCZOS 4u
// Flags of a film sample.
#define FILM_SAMPLE_VALID 1u
#define FILM_SAMPLE_COVERED 2u

// VisiblePoint.flags
#define VISIBLE_POINT_NORMAL_MAP 1u

#endif
