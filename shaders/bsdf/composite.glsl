// Composite BSDFs (src/scene/bsdf/composite.rs): Mitsuba 3's mask, blendbsdf and
// twosided with two sides and bumpmap, resolved at a surface point into one leaf record, so that
// the kernels evaluate and sample one model per vertex without recursion. A blend
// (a mask is a blend of the pass-through mask_null and its BSDF by the opacity)
// takes child 1 with probability w and child 0 with 1 − w, from the vertex's lobe
// number u, which is rescaled to [0, 1) for the leaf (as Mitsuba's blendbsdf::sample
// and mask::sample): the mean of what the vertex evaluates and samples is the blend
// (pbrt-v4's MixMaterial). Needs scene_bindings.glsl, texture.glsl, surface.glsl,
// bsdf.glsl (BSDF_COMPOSITE, BSDF_HAS), normal_map.glsl.
#ifndef BSDF_COMPOSITE_GLSL
#define BSDF_COMPOSITE_GLSL

// BsdfRecord.distribution of a node (kind BSDF_COMPOSITE).
#define COMPOSITE_BLEND 0u
#define COMPOSITE_TWOSIDED 1u
#define COMPOSITE_BUMP 2u
// Deepest nesting resolved (the loader's trees are finite; this bounds the loop).
#define COMPOSITE_MAX_DEPTH 16

// The leaf a surface point resolves to: its record index, the flags to add to it
// (BSDF_TWOSIDED where a twosided node chose a side), the lobe number left for it, and
// whether a bump map replaced the shading frame (then nm is its frame, as a normal
// map's: normal_map.glsl).
struct CompositeLeaf {
    uint index;
    uint flags;
    float u;
    bool bumped;
    NormalMapFrame nm;
};

// The gradient (∂h/∂u, ∂h/∂v) of texture `id`'s luminance at uv, as Mitsuba's
// Texture::eval_1_grad: a bitmap's bilinear interpolation differentiated within its
// texel cell (0 for nearest filtering) and taken through its to_uv map; other
// textures by central differences.
vec2 composite_height_grad(uint id, vec2 uv) {
    TextureRecord t = texture_load(id - 1u);
    vec2 grad;
    if (TEXTURE_HAS(TEXTURE_BITMAP) && t.kind == TEXTURE_BITMAP) {
        vec2 p = vec2(dot(t.to_uv_u.xyz, vec3(uv, 1.0)), dot(t.to_uv_v.xyz, vec3(uv, 1.0)));
        TexelFootprint f = texture_footprint(t.flags, int(t.width), int(t.height), p);
        float f00 = texture_luminance(texture_texel(t, f.xa, f.ya));
        float f10 = texture_luminance(texture_texel(t, f.xb, f.ya));
        float f01 = texture_luminance(texture_texel(t, f.xa, f.yb));
        float f11 = texture_luminance(texture_texel(t, f.xb, f.yb));
        bool nearest = (t.flags & TEXTURE_NEAREST) != 0u;
        // ∂h/∂x, ∂h/∂y in texels, then per unit of p, then through to_uv (transposed).
        vec2 dxy = vec2(mix(f10 - f00, f11 - f01, f.fy), mix(f01 - f00, f11 - f10, f.fx));
        vec2 dp = nearest ? vec2(0.0) : dxy * vec2(float(t.width), float(t.height));
        grad = vec2(t.to_uv_u.x * dp.x + t.to_uv_v.x * dp.y, t.to_uv_u.y * dp.x + t.to_uv_v.y * dp.y);
    } else {
        const float H = 1e-3;
        grad = vec2(texture_eval_1(id, uv + vec2(H, 0.0)) - texture_eval_1(id, uv - vec2(H, 0.0)),
                    texture_eval_1(id, uv + vec2(0.0, H)) - texture_eval_1(id, uv - vec2(0.0, H)))
            / (2.0 * H);
    }
    return grad;
}

// ∂p/∂u and ∂p/∂v of primitive `prim` at barycentrics (or a disk's point) bary, as
// Mitsuba's shapes give them: a triangle's from its uvs (its edges without uvs), a
// sphere's from its (φ/2π, θ/π) parameterization. Other quadrics take the shading
// frame's unit axes (their bump maps tilt by the gradient per unit length).
void composite_derivatives(uint prim_index, vec2 bary, Surface s, out vec3 dpdu, out vec3 dpdv) {
    Prim prim = prim_load(prim_index);
    dpdu = s.ss;
    dpdv = cross(s.ns, s.ss);
    if (prim.kind == PRIM_TRIANGLE) {
        ShapeRecord shape = shape_load(prim.shape);
        vec3 dp0 = prim.p1 - prim.p0, dp1 = prim.p2 - prim.p0;
        dpdu = dp0;
        dpdv = dp1;
        if (SURFACE_HAS(SURFACE_FEATURE_UVS) && (shape.flags & SHAPE_HAS_UVS) != 0u) {
            TriangleRecord tri = triangle_load(prim.index);
            vec2 uv0 = vec2(vertex_texel(tri.v0, 0u).w, vertex_texel(tri.v0, 1u).x);
            vec2 uv1 = vec2(vertex_texel(tri.v1, 0u).w, vertex_texel(tri.v1, 1u).x);
            vec2 uv2 = vec2(vertex_texel(tri.v2, 0u).w, vertex_texel(tri.v2, 1u).x);
            vec2 duv0 = uv1 - uv0, duv1 = uv2 - uv0;
            float det = duv0.x * duv1.y - duv0.y * duv1.x;
            if (det != 0.0) {
                dpdu = (duv1.y * dp0 - duv0.y * dp1) / det;
                dpdv = (duv0.x * dp1 - duv1.x * dp0) / det;
            }
        }
    } else if (SURFACE_HAS(SURFACE_FEATURE_SPHERES) && prim.kind == PRIM_SPHERE) {
        ShapeRecord shape = shape_load(prim.shape);
        float mirror = (shape.flags & SHAPE_MIRRORED) != 0u ? -1.0 : 1.0;
        float r = length(prim.p1);
        vec3 a3 = mirror * cross(prim.p1, prim.p2) / r;
        vec3 d = normalize(s.p - prim.p0);
        vec3 l = vec3(dot(d, prim.p1), dot(d, prim.p2), dot(d, a3)) / r;
        float rd = length(l.xy);
        dpdu = 2.0 * PI * (l.x * prim.p2 - l.y * prim.p1);
        dpdv = rd > 0.0 ? PI * (l.z * (l.x * prim.p1 + l.y * prim.p2) / rd - rd * a3) : PI * prim.p1;
    }
}

// Resolves BSDF record `index` at surface point s of primitive `prim` (barycentrics
// bary) seen from wo (world, towards the viewer) with the uniform number u. Records
// that are not nodes resolve to themselves. A bump map replaces s.ns and s.ss.
CompositeLeaf bsdf_composite_resolve(uint index, inout Surface s, uint prim, vec2 bary, vec3 wo, float u) {
    CompositeLeaf leaf = CompositeLeaf(index, 0u, u, false, NormalMapFrame(s.ns, s.ns, 0.0));
    if (!BSDF_HAS(BSDF_COMPOSITE)) return leaf;
    for (int i = 0; i < COMPOSITE_MAX_DEPTH; i++) {
        BsdfRecord b = bsdf_load(leaf.index);
        if (b.kind != BSDF_COMPOSITE) break;
        uint c0 = b.tex_specular, c1 = b.tex_transmittance;
        if (b.distribution == COMPOSITE_TWOSIDED) {
            // Mitsuba's twosided: the back (wo below the shading normal) scatters by
            // its own BSDF in the mirrored frame.
            bool back = dot(wo, s.ns) < 0.0;
            leaf.index = back ? c1 : c0;
            leaf.flags |= BSDF_TWOSIDED;
        } else if (b.distribution == COMPOSITE_BUMP) {
            // Mitsuba 3.9's bumpmap::frame: ∂p/∂u and ∂p/∂v tilted along the shading
            // normal by the scaled height gradient; their cross product, turned to
            // the geometric normal's side, is the new shading normal (flipped as a
            // normal map's where it faces away from wo), and ∂p/∂u made orthogonal to
            // it the new tangent.
            vec3 dpdu, dpdv;
            composite_derivatives(prim, bary, s, dpdu, dpdv);
            vec2 g = b.eta * composite_height_grad(b.tex_reflectance, s.uv);
            vec3 du = dpdu + s.ns * (g.x - dot(s.ns, dpdu));
            vec3 dv = dpdv + s.ns * (g.y - dot(s.ns, dpdv));
            vec3 n = cross(du, dv);
            float len = length(n);
            if (len > 0.0) {
                n /= len;
                if (dot(s.ng, n) < 0.0) n = -n;
                vec3 n0 = s.ns;
                if ((b.flags & BSDF_NORMALMAP_FLIP) != 0u && dot(wo, n0) * dot(wo, n) <= 0.0) {
                    n = 2.0 * dot(n, n0) * n0 - n; // the tangential part negated
                }
                leaf.bumped = true;
                leaf.nm.n0 = n0;
                leaf.nm.n = n;
                // Estevez et al. 2019's roughness of the tilt (normal_map_frame_texel).
                leaf.nm.alpha2 = (b.flags & BSDF_NORMALMAP_SHADOWING) != 0u ? min(0.125 * normal_map_tan2(dot(n, n0)), 1.0) : 0.0;
                s.ns = n;
                s.ss = surface_tangent(dpdu, n);
            }
            leaf.index = c0;
        } else {
            // Blend or mask: w is child 1's probability, the texture read as Mitsuba's
            // eval_1 (Mitsuba clamps it to [0, 1]).
            float w = b.tex_reflectance != 0u ? texture_eval_1(b.tex_reflectance, s.uv) : b.eta;
            w = clamp(w, 0.0, 1.0);
            bool second = leaf.u < w;
            leaf.index = second ? c1 : c0;
            leaf.u = second ? leaf.u / w : (leaf.u - w) / (1.0 - w);
            leaf.u = min(leaf.u, 0.99999994);
        }
    }
    return leaf;
}

#endif
