// Descriptor set 0: the scene, read-only for every kernel that includes this file.
// Bindings are mirrored in src/render/scene_buffers.rs.
#ifndef SCENE_BINDINGS_GLSL
#define SCENE_BINDINGS_GLSL

#include "scene/layout.glsl"

// Every scene record is read through a *_load function below, never from the bindings
// directly. Kernels are compiled twice over (build.rs; gpu::SceneAccess picks one for a
// device and a scene): by default each array is a storage texel buffer read with
// imageLoad (BindingKind::Texels: llvmpipe up to Mesa 22.3 gathers an image load at
// scattered addresses inline, much faster than it loads from a storage buffer or calls
// its texel-fetch function); with SCENE_STORAGE defined, a storage buffer read by index
// (llvmpipe from Mesa 26 calls a function for every image load, and gathers a storage
// buffer load inline, or loads it once where every lane reads one address).
#ifdef SCENE_STORAGE
#define SCENE_TEXELS(b, NAME) \
    layout(std430, set = 0, binding = b) readonly buffer NAME##_block { uvec4 NAME[]; };
#define SCENE_WORDS(b, NAME) \
    layout(std430, set = 0, binding = b) readonly buffer NAME##_block { uint NAME[]; };
#define SCENE_LOAD(NAME, k) scene_storage_texel(NAME[k])
uvec4 scene_storage_texel(uvec4 t) { return t; }
uvec4 scene_storage_texel(uint w) { return uvec4(w, 0u, 0u, 0u); }
#else
#define SCENE_TEXELS(b, NAME) layout(set = 0, binding = b, rgba32ui) uniform readonly uimageBuffer NAME;
#define SCENE_WORDS(b, NAME) layout(set = 0, binding = b, r32ui) uniform readonly uimageBuffer NAME;
#define SCENE_LOAD(NAME, k) imageLoad(NAME, int(k))
#endif

#ifdef SCENE_SPLIT
#include "generated/spec_constants.glsl"
SPEC(SCENE_PART_SHIFT);
#define SCENE_PART_MASK ((1u << SCENE_PART_SHIFT) - 1u)
SPEC(BVH_NODE_PARTS);
SPEC(PRIM_PARTS);
SPEC(TRIANGLE_PARTS);
SPEC(VERTEX_PARTS);
SPEC(TEXEL_PARTS);
SPEC(DIST_PARTS);
SPEC(GRID_PARTS);
SPEC(GRID_PACKED_PARTS);
#endif

// BVH nodes and primitives: 4 and 3 uvec4 texels a record (bvh_node_load, prim_load).
SCENE_TEXELS(0, bvh_node_texels)
SCENE_TEXELS(15, bvh_node_texels_1)
SCENE_TEXELS(16, bvh_node_texels_2)
SCENE_TEXELS(17, bvh_node_texels_3)
SCENE_TEXELS(1, prim_texels)
SCENE_TEXELS(18, prim_texels_1)
SCENE_TEXELS(19, prim_texels_2)
SCENE_TEXELS(20, prim_texels_3)
// Shapes and triangles (one texel each) and vertices (two) likewise: read them
// with shape_load, triangle_load and vertex_load.
SCENE_TEXELS(2, shape_texels)
SCENE_TEXELS(3, triangle_texels)
SCENE_TEXELS(21, triangle_texels_1)
SCENE_TEXELS(4, vertex_texels)
SCENE_TEXELS(22, vertex_texels_1)
// BSDFs, emitters and alias tables (bsdf_load, emitter_load, alias_load).
SCENE_TEXELS(5, bsdf_texels)
SCENE_TEXELS(6, emitter_texels)
// Emitter alias table at [0, emitter_count), then each mesh emitter's triangle table.
SCENE_TEXELS(7, alias_texels)
// Textures (texture.glsl): records (texture_load), and every bitmap's RGB texels, three
// floats each (texel_value).
SCENE_TEXELS(8, texture_texels)
SCENE_WORDS(9, texel_words)
SCENE_WORDS(23, texel_words_1)
SCENE_WORDS(24, texel_words_2)
SCENE_WORDS(25, texel_words_3)
// Sampling distributions of environment maps and textured area emitters
// (distribution2d.glsl; dist_value).
SCENE_WORDS(10, dist_words)
SCENE_WORDS(26, dist_words_1)
// Media (shaders/medium/medium.glsl): records (medium_load), density and albedo grids
// (grid_value), majorant grids (majorant_value), and density grids packed a texel per
// voxel (grid_packed; MEDIUM_DENSITY_PACKED).
SCENE_TEXELS(11, medium_texels)
SCENE_WORDS(12, grid_words)
SCENE_WORDS(27, grid_words_1)
SCENE_WORDS(28, grid_words_2)
SCENE_WORDS(29, grid_words_3)
SCENE_WORDS(13, majorant_words)
SCENE_TEXELS(14, grid_packed_texels)
SCENE_TEXELS(30, grid_packed_texels_1)

// `uvec4 fn(uint k)`: texel k of an array of up to two (four) parts named IMG, IMG_1
// (, IMG_2, IMG_3). Each further part costs a masked gather, paid only by scenes
// whose array is split.
#ifdef SCENE_SPLIT
// The first two parts: sets `w` to texel k (local index `j`) if it lies in one.
#define SCENE_ARRAY_FIRST_TWO(IMG, PARTS)                                                \
    if (PARTS == 1u) return SCENE_LOAD(IMG, k);                                          \
    int j = int(k & SCENE_PART_MASK);                                                    \
    uint part = k >> SCENE_PART_SHIFT;                                                   \
    uvec4 w = SCENE_LOAD(IMG, j);                                                        \
    if (part == 1u) w = SCENE_LOAD(IMG##_1, j);
#define SCENE_ARRAY_2(fn, IMG, PARTS)                                                    \
    uvec4 fn(uint k) {                                                                   \
        SCENE_ARRAY_FIRST_TWO(IMG, PARTS)                                                \
        return w;                                                                        \
    }
#define SCENE_ARRAY_4(fn, IMG, PARTS)                                                    \
    uvec4 fn(uint k) {                                                                   \
        SCENE_ARRAY_FIRST_TWO(IMG, PARTS)                                                \
        if (PARTS > 2u && part == 2u) w = SCENE_LOAD(IMG##_2, j);                        \
        if (PARTS > 3u && part == 3u) w = SCENE_LOAD(IMG##_3, j);                        \
        return w;                                                                        \
    }
#else
#define SCENE_ARRAY_2(fn, IMG, PARTS) uvec4 fn(uint k) { return SCENE_LOAD(IMG, k); }
#define SCENE_ARRAY_4(fn, IMG, PARTS) uvec4 fn(uint k) { return SCENE_LOAD(IMG, k); }
#endif
SCENE_ARRAY_4(bvh_node_texel, bvh_node_texels, BVH_NODE_PARTS)
SCENE_ARRAY_4(prim_texel, prim_texels, PRIM_PARTS)
SCENE_ARRAY_2(triangle_texel, triangle_texels, TRIANGLE_PARTS)
SCENE_ARRAY_2(vertex_texel_raw, vertex_texels, VERTEX_PARTS)
SCENE_ARRAY_4(texel_word, texel_words, TEXEL_PARTS)
SCENE_ARRAY_2(dist_word, dist_words, DIST_PARTS)
SCENE_ARRAY_4(grid_word, grid_words, GRID_PARTS)
SCENE_ARRAY_2(grid_packed_texel, grid_packed_texels, GRID_PACKED_PARTS)

float texel_value(uint k) { return uintBitsToFloat(texel_word(k).x); }
float dist_value(uint k) { return uintBitsToFloat(dist_word(k).x); }
float grid_value(uint k) { return uintBitsToFloat(grid_word(k).x); }
float majorant_value(uint k) { return uintBitsToFloat(SCENE_LOAD(majorant_words, k).x); }
vec4 grid_packed(uint k) { return uintBitsToFloat(grid_packed_texel(k)); }

// The records' loaders (generated: generated/records.glsl), `T NAME_load(uint i)`, each
// reading its array's texels through `NAME_texel`. Vertices are also read a texel at a
// time (vertex_texel).
uvec4 shape_texel(uint k) { return SCENE_LOAD(shape_texels, k); }
uvec4 bsdf_texel(uint k) { return SCENE_LOAD(bsdf_texels, k); }
uvec4 emitter_texel(uint k) { return SCENE_LOAD(emitter_texels, k); }
uvec4 alias_texel(uint k) { return SCENE_LOAD(alias_texels, k); }
uvec4 texture_texel(uint k) { return SCENE_LOAD(texture_texels, k); }
uvec4 medium_texel(uint k) { return SCENE_LOAD(medium_texels, k); }
BvhNode_LOAD(bvh_node_load, bvh_node_texel)
Prim_LOAD(prim_load, prim_texel)
ShapeRecord_LOAD(shape_load, shape_texel)
TriangleRecord_LOAD(triangle_load, triangle_texel)
Vertex_LOAD(vertex_load, vertex_texel_raw)
BsdfRecord_LOAD(bsdf_load, bsdf_texel)
EmitterRecord_LOAD(emitter_load, emitter_texel)
AliasEntry_LOAD(alias_load, alias_texel)
TextureRecord_LOAD(texture_load, texture_texel)
MediumRecord_LOAD(medium_load, medium_texel)

// Texel k (0: normal and u; 1: v) of vertex i.
vec4 vertex_texel(uint i, uint k) {
    return uintBitsToFloat(vertex_texel_raw(Vertex_TEXELS * i + k));
}

#endif
