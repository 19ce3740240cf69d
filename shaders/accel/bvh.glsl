// BVH traversal: closest hit, any hit, and the two nearest hits (bvh_closest_two). The
// first two mirror Bvh::trace in src/accel/bvh.rs step for step; the layout is BvhNode /
// Prim from layout.glsl (Aila, Laine 2009: both children's boxes in the parent;
// count == 0: inner node, count > 0: leaf).
//
// The including kernel must include scene_bindings.glsl (bvh_node_load, prim_load) first.
// Optional: #define BVH_PRIM_KINDS to the quadric kinds the scene has (a mask of
// SURFACE_FEATURE_SPHERES, _DISKS, _CYLINDERS; e.g. a specialization constant) before
// including, so the tests of absent kinds compile out.
#ifndef BVH_GLSL
#define BVH_GLSL

#ifndef SCENE_BINDINGS_GLSL
#error "include scene_bindings.glsl before bvh.glsl"
#endif

#include "scene/layout.glsl"
#include "generated/spec_constants.glsl"
#include "shape/intersect_triangle.glsl"
#include "shape/intersect_sphere.glsl"
#include "shape/intersect_disk.glsl"
#include "shape/intersect_cylinder.glsl"
#include "shape/intersect_sdfgrid.glsl"
#include "shape/intersect_curve.glsl"
#include "shape/intersect_bspline.glsl"
#include "shape/intersect_ellipsoid.glsl"
#include "accel/instance.glsl"

// Traversal stack entries; the build keeps every leaf at depth <= this (root = 0).
// Must equal accel::BVH_STACK_SIZE (a Rust test reads this line).
#define BVH_STACK_SIZE 32
// Stack entries are child references packed as (index << BVH_COUNT_BITS) | count.
#define BVH_COUNT_BITS 4u
#define BVH_COUNT_MASK 15u
// Item meaning "nothing left to visit" (a leaf reference no BVH can have).
#define BVH_DONE 0xffffffffu
// Item meaning "the group's tree of an instance is done: back to world space" (a leaf
// reference no BVH can have either: leaves hold at most 8 primitives).
#define BVH_LEAVE 0xfffffffeu
// 1 + 2 gamma(3) rounded up to a float (Ize 2013, "Robust BVH Ray Traversal", JCGT 2(2)):
// the box far distance is scaled so rounding never culls a box the ray enters.
#define BVH_TFAR_SCALE 1.00000048
#define HIT_NONE 0xffffffffu

#ifndef BVH_PRIM_KINDS
#define BVH_PRIM_KINDS 0xffffffffu
#endif
#define BVH_HAS(f) ((BVH_PRIM_KINDS & (f)) != 0u)

// Entries of the traversal stack: the tree's deepest leaf depth bounds them, so the
// including kernel may #define BVH_STACK_DEPTH to a specialization constant holding
// the scene's (BvhStats::stack_depth: the deepest leaf's depth, at least 1, at most
// BVH_STACK_SIZE).
#ifndef BVH_STACK_DEPTH
#define BVH_STACK_DEPTH BVH_STACK_SIZE
#endif

// The primitives at the start of prims[] that are tested in turn (bvh_trace_flat),
// and whether the tree follows (accel::FlatPrims; two specialization constants): the
// including kernel may #define BVH_FLAT_PRIMS to their count, with BVH_FLAT_ONLY set
// where they are every primitive of the scene (a scene of a few: no tree), and
// BVH_FLAT_KINDS to the PRIM_* kinds of the first BVH_FLAT_CAPACITY, two bits each,
// primitive k at bit 2k; any after those are triangles. Without BVH_FLAT_ONLY they are
// the scene's few quadrics (accel::Bvh::apart), and the tree holds the triangles
// alone. 0: the tree holds every primitive.
#define BVH_FLAT_CAPACITY 16
#define BVH_FLAT_ONLY 0x10000u
// With BVH_FLAT_VERTEX_CONSTANTS also set, the vertices of the triangles tested in turn
// are the constants FLAT_P<k>_<i> (gpu::spec_ids::flat_vertex) rather than loads: a load
// every lane makes from one address costs llvmpipe a bounds check per word, a constant
// nothing (the Cornell box at 16 lanes, its first 16 triangles: 1.38 -> 1.21 s).
#define BVH_FLAT_VERTEX_CONSTANTS 0x20000u
#ifndef BVH_FLAT_PRIMS
#define BVH_FLAT_PRIMS 0u
#endif
#ifndef BVH_FLAT_KINDS
#define BVH_FLAT_KINDS 0u
#endif
#define BVH_FLAT_COUNT (BVH_FLAT_PRIMS & 0xffffu)
// The PRIM_* kind of primitive k (a literal) of those tested in turn.
#define BVH_FLAT_KIND(k)                                                                 \
    (uint(k) < uint(BVH_FLAT_CAPACITY) ? (BVH_FLAT_KINDS >> (2u * (uint(k) & 15u))) & 3u \
                                       : PRIM_TRIANGLE)
#define BVH_TREE ((BVH_FLAT_PRIMS & BVH_FLAT_ONLY) == 0u)
#define BVH_VERTEX_CONSTANTS ((BVH_FLAT_PRIMS & BVH_FLAT_VERTEX_CONSTANTS) != 0u)
SPEC(FLAT_VERTICES)
// Primitive k (a literal) of those tested in turn, a triangle's vertices from the
// constants where they hold them (the other fields are not read by a flat step's
// test). Quadrics are loaded: their tests compute from their vertices alone (a
// sphere's radius), which the compiler would fold with other roundings.
#define BVH_FLAT_PRIM(k)                                                                 \
    (BVH_VERTEX_CONSTANTS && BVH_FLAT_KIND(k) == PRIM_TRIANGLE                           \
         ? Prim(vec3(FLAT_P##k##_0, FLAT_P##k##_1, FLAT_P##k##_2), 0u,                   \
                vec3(FLAT_P##k##_3, FLAT_P##k##_4, FLAT_P##k##_5), 0u,                   \
                vec3(FLAT_P##k##_6, FLAT_P##k##_7, FLAT_P##k##_8), 0u)                   \
         : prim_load(uint(k)))

// t: distance (tmax on a miss); u, v: triangle barycentrics, p = (1-u-v) p0 + u p1 + v p2,
// or a disk's object-space (x, y), or a curve segment's parameter in u (0 for spheres
// and cylinders); prim: index into
// prims[], HIT_NONE on a miss.
struct Hit {
    float t;
    float u;
    float v;
    uint prim;
};

// Per-ray part of the slab test: inverse direction (+-inf for a zero or denormal
// component: Vulkan leaves x / y unspecified for |y| < 2^-126) and its sign, which
// picks each axis' near plane.
struct BvhRay {
    vec3 o;
    vec3 inv;
    bvec3 neg;
};

float bvh_inv(float d) {
    return abs(d) >= 1.17549435e-38 ? 1.0 / d : uintBitsToFloat(d < 0.0 ? 0xff800000u : 0x7f800000u);
}

// Whether the ray enters the box within [tmin, tmax]; tnear: the entry distance.
// Compare-and-select, not min/max (undefined on NaN): 0 * inf = NaN, from an origin on
// the slab plane of a zero direction component, fails the comparison and is ignored.
// The empty box (min = +inf, max = -inf) is never entered.
bool bvh_slab(BvhRay r, vec3 bmin, vec3 bmax, float tmin, float tmax, out float tnear) {
    vec3 t0 = (mix(bmin, bmax, r.neg) - r.o) * r.inv;
    vec3 t1 = (mix(bmax, bmin, r.neg) - r.o) * r.inv;
    float tn = tmin;
    float tf = tmax;
    tn = t0.x > tn ? t0.x : tn;
    tf = t1.x < tf ? t1.x : tf;
    tn = t0.y > tn ? t0.y : tn;
    tf = t1.y < tf ? t1.y : tf;
    tn = t0.z > tn ? t0.z : tn;
    tf = t1.z < tf ? t1.z : tf;
    tnear = tn;
    return tn <= tf * BVH_TFAR_SCALE;
}

// The traversal stack lives in registers and shifts on every push and pop: stack[0]
// is the top, and popping an empty stack yields BVH_DONE. Once the loops unroll every
// index is a constant, so a push or a pop is BVH_STACK_DEPTH selects per SIMD vector.
// An array indexed by a per-lane stack pointer is a scatter or a gather across the
// lanes instead, which llvmpipe runs as a loop over the lanes that branches on each
// lane's mask: on lavapipe the shifting stack rendered the Cornell box (depth 6) 28%
// faster and Nori's table scene (depth 19) 25% faster, and at depth 32 it still wins.
#define BVH_STACK_PUSH(stack, x)                                                         \
    {                                                                                    \
        for (int k_ = BVH_STACK_DEPTH - 1; k_ > 0; k_--) stack[k_] = stack[k_ - 1];      \
        stack[0] = (x);                                                                  \
    }
#define BVH_STACK_POP(stack, x)                                                          \
    {                                                                                    \
        x = stack[0];                                                                    \
        for (int k_ = 0; k_ < BVH_STACK_DEPTH - 1; k_++) stack[k_] = stack[k_ + 1];      \
        stack[BVH_STACK_DEPTH - 1] = BVH_DONE;                                           \
    }

// A bit per PRIM_* kind, for bvh_prim_hit_of.
#define BVH_KIND_BIT(k) (1u << (k))

// Whether ray (o, d) hits primitive p within (tmin, tmax): its distance t and (u, v)
// as in Hit. tr: triangle_ray_make(d). `kinds` (BVH_KIND_BIT of each kind p may be;
// a constant) compiles the tests of the others away, and with one kind the test of
// p.kind too.
bool bvh_prim_hit_of(uint kinds, Prim p, TriangleRay tr, vec3 o, vec3 d, float tmin,
                     float tmax, out float t, out float u, out float v) {
    u = 0.0;
    v = 0.0;
    t = tmax;
    bool one = bitCount(kinds) == 1;
    if ((kinds & BVH_KIND_BIT(PRIM_SPHERE)) != 0u && (one || p.kind == PRIM_SPHERE)) {
        return intersect_sphere(o, d, p.p0, length(p.p1), tmin, tmax, t);
    } else if ((kinds & BVH_KIND_BIT(PRIM_DISK)) != 0u && (one || p.kind == PRIM_DISK)) {
        vec2 xy;
        bool found = intersect_disk(o, d, p.p0, p.p1, p.p2, tmin, tmax, t, xy);
        u = xy.x;
        v = xy.y;
        return found;
    } else if ((kinds & BVH_KIND_BIT(PRIM_CYLINDER)) != 0u && (one || p.kind == PRIM_CYLINDER)) {
        return intersect_cylinder(o, d, p.p0, p.p2, length(p.p1), tmin, tmax, t);
    } else if ((kinds & BVH_KIND_BIT(PRIM_SDFGRID)) != 0u && (one || p.kind == PRIM_SDFGRID)) {
        // u: the voxel hit, for the hit geometry (sdf_surface).
        return intersect_sdfgrid(o, d, p, tmin, tmax, t, u);
    } else if ((kinds & BVH_KIND_BIT(PRIM_LINEAR_CURVE)) != 0u
               && (one || p.kind == PRIM_LINEAR_CURVE)) {
        return intersect_linear_curve(o, d, p.p0, p.p1, p.p2.x, p.p2.y, p.p2.z < 0.0, tmin, tmax,
                                      t, u);
    } else if ((kinds & BVH_KIND_BIT(PRIM_BSPLINE_CURVE)) != 0u
               && (one || p.kind == PRIM_BSPLINE_CURVE)) {
        // u: the segment's parameter (surface_bspline_curve).
        vec4 cp[4];
        bspline_points(floatBitsToUint(p.p2.x), cp);
        return intersect_bspline_curve(o, d, cp, tmin, tmax, t, u);
    } else if ((kinds & BVH_KIND_BIT(PRIM_ELLIPSOID)) != 0u && (one || p.kind == PRIM_ELLIPSOID)) {
        return intersect_ellipsoid(o, d, floatBitsToUint(p.p2.x), tmin, tmax, t);
    } else if ((kinds & BVH_KIND_BIT(PRIM_TRIANGLE)) != 0u) {
        return intersect_triangle(tr, o, p.p0, p.p1, p.p2, tmin, tmax, t, u, v);
    }
    return false;
}

// The kinds a scene's tree may hold: triangles, curves and the quadrics of
// BVH_PRIM_KINDS, or triangles and curves where the quadrics are tested apart;
// sdfgrids are never apart.
#define BVH_KINDS (BVH_KIND_BIT(PRIM_TRIANGLE)                                          \
    | (BVH_HAS(SURFACE_FEATURE_SDFGRIDS) ? BVH_KIND_BIT(PRIM_SDFGRID) : 0u)             \
    | (BVH_HAS(SURFACE_FEATURE_LINEAR_CURVES) ? BVH_KIND_BIT(PRIM_LINEAR_CURVE) : 0u)   \
    | (BVH_HAS(SURFACE_FEATURE_BSPLINE_CURVES) ? BVH_KIND_BIT(PRIM_BSPLINE_CURVE) : 0u) \
    | (BVH_HAS(SURFACE_FEATURE_ELLIPSOIDS) ? BVH_KIND_BIT(PRIM_ELLIPSOID) : 0u)         \
    | (BVH_FLAT_COUNT > 0u ? 0u :                                                       \
       ((BVH_HAS(SURFACE_FEATURE_SPHERES) ? BVH_KIND_BIT(PRIM_SPHERE) : 0u)             \
        | (BVH_HAS(SURFACE_FEATURE_DISKS) ? BVH_KIND_BIT(PRIM_DISK) : 0u)               \
        | (BVH_HAS(SURFACE_FEATURE_CYLINDERS) ? BVH_KIND_BIT(PRIM_CYLINDER) : 0u))))

bool bvh_prim_hit(Prim p, TriangleRay tr, vec3 o, vec3 d, float tmin, float tmax,
                  out float t, out float u, out float v) {
    return bvh_prim_hit_of(BVH_KINDS, p, tr, o, d, tmin, tmax, t, u, v);
}

// What a traversal looks for (bvh_trace's `mode`, a constant at every call, so the
// others' code compiles away): the closest hit; any hit (stops at the first found);
// the two closest hits (the closest, and the nearest of the others, ties included).
#define BVH_CLOSEST 0u
#define BVH_ANY 1u
#define BVH_TWO 2u

// Records a hit at t < the traversal's bound (bvh_bound): in BVH_TWO mode the nearer of
// the two kept moves to `second` when the new one is nearer, else the new one is second.
void bvh_record(uint mode, inout Hit hit, inout Hit second, Hit found) {
    if (mode == BVH_TWO && !(found.t < hit.t)) {
        second = found;
    } else {
        if (mode == BVH_TWO) second = hit;
        hit = found;
    }
}

// The distance beyond which a traversal no longer looks.
float bvh_bound(uint mode, Hit hit, Hit second) { return mode == BVH_TWO ? second.t : hit.t; }

// Primitive k of those tested in turn, only for its own kind: once BVH_FLAT_PRIMS and
// BVH_FLAT_KINDS are specialized, a step past the last one compiles away and `kinds`
// is a constant with one bit.
#define BVH_FLAT_STEP(k)                                                                 \
    if (uint(k) < BVH_FLAT_COUNT) {                                                      \
        float t, u, v;                                                                   \
        uint kinds = BVH_KIND_BIT(BVH_FLAT_KIND(k));                                     \
        if (bvh_prim_hit_of(kinds, BVH_FLAT_PRIM(k), tr, o, d, tmin,                     \
                            bvh_bound(mode, hit, second), t, u, v)) {                    \
            bvh_record(mode, hit, second, Hit(t, u, v, uint(k)));                        \
        }                                                                                \
    }

// The primitives tested in turn (BVH_FLAT_COUNT of them: every one of a small scene,
// or the quadrics apart from the tree), in order, as accel::brute_force_closest does
// (of equal distances, the lowest index), recorded into hit and second. Without a tree
// there are no node loads, no stack and no leaf loop, and each primitive is loaded from
// an address common to all lanes and tested for its one kind: on llvmpipe (Mesa 22.3),
// which loads per lane and runs every branch of a leaf's kind test for every lane, this
// costs far less than a traversal of a few primitives (accel::FLAT_PRIMS_MAX), and a
// few quadrics cost less here than in the leaves of a tree of triangles
// (accel::APART_QUADRICS_MAX). The steps are written out, one per primitive the
// flat traversal may hold (accel::FLAT_STEPS: scenes of up to
// accel::FLAT_PRIMS_MAX_WIDE on llvmpipe at 16 lanes), each for its own kind (the first
// BVH_FLAT_CAPACITY's from BVH_FLAT_KINDS, triangles after them), because Mesa unrolls
// no loop with a body this large, and a loop's triangles are loads where written-out
// steps take their vertices from constants. Every ray tests every primitive: any-hit
// queries gain nothing from stopping early on llvmpipe.
void bvh_trace_flat(vec3 o, vec3 d, TriangleRay tr, float tmin, uint mode, inout Hit hit,
                    inout Hit second) {
    BVH_FLAT_STEP(0) BVH_FLAT_STEP(1) BVH_FLAT_STEP(2) BVH_FLAT_STEP(3)
    BVH_FLAT_STEP(4) BVH_FLAT_STEP(5) BVH_FLAT_STEP(6) BVH_FLAT_STEP(7)
    BVH_FLAT_STEP(8) BVH_FLAT_STEP(9) BVH_FLAT_STEP(10) BVH_FLAT_STEP(11)
    BVH_FLAT_STEP(12) BVH_FLAT_STEP(13) BVH_FLAT_STEP(14) BVH_FLAT_STEP(15)
    BVH_FLAT_STEP(16) BVH_FLAT_STEP(17) BVH_FLAT_STEP(18) BVH_FLAT_STEP(19)
    BVH_FLAT_STEP(20) BVH_FLAT_STEP(21) BVH_FLAT_STEP(22) BVH_FLAT_STEP(23)
    BVH_FLAT_STEP(24) BVH_FLAT_STEP(25) BVH_FLAT_STEP(26) BVH_FLAT_STEP(27)
    BVH_FLAT_STEP(28) BVH_FLAT_STEP(29) BVH_FLAT_STEP(30) BVH_FLAT_STEP(31)
    BVH_FLAT_STEP(32) BVH_FLAT_STEP(33) BVH_FLAT_STEP(34) BVH_FLAT_STEP(35)
    BVH_FLAT_STEP(36) BVH_FLAT_STEP(37) BVH_FLAT_STEP(38) BVH_FLAT_STEP(39)
}

// Stack traversal visiting the nearer child first, for what `mode` asks (BVH_CLOSEST,
// BVH_ANY: returns at the first hit found, BVH_TWO: `second` too; a miss in it has
// t = tmax). Requires 0 <= tmin and d != 0. `division_last` (a constant): triangles
// are tested without a division first (intersect_triangle), which pays where most
// SIMD groups find no candidate in most triangles: shadow rays, coherent rays
// (camera rays, whose lanes are neighbouring pixels), and the two-hit rays of media
// scenes (mostly inside a medium's few boundary triangles); for the scattered
// closest-hit rays of a closed room it costs more than it saves (at 16 lanes, Cornell
// box: shadow rays -8%, camera rays -10%, rays from bounce 2 on +11%; media cube, its
// two-hit rays: 0.713 -> 0.679 s). The primitives tested in turn
// (bvh_trace_flat) come first; the tree, if the scene has one, after them.
//
// No return inside the loops (an any-hit query breaks out of both): spirv-opt's
// merge-return (gpu::specialize's INLINE_PASSES) would turn one into flags tested
// after each loop.
Hit bvh_trace(vec3 o, vec3 d, float tmin, float tmax, uint mode, bool division_last,
              out Hit second) {
    TriangleRay tr = triangle_ray_make(d);
    tr.division_last = division_last;
    Hit hit = Hit(tmax, 0.0, 0.0, HIT_NONE);
    second = hit;
    if (BVH_FLAT_COUNT > 0u) bvh_trace_flat(o, d, tr, tmin, mode, hit, second);
    if (!BVH_TREE) return hit;
    BvhRay r;
    r.o = o;
    r.inv = vec3(bvh_inv(d.x), bvh_inv(d.y), bvh_inv(d.z));
    r.neg = lessThan(r.inv, vec3(0.0));
    uint stack[BVH_STACK_DEPTH];
    for (int k = 0; k < BVH_STACK_DEPTH; k++) stack[k] = BVH_DONE;
    // Instances (instance.glsl): the world ray, kept while the ray is in a group's
    // space, and the instance part of the hit names found there (0 outside).
    vec3 world_o = o;
    vec3 world_d = d;
    uint name = 0u;
    // The current child reference: inner node 0 (done for an any-hit query already
    // answered by a primitive tested in turn).
    uint item = (BVH_FLAT_COUNT > 0u && mode == BVH_ANY && hit.prim != HIT_NONE) ? BVH_DONE : 0u;
    // "While-while" order (Aila, Laine 2009): descend through inner nodes until a leaf
    // is found, then test its primitives. SIMD lanes (llvmpipe, GPU warps) step
    // through inner nodes together and through leaves together, instead of paying for
    // both in every iteration where some lanes are at a leaf and others are not.
    // The inner loops are do-whiles behind an if: llvmpipe (Mesa 22.3) tests whether
    // any lane goes on only at the end of a loop's body, so a while loop also runs
    // its body (masked off) in the pass in which its condition stops the last lane:
    // one node visit and one primitive test more per leaf.
    while (true) {
        if ((item & BVH_COUNT_MASK) == 0u) do {
            BvhNode n = bvh_node_load(item >> BVH_COUNT_BITS);
            float tl, tr_;
            float bound = bvh_bound(mode, hit, second);
            bool hit_l = bvh_slab(r, n.left_min, n.left_max, tmin, bound, tl);
            bool hit_r = bvh_slab(r, n.right_min, n.right_max, tmin, bound, tr_);
            uint left = (n.left_index << BVH_COUNT_BITS) | n.left_count;
            uint right = (n.right_index << BVH_COUNT_BITS) | n.right_count;
            if (hit_l && hit_r) { // go to the nearer, push the other
                bool left_near = tl <= tr_;
                BVH_STACK_PUSH(stack, left_near ? right : left);
                item = left_near ? left : right;
            } else if (hit_l || hit_r) {
                item = hit_l ? left : right;
            } else {
                BVH_STACK_POP(stack, item);
            }
        } while ((item & BVH_COUNT_MASK) == 0u);
        if (item == BVH_DONE) {
            break;
        }
        if (INSTANCED && item == BVH_LEAVE) { // back from an instance's group
            o = world_o;
            d = world_d;
            tr = triangle_ray_make(d);
            r.o = o;
            r.inv = vec3(bvh_inv(d.x), bvh_inv(d.y), bvh_inv(d.z));
            r.neg = lessThan(r.inv, vec3(0.0));
            name = 0u;
            BVH_STACK_POP(stack, item);
            continue;
        }
        uint index = item >> BVH_COUNT_BITS;
        uint count = item & BVH_COUNT_MASK; // a leaf holds at least one primitive
        if (INSTANCED && index >= BVH_INSTANCE_SLOTS) {
            // A leaf of instances k .. end - 1 (instance.glsl), which has no boxes of
            // its own: each in turn, the ray moves to the group's space (an affine map
            // keeps t) and meets the box of its root node there, or the next is tried,
            // with no stack traffic. Into the first it meets: the rest of the leaf and
            // the way back wait on the stack, and the group's tree is walked from its
            // root.
            uint k = index - BVH_INSTANCE_SLOTS;
            uint end = k + count;
            bool into = false;
            uint root;
            BvhRay ir;
            do {
                InstanceMap m = instance_to_object(k);
                ir.o = instance_point(m, world_o);
                vec3 id = instance_vector(m, world_d);
                ir.inv = vec3(bvh_inv(id.x), bvh_inv(id.y), bvh_inv(id.z));
                ir.neg = lessThan(ir.inv, vec3(0.0));
                root = instance_root(k);
                BvhNode n = bvh_node_load(root);
                float tn;
                into = bvh_slab(ir, min(n.left_min, n.right_min), max(n.left_max, n.right_max),
                                tmin, bvh_bound(mode, hit, second), tn);
                d = id;
                k++;
            } while (!into && k < end);
            if (into) {
                if (k < end) BVH_STACK_PUSH(stack, ((k + BVH_INSTANCE_SLOTS) << BVH_COUNT_BITS) | (end - k));
                BVH_STACK_PUSH(stack, BVH_LEAVE);
                r = ir;
                o = ir.o;
                tr = triangle_ray_make(d);
                name = k << INSTANCE_SHIFT; // instance k - 1, plus 1
                item = root << BVH_COUNT_BITS;
            } else {
                d = world_d;
                BVH_STACK_POP(stack, item);
            }
            continue;
        }
        uint i = index;
        do {
            float t, u, v;
            Prim p = prim_load(i);
            if (bvh_prim_hit(p, tr, o, d, tmin, bvh_bound(mode, hit, second), t, u, v)) {
                bvh_record(mode, hit, second, Hit(t, u, v, INSTANCED ? (name | i) : i));
                if (mode == BVH_ANY) break;
            }
            i++;
        } while (i < index + count);
        // An any-hit query is answered by its first hit.
        if (mode == BVH_ANY && hit.prim != HIT_NONE) break;
        BVH_STACK_POP(stack, item);
    }
    return hit;
}

// Closest hit with tmin < t < tmax; prim == HIT_NONE on a miss.
Hit bvh_closest(vec3 o, vec3 d, float tmin, float tmax) {
    Hit unused;
    return bvh_trace(o, d, tmin, tmax, BVH_CLOSEST, false, unused);
}

// bvh_closest for rays whose SIMD lanes are coherent (camera rays): the same hits,
// found sooner (bvh_trace's division_last).
Hit bvh_closest_coherent(vec3 o, vec3 d, float tmin, float tmax) {
    Hit unused;
    return bvh_trace(o, d, tmin, tmax, BVH_CLOSEST, true, unused);
}

// Whether anything is hit with tmin < t < tmax (shadow rays); stops at the first hit.
bool bvh_any(vec3 o, vec3 d, float tmin, float tmax) {
    Hit unused;
    return bvh_trace(o, d, tmin, tmax, BVH_ANY, true, unused).prim != HIT_NONE;
}

// The closest hit with tmin < t < tmax and, in `second`, the nearest of the others
// (t >= the closest's; prim == HIT_NONE and t = tmax if there is none): a ray that
// passes through the closest surface (a null boundary) goes on to `second` without a
// second traversal (transmittance.glsl, vol_path.glsl). Its traversal prunes by the
// second's distance, so it visits more of the tree than bvh_closest.
// A primitive is tested once, for its nearest hit: a sphere or a cylinder may be hit
// again before `second` (bvh_hit_once says where that cannot be).
Hit bvh_closest_two(vec3 o, vec3 d, float tmin, float tmax, out Hit second) {
    return bvh_trace(o, d, tmin, tmax, BVH_TWO, true, second);
}

// Whether a ray meets primitive p at most once (it is flat): then bvh_closest_two's
// `second` is what a ray passing through its closest hit meets next.
bool bvh_hit_once(Prim p) {
    // One mask test: glslang 11 folds a chain of four short-circuit ||s of
    // specialization constants into a phi, then negates that phi as a specialization
    // constant (invalid SPIR-V: vkCreateComputePipelines fails).
    bool quadrics = BVH_HAS(SURFACE_FEATURE_SPHERES | SURFACE_FEATURE_CYLINDERS
                            | SURFACE_FEATURE_SDFGRIDS | SURFACE_FEATURE_LINEAR_CURVES
                            | SURFACE_FEATURE_BSPLINE_CURVES);
    return !quadrics || p.kind == PRIM_TRIANGLE || p.kind == PRIM_DISK;
}

// A ray passed its closest hit, primitive `crossed`, and goes on from an origin
// `advance` further along it, with `remaining` left of its range: `second` (from
// bvh_closest_two) is measured from there (a miss ends at `remaining`), and is the
// ray's closest hit from there, with no trace, where it lies beyond that origin and
// `crossed` is flat (not so for a surface coincident with the one passed, or a quadric
// the ray may meet again: those trace).
bool bvh_second_goes_on(Prim crossed, float advance, float remaining, inout Hit second) {
    second.t = second.prim == HIT_NONE ? remaining : second.t - advance;
    return second.t > 0.0 && bvh_hit_once(crossed);
}

#endif
