// Textures: texture_eval(id, uv) for a texture id (index + 1, as BsdfRecord and
// EmitterRecord store them). Needs scene_bindings.glsl. The CPU reference, with the
// conventions (Mitsuba 3's bitmap and checkerboard) and the XML parameters, is
// src/scene/texture.rs; tests/texture_lookups_gpu_vs_cpu.rs checks that the two agree.
//
// Kinds a scene does not use compile away: define TEXTURE_KINDS (a bit per
// TEXTURE_* kind) before including this file; the default keeps all.
#ifndef TEXTURE_GLSL
#define TEXTURE_GLSL

#ifndef TEXTURE_KINDS
#define TEXTURE_KINDS 0xffffffffu
#endif
#define TEXTURE_HAS(k) ((TEXTURE_KINDS & (1u << (k))) != 0u)
// Features of the same mask (TEXTURE_FEATURE_* in layout.glsl): textured BSDF
// parameters, normal maps, environment maps, textured area emitters.
#define TEXTURE_USES(f) ((TEXTURE_KINDS & (f)) != 0u)

#include "numeric/convert.glsl"
#include "texture/texture_hit.glsl"

// A texel index brought into [0, n) by the wrap mode (as Mitsuba's, on indices).
// The remainder of i by m comes from a float quotient, corrected by one step either
// way: llvmpipe (Mesa 22.3) has no vector integer division and divides lane by lane
// (an integer % took a quarter of the shade time of scenes/textures/textures.xml).
// Exact for |i| <= 2^22 (texture_footprint's indices; convert.glsl).
int texture_wrap(int i, int n, uint mode) {
    if (mode == TEXTURE_WRAP_CLAMP) return clamp(i, 0, n - 1);
    int m = mode == TEXTURE_WRAP_MIRROR ? 2 * n : n;
    int r = i - m * trunc_to_int(floor(float(i) / float(m)));
    if (r < 0) r += m;
    if (r >= m) r -= m;
    return (mode == TEXTURE_WRAP_MIRROR && r >= n) ? 2 * n - 1 - r : r;
}

vec3 texture_texel(TextureRecord t, int x, int y) {
    uint k = t.offset + 3u * (uint(y) * t.width + uint(x));
    return vec3(texel_value(k), texel_value(k + 1u), texel_value(k + 2u));
}

// The texels a lookup at p (already through to_uv) reads, on a W x H grid with the
// texture's flags (wrap mode, filter): texel (i, j) centred at ((i+½)/W, (j+½)/H), row 0
// at v = 0; corners (xa, ya) .. (xb, yb) wrapped into the grid and bilinear weights
// (fx, fy). Nearest is the bilinear footprint with the texel (⌊pW⌋, ⌊pH⌋) as its first
// corner and weights 0 on the others, mix(a, b, 0) = a for finite texels: llvmpipe runs
// both sides of a branch, so a separate nearest path would cost every bilinear lookup
// its texel reads too. Bitmaps and textured emitters' densities (emitter_texture.glsl)
// look up their grids through it.
struct TexelFootprint {
    int xa, xb, ya, yb;
    float fx, fy;
};

TexelFootprint texture_footprint(uint flags, int w, int h, vec2 p) {
    uint mode = (flags >> TEXTURE_WRAP_SHIFT) & 3u;
    bool nearest = (flags & TEXTURE_NEAREST) != 0u;
    float x = p.x * float(w);
    float y = p.y * float(h);
    if (!nearest) {
        x -= 0.5;
        y -= 0.5;
    }
    float x0f = floor(x), y0f = floor(y);
    TexelFootprint f;
    f.fx = nearest ? 0.0 : x - x0f;
    f.fy = nearest ? 0.0 : y - y0f;
    // Indices within 2^22 texels of the origin (convert.glsl's range), beyond which a
    // float coordinate no longer resolves a texel anyway (its ulp is half a texel).
    const float far = 4194303.0;
    int x0 = trunc_to_int(clamp(x0f, -far, far)), y0 = trunc_to_int(clamp(y0f, -far, far));
    f.xa = texture_wrap(x0, w, mode);
    f.xb = texture_wrap(x0 + 1, w, mode);
    f.ya = texture_wrap(y0, h, mode);
    f.yb = texture_wrap(y0 + 1, h, mode);
    return f;
}

// Bitmap at p (already through to_uv), nearest or bilinear (texture_footprint).
vec3 texture_bitmap(TextureRecord t, vec2 p) {
    TexelFootprint f = texture_footprint(t.flags, int(t.width), int(t.height), p);
    vec3 a = mix(texture_texel(t, f.xa, f.ya), texture_texel(t, f.xb, f.ya), f.fx);
    vec3 b = mix(texture_texel(t, f.xa, f.yb), texture_texel(t, f.xb, f.yb), f.fx);
    return mix(a, b, f.fy);
}

// Integer hash of a lattice point (lattice_hash in texture.rs).
uint texture_hash(int x, int y, uint seed) {
    uint h = (uint(x) * 0x8da6b343u) ^ (uint(y) * 0xd8163841u) ^ (seed * 0xcb1ab31fu);
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    h *= 0x846ca68bu;
    h ^= h >> 16;
    return h;
}

// Gradient of a lattice point (one of eight unit directions) dotted with offset d.
float texture_grad(uint h, vec2 d) {
    const float S = 0.70710678;
    switch (h & 7u) {
    case 0u: return d.x;
    case 1u: return -d.x;
    case 2u: return d.y;
    case 3u: return -d.y;
    case 4u: return S * (d.x + d.y);
    case 5u: return S * (-d.x + d.y);
    case 6u: return S * (d.x - d.y);
    default: return S * (-d.x - d.y);
    }
}

// Perlin's quintic fade 6t⁵ − 15t⁴ + 10t³ (Perlin 2002, "Improving Noise").
vec2 texture_fade(vec2 t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

// 2D gradient noise in [-1, 1] (Perlin 2002), gradients from a hash of the lattice.
float texture_perlin(vec2 p, uint seed) {
    vec2 i = floor(p);
    vec2 f = p - i;
    int x = int(i.x), y = int(i.y);
    float n00 = texture_grad(texture_hash(x, y, seed), f);
    float n10 = texture_grad(texture_hash(x + 1, y, seed), f - vec2(1.0, 0.0));
    float n01 = texture_grad(texture_hash(x, y + 1, seed), f - vec2(0.0, 1.0));
    float n11 = texture_grad(texture_hash(x + 1, y + 1, seed), f - vec2(1.0, 1.0));
    vec2 s = texture_fade(f);
    float a = n00 + s.x * (n10 - n00);
    float b = n01 + s.x * (n11 - n01);
    return 1.41421356 * (a + s.y * (b - a));
}

// Fractal Brownian motion: octaves at doubling frequency, halving amplitude, in [-1, 1].
float texture_fbm(vec2 p, uint octaves, uint seed) {
    float sum = 0.0, amp = 1.0, norm = 0.0, freq = 1.0;
    for (uint o = 0u; o < octaves; o++) {
        sum += amp * texture_perlin(p * freq, seed + o);
        norm += amp;
        amp *= 0.5;
        freq *= 2.0;
    }
    return norm > 0.0 ? sum / norm : 0.0;
}

// Channel values k.. of a mesh attribute of `dim` channels (1: broadcast).
vec3 texture_attribute_at(uint k, uint dim) {
    float x = texel_value(k);
    return dim == 1u ? vec3(x) : vec3(x, texel_value(k + 1u), texel_value(k + 2u));
}

// Mitsuba's mesh_attribute at the hit of the latest surface_at (texture_hit.glsl):
// a face attribute as stored for the triangle, a vertex attribute interpolated by the
// barycentrics (Mesh::interpolate_attribute), times the scale; 0 on a shape without
// it (the loader refuses those that read it). The shape's table word is the start
// of its values, offset so that the global triangle or vertex number indexes them.
vec3 texture_mesh_attribute(TextureRecord t) {
    uint base = texel_word(t.offset + texture_hit_shape).x;
    if (base == NONE) return vec3(0.0);
    uint dim = t.width;
    vec3 value;
    if ((t.flags & TEXTURE_ATTRIBUTE_FACE) != 0u) {
        value = texture_attribute_at(base + dim * texture_hit_triangle, dim);
    } else {
        TriangleRecord tri = triangle_load(texture_hit_triangle);
        vec2 b = texture_hit_bary;
        value = texture_attribute_at(base + dim * tri.v0, dim) * (1.0 - b.x - b.y)
            + texture_attribute_at(base + dim * tri.v1, dim) * b.x
            + texture_attribute_at(base + dim * tri.v2, dim) * b.y;
    }
    return value * t.frequency;
}

vec3 texture_eval(uint id, vec2 uv) {
    TextureRecord t = texture_load(id - 1u);
    vec2 p = vec2(dot(t.to_uv_u.xyz, vec3(uv, 1.0)), dot(t.to_uv_v.xyz, vec3(uv, 1.0)));
    switch (t.kind) {
    case TEXTURE_CONSTANT:
        if (TEXTURE_HAS(TEXTURE_CONSTANT)) return t.color0;
        break;
    case TEXTURE_MESH_ATTRIBUTE:
        if (TEXTURE_HAS(TEXTURE_MESH_ATTRIBUTE)) return texture_mesh_attribute(t);
        break;
    case TEXTURE_BITMAP:
        if (TEXTURE_HAS(TEXTURE_BITMAP)) return texture_bitmap(t, p);
        break;
    case TEXTURE_CHECKERBOARD:
        if (TEXTURE_HAS(TEXTURE_CHECKERBOARD)) {
            vec2 f = p - floor(p);
            return ((f.x > 0.5) == (f.y > 0.5)) ? t.color0 : t.color1;
        }
        break;
    case TEXTURE_NOISE:
        if (TEXTURE_HAS(TEXTURE_NOISE)) {
            float n = texture_fbm(p * t.frequency, t.octaves, t.seed);
            return mix(t.color0, t.color1, 0.5 + 0.5 * n);
        }
        break;
    case TEXTURE_MARBLE:
        if (TEXTURE_HAS(TEXTURE_MARBLE)) {
            // Stripes along u bent by fBm, through a cosine (Perlin 1985, marble).
            vec2 q = p * t.frequency;
            float n = texture_fbm(q, t.octaves, t.seed);
            float s = 0.5 - 0.5 * cos(6.28318531 * (q.x + t.variation * n));
            return mix(t.color0, t.color1, s);
        }
        break;
    }
    return vec3(0.0);
}

// Luminance of linear sRGB (Rec. 709): a texture read as a float.
float texture_luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// The color c = texture_eval(id, uv) as Mitsuba's eval_1 sees it: Mitsuba's
// checkerboard eval_1 swaps the squares of eval (see texture_eval_1).
vec3 texture_eval_1_color(uint id, vec3 c) {
    if (TEXTURE_HAS(TEXTURE_CHECKERBOARD)) {
        TextureRecord t = texture_load(id - 1u);
        if (t.kind == TEXTURE_CHECKERBOARD) c = c == t.color0 ? t.color1 : t.color0;
    }
    return c;
}

// Texture id read as a float, as Mitsuba's Texture::eval_1 (what its BSDFs read for
// scalar parameters: principled's): the luminance of texture_eval, except that
// Mitsuba's checkerboard eval_1 swaps the squares of eval (src/textures/checkerboard.cpp
// tests mask.x != mask.y where eval tests ==; Mitsuba 3.9.1 renders so).
float texture_eval_1(uint id, vec2 uv) { return texture_luminance(texture_eval_1_color(id, texture_eval(id, uv))); }

#endif
