// Descriptor set 0: the scene, read-only for every kernel that includes this file.
// Bindings are mirrored in src/render/scene_buffers.rs.
#ifndef SCENE_BINDINGS_GLSL
#define SCENE_BINDINGS_GLSL

#include "layout.glsl"

// BVH nodes and primitives are texel buffers (BindingKind::Texels in src/gpu/kernel.rs:
// llvmpipe gathers a texel fetch at scattered addresses much faster than it loads from
// a storage buffer): 4 and 3 uvec4 texels a record, read through bvh_node_load and
// prim_load below.
layout(set = 0, binding = 0) uniform usamplerBuffer bvh_node_texels;
layout(set = 0, binding = 1) uniform usamplerBuffer prim_texels;
// Shapes (one texel each), triangles and vertices (4-byte texels) likewise: read them
// with shape_load, triangle_load and vertex_load.
layout(set = 0, binding = 2) uniform usamplerBuffer shape_texels;
layout(set = 0, binding = 3) uniform usamplerBuffer triangle_words;
layout(set = 0, binding = 4) uniform usamplerBuffer vertex_words;
layout(std430, set = 0, binding = 5) readonly buffer BsdfBuffer { BsdfRecord bsdfs[]; };
layout(std430, set = 0, binding = 6) readonly buffer EmitterBuffer { EmitterRecord emitters[]; };
// Emitter alias table at [0, emitter_count), then each mesh emitter's triangle table.
layout(std430, set = 0, binding = 7) readonly buffer AliasBuffer { AliasEntry alias_table[]; };

BvhNode bvh_node_load(uint i) {
    int base = int(4u * i);
    uvec4 a = texelFetch(bvh_node_texels, base);
    uvec4 b = texelFetch(bvh_node_texels, base + 1);
    uvec4 c = texelFetch(bvh_node_texels, base + 2);
    uvec4 d = texelFetch(bvh_node_texels, base + 3);
    return BvhNode(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w,
                   uintBitsToFloat(c.xyz), c.w, uintBitsToFloat(d.xyz), d.w);
}

Prim prim_load(uint i) {
    int base = int(3u * i);
    uvec4 a = texelFetch(prim_texels, base);
    uvec4 b = texelFetch(prim_texels, base + 1);
    uvec4 c = texelFetch(prim_texels, base + 2);
    return Prim(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w, uintBitsToFloat(c.xyz), c.w);
}

ShapeRecord shape_load(uint i) {
    uvec4 w = texelFetch(shape_texels, int(i));
    return ShapeRecord(w.x, w.y, w.z, w.w);
}

TriangleRecord triangle_load(uint i) {
    int b = int(3u * i);
    return TriangleRecord(texelFetch(triangle_words, b).x, texelFetch(triangle_words, b + 1).x,
                          texelFetch(triangle_words, b + 2).x);
}

Vertex vertex_load(uint i) {
    int b = int(5u * i);
    return Vertex(uintBitsToFloat(texelFetch(vertex_words, b).x), uintBitsToFloat(texelFetch(vertex_words, b + 1).x),
                  uintBitsToFloat(texelFetch(vertex_words, b + 2).x), uintBitsToFloat(texelFetch(vertex_words, b + 3).x),
                  uintBitsToFloat(texelFetch(vertex_words, b + 4).x));
}

#endif
