// Descriptor set 0: the scene, read-only for every kernel that includes this file.
// Bindings are mirrored in src/render/scene_buffers.rs.
#ifndef SCENE_BINDINGS_GLSL
#define SCENE_BINDINGS_GLSL

#include "scene/layout.glsl"

// Every scene record is read through a storage texel buffer with imageLoad
// (BindingKind::Texels in src/gpu/kernel.rs: llvmpipe gathers an image load at
// scattered addresses inline, much faster than it loads from a storage buffer or
// calls its texel-fetch function). Use the *_load functions below, never the images.
//
// Large arrays may be split over several bindings (src/render/scene_parts.rs): one
// texel-buffer view addresses at most maxTexelBufferElements texels (lavapipe: 2^27)
// within one allocation, so an array past that is cut into parts of 2^SCENE_PART_SHIFT
// texels, part p at binding `NAME_p`, and a load tests its part against each binding
// (no descriptor indexing on lavapipe). Every kernel that includes this file is also
// compiled with SCENE_SPLIT defined (build.rs), the variant the renderer runs for a
// scene with a split array: there the parts of each array are specialization
// constants that every kernel gets from its BindingLayout (ScenePlan::spec, ids 64 and
// up: kernels number their own constants below 64). Without SCENE_SPLIT, the common
// case, a load is the one image load it always was (the split loads' dead code would
// cost llvmpipe 0.2 s of pipeline creation on every render).
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
layout(set = 0, binding = 0, rgba32ui) uniform readonly uimageBuffer bvh_node_texels;
layout(set = 0, binding = 15, rgba32ui) uniform readonly uimageBuffer bvh_node_texels_1;
layout(set = 0, binding = 16, rgba32ui) uniform readonly uimageBuffer bvh_node_texels_2;
layout(set = 0, binding = 17, rgba32ui) uniform readonly uimageBuffer bvh_node_texels_3;
layout(set = 0, binding = 1, rgba32ui) uniform readonly uimageBuffer prim_texels;
layout(set = 0, binding = 18, rgba32ui) uniform readonly uimageBuffer prim_texels_1;
layout(set = 0, binding = 19, rgba32ui) uniform readonly uimageBuffer prim_texels_2;
layout(set = 0, binding = 20, rgba32ui) uniform readonly uimageBuffer prim_texels_3;
// Shapes and triangles (one texel each) and vertices (two) likewise: read them
// with shape_load, triangle_load and vertex_load.
layout(set = 0, binding = 2, rgba32ui) uniform readonly uimageBuffer shape_texels;
layout(set = 0, binding = 3, rgba32ui) uniform readonly uimageBuffer triangle_texels;
layout(set = 0, binding = 21, rgba32ui) uniform readonly uimageBuffer triangle_texels_1;
layout(set = 0, binding = 4, rgba32ui) uniform readonly uimageBuffer vertex_texels;
layout(set = 0, binding = 22, rgba32ui) uniform readonly uimageBuffer vertex_texels_1;
// BSDFs, emitters and alias tables (bsdf_load, emitter_load, alias_load).
layout(set = 0, binding = 5, rgba32ui) uniform readonly uimageBuffer bsdf_texels;
layout(set = 0, binding = 6, rgba32ui) uniform readonly uimageBuffer emitter_texels;
// Emitter alias table at [0, emitter_count), then each mesh emitter's triangle table.
layout(set = 0, binding = 7, rgba32ui) uniform readonly uimageBuffer alias_texels;
// Textures (texture.glsl): records (texture_load), and every bitmap's RGB texels, three
// floats each (texel_value).
layout(set = 0, binding = 8, rgba32ui) uniform readonly uimageBuffer texture_texels;
layout(set = 0, binding = 9, r32ui) uniform readonly uimageBuffer texel_words;
layout(set = 0, binding = 23, r32ui) uniform readonly uimageBuffer texel_words_1;
layout(set = 0, binding = 24, r32ui) uniform readonly uimageBuffer texel_words_2;
layout(set = 0, binding = 25, r32ui) uniform readonly uimageBuffer texel_words_3;
// Sampling distributions of environment maps and textured area emitters
// (distribution2d.glsl; dist_value).
layout(set = 0, binding = 10, r32ui) uniform readonly uimageBuffer dist_words;
layout(set = 0, binding = 26, r32ui) uniform readonly uimageBuffer dist_words_1;
// Media (shaders/medium/medium.glsl): records (medium_load), density and albedo grids
// (grid_value), majorant grids (majorant_value), and density grids packed a texel per
// voxel (grid_packed; MEDIUM_DENSITY_PACKED).
layout(set = 0, binding = 11, rgba32ui) uniform readonly uimageBuffer medium_texels;
layout(set = 0, binding = 12, r32ui) uniform readonly uimageBuffer grid_words;
layout(set = 0, binding = 27, r32ui) uniform readonly uimageBuffer grid_words_1;
layout(set = 0, binding = 28, r32ui) uniform readonly uimageBuffer grid_words_2;
layout(set = 0, binding = 29, r32ui) uniform readonly uimageBuffer grid_words_3;
layout(set = 0, binding = 13, r32ui) uniform readonly uimageBuffer majorant_words;
layout(set = 0, binding = 14, rgba32ui) uniform readonly uimageBuffer grid_packed_texels;
layout(set = 0, binding = 30, rgba32ui) uniform readonly uimageBuffer grid_packed_texels_1;

// `uvec4 fn(uint k)`: texel k of an array of up to two (four) parts named IMG, IMG_1
// (, IMG_2, IMG_3). Each further part costs a masked gather, paid only by scenes
// whose array is split.
#ifdef SCENE_SPLIT
// The first two parts: sets `w` to texel k (local index `j`) if it lies in one.
#define SCENE_ARRAY_FIRST_TWO(IMG, PARTS)                                                \
    if (PARTS == 1u) return imageLoad(IMG, int(k));                                      \
    int j = int(k & SCENE_PART_MASK);                                                    \
    uint part = k >> SCENE_PART_SHIFT;                                                   \
    uvec4 w = imageLoad(IMG, j);                                                         \
    if (part == 1u) w = imageLoad(IMG##_1, j);
#define SCENE_ARRAY_2(fn, IMG, PARTS)                                                    \
    uvec4 fn(uint k) {                                                                   \
        SCENE_ARRAY_FIRST_TWO(IMG, PARTS)                                                \
        return w;                                                                        \
    }
#define SCENE_ARRAY_4(fn, IMG, PARTS)                                                    \
    uvec4 fn(uint k) {                                                                   \
        SCENE_ARRAY_FIRST_TWO(IMG, PARTS)                                                \
        if (PARTS > 2u && part == 2u) w = imageLoad(IMG##_2, j);                         \
        if (PARTS > 3u && part == 3u) w = imageLoad(IMG##_3, j);                         \
        return w;                                                                        \
    }
#else
#define SCENE_ARRAY_2(fn, IMG, PARTS) uvec4 fn(uint k) { return imageLoad(IMG, int(k)); }
#define SCENE_ARRAY_4(fn, IMG, PARTS) uvec4 fn(uint k) { return imageLoad(IMG, int(k)); }
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
float majorant_value(uint k) { return uintBitsToFloat(imageLoad(majorant_words, int(k)).x); }
vec4 grid_packed(uint k) { return uintBitsToFloat(grid_packed_texel(k)); }

// The records' loaders (generated: generated/records.glsl), `T NAME_load(uint i)`, each
// reading its array's texels through `NAME_texel`. Vertices are also read a texel at a
// time (vertex_texel).
uvec4 shape_texel(uint k) { return imageLoad(shape_texels, int(k)); }
uvec4 bsdf_texel(uint k) { return imageLoad(bsdf_texels, int(k)); }
uvec4 emitter_texel(uint k) { return imageLoad(emitter_texels, int(k)); }
uvec4 alias_texel(uint k) { return imageLoad(alias_texels, int(k)); }
uvec4 texture_texel(uint k) { return imageLoad(texture_texels, int(k)); }
uvec4 medium_texel(uint k) { return imageLoad(medium_texels, int(k)); }
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
