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
layout(constant_id = 64) const uint SCENE_PART_SHIFT = 27u;
#define SCENE_PART_MASK ((1u << SCENE_PART_SHIFT) - 1u)
layout(constant_id = 65) const uint BVH_NODE_PARTS = 1u;
layout(constant_id = 66) const uint PRIM_PARTS = 1u;
layout(constant_id = 68) const uint TRIANGLE_PARTS = 1u;
layout(constant_id = 69) const uint VERTEX_PARTS = 1u;
layout(constant_id = 74) const uint TEXEL_PARTS = 1u;
layout(constant_id = 75) const uint DIST_PARTS = 1u;
layout(constant_id = 77) const uint GRID_PARTS = 1u;
layout(constant_id = 79) const uint GRID_PACKED_PARTS = 1u;
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

// TextureRecord: 6 texels.
TextureRecord texture_load(uint i) {
    int b = int(6u * i);
    uvec4 w0 = imageLoad(texture_texels, b);
    uvec4 w1 = imageLoad(texture_texels, b + 1);
    uvec4 w2 = imageLoad(texture_texels, b + 2);
    uvec4 w3 = imageLoad(texture_texels, b + 3);
    return TextureRecord(w0.x, w0.y, w0.z, w0.w, w1.x, w1.y, w1.z, w1.w,
                         uintBitsToFloat(w2.xyz), uintBitsToFloat(w2.w),
                         uintBitsToFloat(w3.xyz), uintBitsToFloat(w3.w),
                         uintBitsToFloat(imageLoad(texture_texels, b + 4)),
                         uintBitsToFloat(imageLoad(texture_texels, b + 5)));
}

// MediumRecord: 9 texels.
MediumRecord medium_load(uint i) {
    int b = int(9u * i);
    uvec4 w0 = imageLoad(medium_texels, b);
    uvec4 w1 = imageLoad(medium_texels, b + 1);
    mat4 to_grid = mat4(uintBitsToFloat(imageLoad(medium_texels, b + 2)),
                        uintBitsToFloat(imageLoad(medium_texels, b + 3)),
                        uintBitsToFloat(imageLoad(medium_texels, b + 4)),
                        uintBitsToFloat(imageLoad(medium_texels, b + 5)));
    uvec4 w6 = imageLoad(medium_texels, b + 6);
    uvec4 w7 = imageLoad(medium_texels, b + 7);
    uvec4 w8 = imageLoad(medium_texels, b + 8);
    return MediumRecord(uintBitsToFloat(w0.xyz), w0.w, uintBitsToFloat(w1.xyz), uintBitsToFloat(w1.w),
                        to_grid, w6.xyz, w6.w, w7.xyz, w7.w, uintBitsToFloat(w8.x), w8.y, w8.z, w8.w);
}

BvhNode bvh_node_load(uint i) {
    uint base = 4u * i;
    uvec4 a = bvh_node_texel(base);
    uvec4 b = bvh_node_texel(base + 1u);
    uvec4 c = bvh_node_texel(base + 2u);
    uvec4 d = bvh_node_texel(base + 3u);
    return BvhNode(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w,
                   uintBitsToFloat(c.xyz), c.w, uintBitsToFloat(d.xyz), d.w);
}

Prim prim_load(uint i) {
    uint base = 3u * i;
    uvec4 a = prim_texel(base);
    uvec4 b = prim_texel(base + 1u);
    uvec4 c = prim_texel(base + 2u);
    return Prim(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w, uintBitsToFloat(c.xyz), c.w);
}

ShapeRecord shape_load(uint i) {
    uvec4 w = imageLoad(shape_texels, int(i));
    return ShapeRecord(w.x, w.y, w.z, w.w);
}

TriangleRecord triangle_load(uint i) {
    uvec4 w = triangle_texel(i);
    return TriangleRecord(w.x, w.y, w.z, w.w);
}

// Texel k (0: normal and u; 1: v) of vertex i.
vec4 vertex_texel(uint i, uint k) {
    return uintBitsToFloat(vertex_texel_raw(2u * i + k));
}

Vertex vertex_load(uint i) {
    uvec4 a = vertex_texel_raw(2u * i);
    uvec4 b = vertex_texel_raw(2u * i + 1u);
    return Vertex(uintBitsToFloat(a.x), uintBitsToFloat(a.y), uintBitsToFloat(a.z), uintBitsToFloat(a.w),
                  uintBitsToFloat(b.x), b.y, b.z, b.w);
}

// BsdfRecord: 16 texels (6 of fields, the 8 of `table`, 2 of texture maps).
BsdfRecord bsdf_load(uint i) {
    int b = int(16u * i);
    uvec4 w0 = imageLoad(bsdf_texels, b);
    uvec4 w1 = imageLoad(bsdf_texels, b + 1);
    uvec4 w2 = imageLoad(bsdf_texels, b + 2);
    uvec4 w3 = imageLoad(bsdf_texels, b + 3);
    uvec4 w4 = imageLoad(bsdf_texels, b + 4);
    uvec4 w5 = imageLoad(bsdf_texels, b + 5);
    BsdfRecord r;
    r.reflectance = uintBitsToFloat(w0.xyz);
    r.kind = w0.w;
    r.specular = uintBitsToFloat(w1.xyz);
    r.flags = w1.w;
    r.transmittance = uintBitsToFloat(w2.xyz);
    r.eta = uintBitsToFloat(w2.w);
    r.cond_eta = uintBitsToFloat(w3.xyz);
    r.alpha_u = uintBitsToFloat(w3.w);
    r.cond_k = uintBitsToFloat(w4.xyz);
    r.alpha_v = uintBitsToFloat(w4.w);
    r.distribution = w5.x;
    r.specular_weight = uintBitsToFloat(w5.y);
    r.internal = uintBitsToFloat(w5.z);
    r.pad0 = w5.w;
    for (int k = 0; k < 8; k++) {
        r.table[k] = uintBitsToFloat(imageLoad(bsdf_texels, b + 6 + k));
    }
    uvec4 w14 = imageLoad(bsdf_texels, b + 14);
    uvec4 w15 = imageLoad(bsdf_texels, b + 15);
    r.tex_reflectance = w14.x;
    r.tex_specular = w14.y;
    r.tex_transmittance = w14.z;
    r.tex_alpha_u = w14.w;
    r.tex_alpha_v = w15.x;
    r.normal_map = w15.y;
    r.pad1 = w15.z;
    r.pad2 = w15.w;
    return r;
}

// EmitterRecord: 9 texels.
EmitterRecord emitter_load(uint i) {
    int b = int(9u * i);
    uvec4 w0 = imageLoad(emitter_texels, b);
    uvec4 w1 = imageLoad(emitter_texels, b + 1);
    uvec4 w2 = imageLoad(emitter_texels, b + 2);
    uvec4 w3 = imageLoad(emitter_texels, b + 3);
    uvec4 w4 = imageLoad(emitter_texels, b + 4);
    uvec4 w5 = imageLoad(emitter_texels, b + 5);
    return EmitterRecord(uintBitsToFloat(w0.xyz), w0.w, uintBitsToFloat(w1.xyz), w1.w,
                         uintBitsToFloat(w2.xyz), uintBitsToFloat(w2.w),
                         uintBitsToFloat(w3.x), uintBitsToFloat(w3.y), uintBitsToFloat(w3.z), uintBitsToFloat(w3.w),
                         w4.x, w4.y, w4.z, w4.w, w5.x, w5.y, w5.z, w5.w,
                         uintBitsToFloat(imageLoad(emitter_texels, b + 6)),
                         uintBitsToFloat(imageLoad(emitter_texels, b + 7)),
                         uintBitsToFloat(imageLoad(emitter_texels, b + 8)));
}

AliasEntry alias_load(uint i) {
    uvec4 w = imageLoad(alias_texels, int(i));
    return AliasEntry(uintBitsToFloat(w.x), w.y, uintBitsToFloat(w.z), w.w);
}

#endif
