// Descriptor set 0: the scene, read-only for every kernel that includes this file.
// Bindings are mirrored in src/render/scene_buffers.rs.
#ifndef SCENE_BINDINGS_GLSL
#define SCENE_BINDINGS_GLSL

#include "layout.glsl"

// BVH nodes and primitives are storage texel buffers read with imageLoad
// (BindingKind::Texels in src/gpu/kernel.rs: llvmpipe gathers an image load at
// scattered addresses inline, much faster than it loads from a storage buffer or
// calls its texel-fetch function): 4 and 3 uvec4 texels a record, read through
// bvh_node_load and prim_load below.
layout(set = 0, binding = 0, rgba32ui) uniform readonly uimageBuffer bvh_node_texels;
layout(set = 0, binding = 1, rgba32ui) uniform readonly uimageBuffer prim_texels;
// Shapes and triangles (one texel each) and vertices (two) likewise: read them
// with shape_load, triangle_load and vertex_load.
layout(set = 0, binding = 2, rgba32ui) uniform readonly uimageBuffer shape_texels;
layout(set = 0, binding = 3, rgba32ui) uniform readonly uimageBuffer triangle_texels;
layout(set = 0, binding = 4, rgba32ui) uniform readonly uimageBuffer vertex_texels;
// BSDFs, emitters and alias tables: texel buffers too (bsdf_load, emitter_load,
// alias_load).
layout(set = 0, binding = 5, rgba32ui) uniform readonly uimageBuffer bsdf_texels;
layout(set = 0, binding = 6, rgba32ui) uniform readonly uimageBuffer emitter_texels;
// Emitter alias table at [0, emitter_count), then each mesh emitter's triangle table.
layout(set = 0, binding = 7, rgba32ui) uniform readonly uimageBuffer alias_texels;
// Textures (texture.glsl): records (texture_load), and every bitmap's RGB texels, three
// floats each (texel_value).
layout(set = 0, binding = 8, rgba32ui) uniform readonly uimageBuffer texture_texels;
layout(set = 0, binding = 9, r32ui) uniform readonly uimageBuffer texel_words;
// Environment map sampling distributions (envmap.glsl; env_dist).
layout(set = 0, binding = 10, r32ui) uniform readonly uimageBuffer env_dist_words;
// Media (shaders/common/medium.glsl): records (medium_load), density and albedo grids
// (grid_value), majorant grids (majorant_value), and density grids packed a texel per
// voxel (grid_packed; MEDIUM_DENSITY_PACKED).
layout(set = 0, binding = 11, rgba32ui) uniform readonly uimageBuffer medium_texels;
layout(set = 0, binding = 12, r32ui) uniform readonly uimageBuffer grid_words;
layout(set = 0, binding = 13, r32ui) uniform readonly uimageBuffer majorant_words;
layout(set = 0, binding = 14, rgba32ui) uniform readonly uimageBuffer grid_packed_texels;

float texel_value(uint k) { return uintBitsToFloat(imageLoad(texel_words, int(k)).x); }
float env_dist(uint k) { return uintBitsToFloat(imageLoad(env_dist_words, int(k)).x); }
float grid_value(uint k) { return uintBitsToFloat(imageLoad(grid_words, int(k)).x); }
float majorant_value(uint k) { return uintBitsToFloat(imageLoad(majorant_words, int(k)).x); }
vec4 grid_packed(uint k) { return uintBitsToFloat(imageLoad(grid_packed_texels, int(k))); }

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
    int base = int(4u * i);
    uvec4 a = imageLoad(bvh_node_texels, base);
    uvec4 b = imageLoad(bvh_node_texels, base + 1);
    uvec4 c = imageLoad(bvh_node_texels, base + 2);
    uvec4 d = imageLoad(bvh_node_texels, base + 3);
    return BvhNode(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w,
                   uintBitsToFloat(c.xyz), c.w, uintBitsToFloat(d.xyz), d.w);
}

Prim prim_load(uint i) {
    int base = int(3u * i);
    uvec4 a = imageLoad(prim_texels, base);
    uvec4 b = imageLoad(prim_texels, base + 1);
    uvec4 c = imageLoad(prim_texels, base + 2);
    return Prim(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w, uintBitsToFloat(c.xyz), c.w);
}

ShapeRecord shape_load(uint i) {
    uvec4 w = imageLoad(shape_texels, int(i));
    return ShapeRecord(w.x, w.y, w.z, w.w);
}

TriangleRecord triangle_load(uint i) {
    uvec4 w = imageLoad(triangle_texels, int(i));
    return TriangleRecord(w.x, w.y, w.z, w.w);
}

// Texel k (0: normal and u; 1: v) of vertex i.
vec4 vertex_texel(uint i, uint k) {
    return uintBitsToFloat(imageLoad(vertex_texels, int(2u * i + k)));
}

Vertex vertex_load(uint i) {
    uvec4 a = imageLoad(vertex_texels, int(2u * i));
    uvec4 b = imageLoad(vertex_texels, int(2u * i + 1u));
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
