// Descriptor set 0: the scene, read-only for every kernel that includes this file.
// Bindings are mirrored in src/render/scene_buffers.rs.
#ifndef SCENE_BINDINGS_GLSL
#define SCENE_BINDINGS_GLSL

#include "layout.glsl"

layout(std430, set = 0, binding = 0) readonly buffer BvhNodeBuffer { BvhNode bvh_nodes[]; };
layout(std430, set = 0, binding = 1) readonly buffer PrimBuffer { Prim prims[]; };
layout(std430, set = 0, binding = 2) readonly buffer ShapeBuffer { ShapeRecord shapes[]; };
layout(std430, set = 0, binding = 3) readonly buffer TriangleBuffer { TriangleRecord triangles[]; };
layout(std430, set = 0, binding = 4) readonly buffer VertexBuffer { Vertex vertices[]; };
layout(std430, set = 0, binding = 5) readonly buffer BsdfBuffer { BsdfRecord bsdfs[]; };
layout(std430, set = 0, binding = 6) readonly buffer EmitterBuffer { EmitterRecord emitters[]; };
// Emitter alias table at [0, emitter_count), then each mesh emitter's triangle table.
layout(std430, set = 0, binding = 7) readonly buffer AliasBuffer { AliasEntry alias_table[]; };
// Textures (texture.glsl): records, and every bitmap's RGB texels, three floats each.
layout(std430, set = 0, binding = 8) readonly buffer TextureBuffer { TextureRecord textures[]; };
layout(std430, set = 0, binding = 9) readonly buffer TexelBuffer { float texels[]; };
// Environment map sampling distributions (envmap.glsl).
layout(std430, set = 0, binding = 10) readonly buffer EnvDistBuffer { float env_dist[]; };

#endif
