// Composite BSDFs (src/scene/bsdf/composite.rs): Mitsuba 3's mask, blendbsdf and
// twosided with two sides and bumpmap, resolved at a surface point without recursion.
// The path tracers resolve a tree into its leaves and mix them as Mitsuba does
// (bsdf_composite_mix, bsdf_composite_others, below). The photon mappers resolve it
// into one leaf record (bsdf_composite_resolve): a blend (a mask is a blend of the
// pass-through mask_null and its BSDF by the opacity) takes child 1 with probability
// w and child 0 with 1 − w, from the vertex's lobe number u, which is rescaled to
// [0, 1) for the leaf: the mean of what the vertex evaluates and samples is the blend
// (pbrt-v4's MixMaterial). Needs scene_bindings.glsl, texture.glsl, surface.glsl,
// bsdf.glsl (BSDF_COMPOSITE, BSDF_HAS), bsdf_textured.glsl, normal_map.glsl.
#ifndef BSDF_COMPOSITE_GLSL
#define BSDF_COMPOSITE_GLSL

// BsdfRecord.distribution of a node (kind BSDF_COMPOSITE).
#define COMPOSITE_BLEND 0u
#define COMPOSITE_TWOSIDED 1u
#define COMPOSITE_BUMP 2u
// Deepest nesting resolved (the loader's trees are finite; this bounds the loop).
#define COMPOSITE_MAX_DEPTH 16

#include "sampling/rng.glsl"
#include "bsdf/mixture.glsl"
#include "bsdf/mask_crossing.glsl"

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

// A bump map's node b at s seen from wo (Mitsuba 3.9's bumpmap::frame): ∂p/∂u and
// ∂p/∂v tilted along the shading normal by the scaled height gradient; their cross
// product, turned to the geometric normal's side, is the new shading normal (flipped
// as a normal map's where it faces away from wo), and ∂p/∂u made orthogonal to it the
// new tangent. Replaces s.ns and s.ss and sets nm (n0, n and the shadowing roughness),
// unless the tilted frame is degenerate (then false, s unchanged).
bool composite_bump(BsdfRecord b, inout Surface s, uint prim, vec2 bary, vec3 wo, inout NormalMapFrame nm) {
    vec3 dpdu, dpdv;
    composite_derivatives(prim, bary, s, dpdu, dpdv);
    vec2 g = b.eta * composite_height_grad(b.tex_reflectance, s.uv);
    vec3 du = dpdu + s.ns * (g.x - dot(s.ns, dpdu));
    vec3 dv = dpdv + s.ns * (g.y - dot(s.ns, dpdv));
    vec3 n = cross(du, dv);
    float len = length(n);
    if (!(len > 0.0)) return false;
    n /= len;
    if (dot(s.ng, n) < 0.0) n = -n;
    vec3 n0 = s.ns;
    if ((b.flags & BSDF_NORMALMAP_FLIP) != 0u && dot(wo, n0) * dot(wo, n) <= 0.0) {
        n = 2.0 * dot(n, n0) * n0 - n; // the tangential part negated
    }
    nm.n0 = n0;
    nm.n = n;
    // Estevez et al. 2019's roughness of the tilt (normal_map_frame_texel).
    nm.alpha2 = (b.flags & BSDF_NORMALMAP_SHADOWING) != 0u ? min(0.125 * normal_map_tan2(dot(n, n0)), 1.0) : 0.0;
    s.ns = n;
    s.ss = surface_tangent(dpdu, n);
    return true;
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
            if (composite_bump(b, s, prim, bary, wo, leaf.nm)) leaf.bumped = true;
            leaf.index = c0;
        } else {
            // Blend or mask: w is child 1's probability.
            float w = bsdf_blend_weight(b, s.uv);
            bool second = leaf.u < w;
            leaf.index = second ? c1 : c0;
            leaf.u = second ? leaf.u / w : (leaf.u - w) / (1.0 - w);
            leaf.u = min(leaf.u, 0.99999994);
        }
    }
    return leaf;
}

// The path tracers mix a blend's children as Mitsuba's blendbsdf does (Mitsuba 3.9.1,
// src/bsdfs/blendbsdf.cpp and mask.cpp): the tree resolves into up to
// COMPOSITE_MAX_LEAVES leaves, each with the product of the weights on its branch,
// and f = Σ wₖ fₖ, pdf = Σ wₖ pdfₖ. Sampling picks leaf j with probability wⱼ (by
// the lobe number, rescaled for the leaf) and samples it, weighed as mixture.glsl
// says (a delta sample by the leaf's own weight, unbiased where Mitsuba 3.9.1's is
// not). path.glsl evaluates the chosen leaf as a single model and the
// others through bsdf_composite_others. Leaves are listed child 1 before child 0, so
// the chosen leaf is the one bsdf_composite_resolve picks with the same number (the
// photon mappers' visible points rely on it). A blend whose two sides would need more
// leaves than there is room for picks one side by its weight, with a number hashed
// from the lobe number, and the side stands for the blend (unbiased, noisier).
#define COMPOSITE_MAX_LEAVES 4
// Nodes visited at most (the loader's trees are finite; this bounds the loop).
#define COMPOSITE_MAX_STEPS 32
// Branches a depth-first walk of a whole tree holds at once (bsdf_composite_null_pass).
#define COMPOSITE_WALK_STACK 8

// One branch of the tree: the record it reached, the flags to add to the record
// (BSDF_TWOSIDED below a twosided node), its weight, and, where a bump map tilted the
// frame (bumped), the new frame (nm.n the shading normal, ss the tangent).
struct CompositeBranch {
    uint index;
    uint flags;
    float weight;
    bool bumped;
    NormalMapFrame nm;
    vec3 ss;
};

// The leaves of a tree (leaf[0, count)), the one the lobe number chose (chosen) with
// the number left for it (u), whether every leaf is delta only (no emitter
// sampling), and whether a blend's side was picked for lack of room (sampled: the
// leaves are then one draw of a random mixture whose mean is the tree's).
struct CompositeMix {
    uint count;
    uint chosen;
    float u;
    bool all_delta;
    bool sampled;
    CompositeBranch leaf[COMPOSITE_MAX_LEAVES];
};

// The leaves of BSDF record `index` at surface point s of primitive `prim`
// (barycentrics bary) seen from wo (world, towards the viewer); u is the vertex's
// lobe number. A record that is no node is its own single leaf.
CompositeMix bsdf_composite_mix(uint index, Surface s, uint prim, vec2 bary, vec3 wo, float u) {
    CompositeMix m;
    m.count = 0u;
    m.chosen = 0u;
    m.u = u;
    m.all_delta = true;
    m.sampled = false;
    bool found = false;
    float below = 0.0; // the weight of the leaves listed so far
    CompositeBranch stack[COMPOSITE_MAX_LEAVES];
    stack[0] = CompositeBranch(index, 0u, 1.0, false, NormalMapFrame(s.ns, s.ns, 0.0), s.ss);
    uint top = 1u;
    for (int i = 0; i < COMPOSITE_MAX_STEPS && top > 0u; i++) {
        top--;
        CompositeBranch e = stack[top];
        BsdfRecord b = bsdf_load(e.index);
        if (b.kind != BSDF_COMPOSITE) {
            m.leaf[m.count] = e;
            m.all_delta = m.all_delta && bsdf_is_delta(b);
            if (!found && u < below + e.weight) {
                found = true;
                m.chosen = m.count;
                m.u = min(max(u - below, 0.0) / e.weight, 0.99999994);
            }
            below += e.weight;
            m.count++;
            continue;
        }
        Surface se = s;
        if (e.bumped) {
            se.ns = e.nm.n;
            se.ss = e.ss;
        }
        uint c0 = b.tex_specular, c1 = b.tex_transmittance;
        if (b.distribution == COMPOSITE_TWOSIDED) {
            // Mitsuba's twosided: the back (wo below the shading normal) scatters by
            // its own BSDF in the mirrored frame.
            e.index = dot(wo, se.ns) < 0.0 ? c1 : c0;
            e.flags |= BSDF_TWOSIDED;
            stack[top++] = e;
        } else if (b.distribution == COMPOSITE_BUMP) {
            if (composite_bump(b, se, prim, bary, wo, e.nm)) {
                e.bumped = true;
                e.ss = se.ss;
            }
            e.index = c0;
            stack[top++] = e;
        } else {
            // Blend or mask: child 1 has weight w, child 0 1 − w. Child 0 goes below
            // child 1 on the stack, so that child 1's leaves come first.
            float w = bsdf_blend_weight(b, s.uv);
            if (w > 0.0 && w < 1.0 && m.count + top + 2u <= uint(COMPOSITE_MAX_LEAVES)) {
                CompositeBranch e1 = e;
                e.index = c0;
                e.weight *= 1.0 - w;
                e1.index = c1;
                e1.weight *= w;
                stack[top++] = e;
                stack[top++] = e1;
            } else {
                float v = rng_to_float(rng_pcg4d(uvec4(floatBitsToUint(u), e.index, m.count, top)).x);
                e.index = v < w ? c1 : c0;
                m.sampled = m.sampled || (w > 0.0 && w < 1.0);
                stack[top++] = e;
            }
        }
    }
    if (!found && m.count > 0u) {
        // The weights' sum rounded below u: the last leaf.
        m.chosen = m.count - 1u;
        m.u = 0.99999994;
    }
    return m;
}

// The weight of the leaves of m that are not pass-throughs (mask_null).
float bsdf_composite_solid_weight(CompositeMix m) {
    float total = 0.0;
    for (uint k = 0u; k < m.count; k++) {
        if (bsdf_load(m.leaf[k].index).kind != BSDF_MASK_NULL) total += m.leaf[k].weight;
    }
    return total;
}

// The leaves of m without its pass-throughs (mask_null), their weights divided by
// what remains, the leaf chosen anew by the lobe number u (as bsdf_composite_mix
// chooses): the BSDF at a surface that a volumetric path did not pass
// (mask_crossing.glsl). m as it is where nothing remains.
CompositeMix bsdf_composite_solid(CompositeMix m, float u) {
    CompositeMix r;
    r.count = 0u;
    r.chosen = 0u;
    r.u = u;
    r.all_delta = true;
    r.sampled = m.sampled;
    float total = 0.0;
    for (uint k = 0u; k < m.count; k++) {
        CompositeBranch e = m.leaf[k];
        BsdfRecord b = bsdf_load(e.index);
        if (b.kind == BSDF_MASK_NULL) continue;
        r.leaf[r.count] = e;
        r.all_delta = r.all_delta && bsdf_is_delta(b);
        total += e.weight;
        r.count++;
    }
    if (r.count == 0u || !(total > 0.0)) return m;
    bool found = false;
    float below = 0.0;
    for (uint k = 0u; k < r.count; k++) {
        r.leaf[k].weight /= total;
        float w = r.leaf[k].weight;
        if (!found && u < below + w) {
            found = true;
            r.chosen = k;
            r.u = min(max(u - below, 0.0) / w, 0.99999994);
        }
        below += w;
    }
    if (!found) {
        r.chosen = r.count - 1u;
        r.u = 0.99999994;
    }
    return r;
}

// How a ray going on along dir passes the tree of record `index` at surface point s
// of primitive `prim` (barycentrics bary), as Mitsuba 3.9.1's BSDF::sample does for
// its Null lobe: x the probability of a pass-through (the sum over the mask_null
// leaves wₖ, the product of the blend and mask weights above each, bump maps passed),
// y its expected weight Σ wₖ gₖ, gₖ the product over the bump maps above leaf k of
// what bumpmap::sample multiplies a sample by: its shadowing term (normal_map_weight:
// Estevez et al. 2019, 2 / (1 + √(1 + α² tan²θ)), θ the angle of dir to the bump
// map's unperturbed normal) and 0 where dir lies on different sides of that normal
// and the bumped one. blendbsdf::sample keeps a pass-through's weight gₖ where the
// blend's other side has no value at −wi (a reflecting BSDF; elsewhere wavetrace
// keeps it too, as its note on delta samples above says). Without bump maps x = y.
// Each branch keeps its frame (ns, ss) as bsdf_composite_mix does, so a bump map
// below another one tilts the tilted frame.
vec2 bsdf_composite_null_pass(uint index, Surface s, uint prim, vec2 bary, vec3 dir) {
    vec2 sum = vec2(0.0);
    // A branch: its record, its weight and g so far, its shading frame.
    uint stack[COMPOSITE_WALK_STACK];
    vec2 weight[COMPOSITE_WALK_STACK];
    vec3 ns[COMPOSITE_WALK_STACK];
    vec3 ss[COMPOSITE_WALK_STACK];
    stack[0] = index;
    weight[0] = vec2(1.0);
    ns[0] = s.ns;
    ss[0] = s.ss;
    uint top = 1u;
    for (int i = 0; i < COMPOSITE_MAX_STEPS && top > 0u; i++) {
        top--;
        uint k = stack[top];
        vec2 w0 = weight[top];
        Surface se = s;
        se.ns = ns[top];
        se.ss = ss[top];
        BsdfRecord b = bsdf_load(k);
        if (b.kind == BSDF_MASK_NULL) sum += w0;
        if (b.kind != BSDF_COMPOSITE || b.distribution == COMPOSITE_TWOSIDED) continue;
        if (b.distribution == COMPOSITE_BUMP) {
            NormalMapFrame nm = NormalMapFrame(se.ns, se.ns, 0.0);
            if (composite_bump(b, se, prim, bary, -dir, nm)) w0.y *= normal_map_weight(nm, dir);
            stack[top] = b.tex_specular;
            weight[top] = w0;
            ns[top] = se.ns;
            ss[top++] = se.ss;
            continue;
        }
        // Blend or mask: child 1 has weight w, child 0 1 − w.
        float w = bsdf_blend_weight(b, s.uv);
        if (top + 2u <= uint(COMPOSITE_WALK_STACK)) {
            stack[top] = b.tex_specular;
            weight[top] = w0 * (1.0 - w);
            ns[top] = se.ns;
            ss[top++] = se.ss;
            stack[top] = b.tex_transmittance;
            weight[top] = w0 * w;
            ns[top] = se.ns;
            ss[top++] = se.ss;
        }
    }
    return sum;
}

// Σ wₖ (fₖ(wo, wi) |cos θi|, pdfₖ(wo, wi)) over the leaves of m other than the chosen
// one, for world directions wo (towards the viewer) and wi, each leaf in its own frame
// from the surface s as it was before any bump map: its bump map's, then its normal
// map's (as path_shade_to treats the chosen leaf, the normal map's factor included).
vec4 bsdf_composite_others(CompositeMix m, Surface s, vec3 wo, vec3 wi) {
    vec4 sum = vec4(0.0);
    for (uint k = 0u; k < m.count; k++) {
        if (k == m.chosen) continue;
        CompositeBranch e = m.leaf[k];
        Surface se = s;
        bool mapped = e.bumped;
        NormalMapFrame nm = e.nm;
        if (e.bumped) {
            se.ns = e.nm.n;
            se.ss = e.ss;
        }
        BsdfRecord b = bsdf_textured(bsdf_load(e.index), s.uv);
        b.flags |= e.flags;
        if (TEXTURE_USES(TEXTURE_FEATURE_NORMALMAP) && b.normal_map != 0u) {
            mapped = true;
            nm = normal_map_frame(b, se, wo);
            se.ns = nm.n;
            se.ss = surface_tangent(se.ss, se.ns);
            b.flags &= ~BSDF_TWOSIDED;
        }
        vec3 wo_l = surface_to_local(se, wo);
        vec3 wi_l = surface_to_local(se, wi);
        float f_m = mapped ? normal_map_weight(nm, wi) : 1.0;
        vec3 f = f_m > 0.0 ? f_m * bsdf_eval(b, wo_l, wi_l, s.uv) : vec3(0.0);
        sum += e.weight * vec4(f, bsdf_pdf(b, wo_l, wi_l, s.uv));
    }
    return sum;
}

#endif
