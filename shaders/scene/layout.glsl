// GPU structs shared with the host. Mirrors src/gpu/layout.rs field for field (std430);
// tests in that file check every size and offset.
#ifndef LAYOUT_GLSL
#define LAYOUT_GLSL

// BVH2 node with both children's bounds. count == 0: index is an inner node;
// count > 0: a leaf with primitives [index, index + count). Root is node 0.
struct BvhNode {
    vec3 left_min;
    uint left_index;
    vec3 left_max;
    uint left_count;
    vec3 right_min;
    uint right_index;
    vec3 right_max;
    uint right_count;
};

#define PRIM_TRIANGLE 0u
#define PRIM_SPHERE 1u
#define PRIM_DISK 2u
#define PRIM_CYLINDER 3u

// Triangle: vertices p0, p1, p2; index = global triangle number.
// Quadric (index = its number): columns of its object-to-world map M: p0 = M 0,
// p1 = M x (length: a sphere's or cylinder's radius), p2 = M y (sphere, disk) or M z
// (a cylinder's axis). The third axis of a sphere or cylinder is the cross product,
// negated with SHAPE_MIRRORED.
struct Prim {
    vec3 p0;
    uint shape;
    vec3 p1;
    uint index;
    vec3 p2;
    uint kind;
};

#define NONE 0xffffffffu

// Per shape (meshes in scene order, then quadrics).
#define SHAPE_HAS_NORMALS 1u
#define SHAPE_HAS_UVS 2u
#define SHAPE_FLIP_NORMALS 4u
#define SHAPE_NULL_BSDF 8u
#define SHAPE_MEDIUM_TRANSITION 16u
#define SHAPE_THIN_DIELECTRIC 32u
#define SHAPE_MIRRORED 64u
#define MEDIUM_NONE16 0xffffu
struct ShapeRecord {
    uint bsdf;
    uint emitter; // NONE if the shape emits nothing
    uint flags;
    uint media;   // interior medium (low 16 bits), exterior (high 16); 0xffff: none
};

// Vertex indices of a triangle into the vertex attribute array.
struct TriangleRecord {
    uint v0;
    uint v1;
    uint v2;
    uint pad0;
};

// Shading attributes of a vertex.
struct Vertex {
    float nx;
    float ny;
    float nz;
    float u;
    float v;
    uint pad0;
    uint pad1;
    uint pad2;
};

// BsdfRecord.kind: BSDF_DIFFUSE, ... in bsdf/dispatch.glsl, generated from
// src/scene/bsdf/kinds.rs.
// BsdfRecord.flags
#define BSDF_TWOSIDED 1u
#define BSDF_NONLINEAR 2u
#define BSDF_NORMALMAP_FLIP 4u
#define BSDF_NORMALMAP_SHADOWING 8u
// BsdfRecord.distribution
#define BSDF_BECKMANN 0u
#define BSDF_GGX 1u
// A BSDF's parameters; which fields a kind reads is listed in src/gpu/layout.rs.
struct BsdfRecord {
    vec3 reflectance;     // diffuse reflectance (diffuse, plastics, Nori kd)
    uint kind;
    vec3 specular;        // specular_reflectance
    uint flags;
    vec3 transmittance;   // specular_transmittance (dielectrics)
    float eta;            // int_ior / ext_ior (dielectrics, plastics, Nori microfacet)
    vec3 cond_eta;        // conductor: real part of the complex index
    float alpha_u;
    vec3 cond_k;          // conductor: imaginary part of the complex index
    float alpha_v;
    uint distribution;
    float specular_weight; // plastics: specular sampling weight; Nori microfacet: ks
    float internal;       // plastic: inner diffuse Fresnel reflectance; roughplastic: R_int
    uint pad0;
    vec4 table[8];        // roughplastic: coating transmittance at cos θ = i/31
    // Textures replacing constants at a hit, as texture index + 1 (0: none).
    uint tex_reflectance;
    uint tex_specular;
    uint tex_transmittance;
    uint tex_alpha_u;     // alpha from the texture's luminance
    uint tex_alpha_v;
    uint normal_map;      // Mitsuba normalmap around the model
    uint pad1;
    uint pad2;
};

#define EMITTER_POINT 0u
#define EMITTER_AREA 1u
#define EMITTER_CONSTANT 2u
#define EMITTER_SPOT 3u
#define EMITTER_ENVMAP 4u
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
// radiance: intensity (W/sr) of point and spot lights, radiance of area and constant
// ones. Spot: axis, cos_cutoff, cutoff (rad), inv_transition = 1/(cutoff - beam width).
// Area: shape, total area; a mesh's triangles by area through alias entries
// [tri_first, tri_first + tri_count); a quadric: tri_count 0, prim (its primitive)
// and prim_kind, and a sphere position = centre, radius.
struct EmitterRecord {
    vec3 position;
    uint kind;
    vec3 radiance;
    uint shape;
    vec3 axis;
    float cos_cutoff;
    float cutoff;
    float inv_transition;
    float area;
    float radius;
    uint tri_first;
    uint tri_count;
    uint prim;            // a quadric's primitive
    uint prim_kind;       // and its kind
    uint texture;         // index + 1: area radiance texture, or the envmap's image
    uint dist_offset;     // envmap: its sampling distribution in dist_value()
    uint dist_width;
    uint dist_height;
    vec4 to_world_x;      // envmap: columns of its rotation
    vec4 to_world_y;
    vec4 to_world_z;
};

#define TEXTURE_BITMAP 0u
#define TEXTURE_CHECKERBOARD 1u
#define TEXTURE_NOISE 2u
#define TEXTURE_MARBLE 3u
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
#define TEXTURE_FEATURE_PARAM_SHIFT 16u
// A texture; lookups map uv by the affine to_uv first (u' = dot(to_uv_u.xyz, (u,v,1))).
// Bitmap: width x height RGB texels at texel_value(offset..), row 0 at v = 0.
struct TextureRecord {
    uint kind;
    uint offset;
    uint width;
    uint height;
    uint flags;
    uint octaves;
    uint seed;
    uint pad0;
    vec3 color0;
    float frequency;
    vec3 color1;
    float variation;
    vec4 to_uv_u;
    vec4 to_uv_v;
};

// Alias table entry (Walker 1977, Vose 1991): keep i with probability prob, else alias;
// pmf: final probability of i; prim: BVH primitive of a light triangle.
struct AliasEntry {
    float prob;
    uint alias;
    float pmf;
    uint prim;
};

// Constant over a render. Bound as a std140 uniform block, which lays it out as
// std430 does only while it has no arrays of scalars or of vec2.
struct Frame {
    mat4 camera_to_world;
    vec2 tan_half_fov;
    float near_clip;
    float far_clip;
    uint width;
    uint height;
    uint seed;
    uint point_light_count;
    float ao_max_t;
    uint ao_uniform;
    uint max_depth;     // segments; 0xffffffff: unbounded
    uint emitter_count;
    uint rr_depth;      // Russian roulette from this depth on
    uint env_emitter;   // constant environment emitter or NONE
    uint hide_emitters; // 1: camera rays do not see emitters
    uint camera_medium; // medium camera rays start in, or NONE
    uint sampler_kind;  // SAMPLER_* (shaders/sampler/sampler.glsl)
    uint sample_count;  // samples of one pass of the sampler
    uint sampler_res_x; // the sampler's strata (see struct Sampler)
    uint sampler_res_y;
    uint sampler_flags; // SAMPLER_JITTER, strength, scrambling
    uint sampler_width;  // the pixel keys' grid (film with its sampled border)
    uint sampler_height;
    uint emitter_strata; // whole strata the emitter choice hands out; 0: by the weights' cdf
    uvec4 emitter_prims[4]; // the area emitters' prims, where few (path_emitted.glsl)
    uint photon_alias;      // photon emission's emitter table (by power) among the alias entries
    uint pad0;
    uint pad1;
    uint pad2;
};

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

// One path of the wavefront, by path slot.
#define PATH_DELTA 1u
#define PATH_THIN_REFLECT 2u
#define PATH_COVERED 4u
struct PathState {
    vec3 throughput;
    uint pixel;         // the random numbers' pixel key (film/film.glsl)
    vec3 radiance;
    uint sample_index;
    float bsdf_pdf; // solid-angle pdf of the current ray's direction (for MIS)
    uint flags;     // PATH_DELTA: the current ray came from a delta lobe;
                    // PATH_THIN_REFLECT: transient, from the medium stage to path_shade;
                    // PATH_COVERED: the camera path counts for the film's alpha
    float eta_scale; // product of (η_t/η_i)² over refractions (for Russian roulette)
    uint medium;    // medium the current ray travels in, or NONE
};

// A ray waiting for `intersect`.
struct RayItem {
    vec3 origin;
    uint path;
    vec3 dir;
    float tmax;
};

// Closest hit of the ray at the same queue position; prim == NONE: miss.
struct HitItem {
    float t;
    float u;
    float v;
    uint prim;
};

// A shadow ray; if unblocked, contribution is added to the path's radiance.
struct ShadowItem {
    vec3 origin;
    uint path;
    vec3 dir;
    float tmax;
    vec3 contribution;
    uint medium; // medium the shadow ray starts in, or NONE
};

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
// Medium features of a scene (a specialization constant; see src/gpu/layout.rs).
#define MEDIUM_FEATURE_HOMOGENEOUS 1u
#define MEDIUM_FEATURE_PACKED1 2u
#define MEDIUM_FEATURE_PACKED3 4u
#define MEDIUM_FEATURE_DENSITY_WORDS 8u
#define MEDIUM_FEATURE_WORDS1 16u
#define MEDIUM_FEATURE_WORDS3 32u
#define MEDIUM_FEATURE_ALBEDO_GRID 64u
#define MEDIUM_FEATURE_GRIDS 14u
// A participating medium; see src/gpu/layout.rs. Homogeneous: sigma_t (scale applied)
// and albedo. Grid: extinction = sigma_t (per-channel scale) x trilinear density at
// `data` (res voxels, channels 1 or 3), world_to_grid maps to the grid's unit cube; a
// coarse majorant grid (maj_res cells at maj_data) bounds it per cell, `majorant`
// everywhere. g: Henyey-Greenstein asymmetry.
struct MediumRecord {
    vec3 sigma_t;
    uint kind;
    vec3 albedo;
    float g;
    mat4 world_to_grid;
    uvec3 res;
    uint data;
    uvec3 maj_res;
    uint maj_data;
    float majorant;
    uint channels;
    uint flags;
    uint albedo_data; // NONE, or an albedo grid on the density voxels at this offset
};

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
#define COUNTER_TAIL_STRIDE 32

// Queue lengths and statistics. The kernels append to the tails, a segment per 128
// bytes (queue.glsl); the lengths they fold into reach the kernels that consume the
// queues through the frame's uniform block (wavefront.glsl: queue_lengths).
struct Counters {
    uint ray_count[2];    // length of ray queue q (the host's, to stop a batch)
    uint rays_traced;
    uint discarded;
    uint deferred[2];     // items left to the full kernels (deferral.glsl)
    uint deferred_total;  // those of the batch's bounces before the current lists
    uint head_pad[25];
    uint tails[64];       // 2 segments x COUNTER_TAIL_STRIDE
};

// VkDispatchIndirectCommand per queue.
struct DispatchArgs {
    uint rays[3];
    uint shadows[3];
    uint hits[3];   // a partitioned bounce's hits and misses (shade_args)
    uint misses[3];
    uint deferred_rays[3];    // the items a bounce's fast shade and shadow deferred
    uint deferred_shadows[3]; // (deferral.glsl)
};

// Push constants of the wavefront kernels.
struct Push {
    uint path_count;
    uint pixel_base;
    uint sample_base;
    uint depth;
    uint queue_in;
    uint capacity; // ray queue q starts at item q * capacity
    uint sample_slot; // the film's sample slot of path 0 of this batch
    uint film_row;    // film_gather: first crop row
    uint film_rows;   // film_gather: crop rows
    uint frame_index; // always 0: the index of `frame` in wavefront.glsl's block
    uint pad1;
    uint pad2;
};

// Push constants of tonemap (the viewer's display of the film).
struct TonemapPush {
    uint width;     // the crop window's size
    uint height;
    float scale;    // 2^exposure
    uint luminance; // 1: show luminance (grey), as the PNG of a luminance film
};

// Reconstruction filters (specialization constant 0 of film_gather).
#define FILTER_BOX 0u
#define FILTER_TENT 1u
#define FILTER_GAUSSIAN 2u
#define FILTER_MITCHELL 3u
#define FILTER_LANCZOS 4u
// Flags of a film sample.
#define FILM_SAMPLE_VALID 1u
#define FILM_SAMPLE_COVERED 2u

// The film: which pixels are sampled and which are kept, the random numbers' pixel
// keys, the sample ring and the filter (film/film.glsl). A std140 uniform block,
// laid out as std430. Pixel coordinates are the full film's (may be negative with a
// sampled border).
struct FilmParams {
    int region_x;        // the sampled region: origin and size
    int region_y;
    uint region_width;
    uint region_height;
    uint crop_x;         // the pixels kept: the crop window
    uint crop_y;
    uint crop_width;
    uint crop_height;
    int key_x;           // pixel key = (y - key_y) * key_width + (x - key_x)
    int key_y;
    uint key_width;
    uint reach;          // pixels a sample reaches on each side of its own
    uint slots;          // sample slots in the ring
    uint coverage;       // 1: every camera path counts as covered (visible environment)
    uint pad0;
    uint pad1;
    vec4 filter_params;  // FILTER_* parameters (film/filter.glsl)
};

// Photon mapping (src/gpu/layout.rs, shaders/photon/): a stored photon. wi: the
// direction it arrived from, octahedral in two snorm16 (photon/record.glsl); path: its
// photon path's index in the emission sequence.
struct Photon {
    vec3 position;
    uint path;
    vec3 power;
    uint wi;
};

// A photon path in flight, by path slot (in the path-state buffer).
struct PhotonPath {
    vec3 power;
    uint index;
    float start_power; // largest channel of the power at emission (Russian roulette)
    uint stored;       // photons stored so far
    uint pad0;
    uint pad1;
};

// Parameters of a photon pass (uniform block; see src/gpu/layout.rs).
struct PhotonParams {
    vec3 scene_center;
    float scene_radius;
    float cell_size;
    float inv_cell_size;
    uint table_mask;
    uint capacity;      // photon slots; photons appended past them are only counted
    float radius;       // photonmapper: gather radius
    float gather_scale; // photonmapper: factor of the photon sum
    float emission_scale; // photonmapper: factor of emission camera paths find
    uint path_limit;    // photons of paths at or above this index stay out of the grid
    uint store_first;   // 1: store at a photon path's first surface too
    uint max_bounces;   // surfaces a photon path meets at most
    uint iteration;     // stream of photon random numbers
    uint first_pixel;   // sppm: the tile's first pixel (visible points, pixel states)
};

// Counters of photon passes.
struct PhotonCounters {
    uint stored;     // photons appended (the excess over capacity was dropped)
    uint max_radius; // sppm: largest radius, as float bits (atomicMax)
    uint pad0;
    uint pad1;
};

// Where a camera path meets its first non-delta surface (bsdf == NONE: none).
#define VISIBLE_POINT_NORMAL_MAP 1u
struct VisiblePoint {
    vec3 p;
    uint bsdf;
    vec3 wo;   // towards the camera
    float u;
    vec3 n;    // shading normal, after a normal map
    float v;
    vec3 beta; // camera path throughput
    float alpha2; // normal map shadowing roughness
    vec3 n0;   // shading normal before the normal map
    uint flags;
};

// One pixel of SPPM (pbrt-v4's SPPMPixel).
struct SppmPixel {
    vec3 tau;
    float radius;
    vec3 ld;   // sum of directly found light over iterations
    float n;   // photon count N
    vec3 phi;  // this iteration's Φ_i
    uint m;    // this iteration's M
};

#endif
