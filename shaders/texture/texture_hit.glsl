// The surface hit a texture lookup belongs to, for textures that read the hit mesh
// rather than the uv (mesh_attribute, texture.glsl): the shape, the global triangle
// number and the barycentrics (u, v) of the latest surface_at (surface.glsl), which
// records them only in scenes with such textures (TEXTURE_KINDS). A lookup follows
// the surface_at of its point, as every caller's does (the shading point, an
// emitter's sampled point, a shadow ray's crossing).
#ifndef TEXTURE_HIT_GLSL
#define TEXTURE_HIT_GLSL

uint texture_hit_shape = 0u;
uint texture_hit_triangle = 0u;
vec2 texture_hit_bary = vec2(0.0);

// Whether the scene has textures that read the hit (a kernel without TEXTURE_KINDS
// defined yet records it: only the lookups' absence compiles it away there).
#ifdef TEXTURE_KINDS
#define TEXTURE_HIT_USED ((TEXTURE_KINDS & (1u << TEXTURE_MESH_ATTRIBUTE)) != 0u)
#else
#define TEXTURE_HIT_USED true
#endif

void texture_hit_set(uint shape, uint triangle, vec2 bary) {
    if (TEXTURE_HIT_USED) {
        texture_hit_shape = shape;
        texture_hit_triangle = triangle;
        texture_hit_bary = bary;
    }
}

#endif
