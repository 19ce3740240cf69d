//! The BVH: a binned-SAH build on the host ([`super::bvh_build`]), flattened to
//! [`BvhNode`]s, and a CPU traversal that mirrors `shaders/accel/bvh.glsl` step for
//! step.
//!
//! Layout: node 0 is the root and always an inner node; each node holds both
//! children's boxes (Aila, Laine 2009). A child with `count > 0` is a leaf over
//! `prims[index .. index + count]`; with `count == 0`, the inner node `nodes[index]`;
//! an absent child has the empty box (min = +inf, max = -inf), which no ray hits.
//!
//! Traversal: a stack of child references, nearer hit child first. The ray/box test is
//! the slab test with a precomputed inverse direction made robust as in Ize 2013,
//! "Robust BVH Ray Traversal" (JCGT 2(2)): near/far planes are picked by the sign of
//! the direction, `0 * inf = NaN` from a zero direction component is discarded by
//! comparisons that are false on NaN, and the far distance is scaled by `1 + 2 gamma(3)`
//! so that rounding never culls a box the ray really enters.

use std::time::Instant;

use glam::Vec3;

use super::bvh_build::{PrimSource, ShapePrims};
use super::{cylinder, disk, sphere, triangle};
use crate::gpu::layout::{
    BvhNode, Prim, PRIM_BSPLINE_CURVE, PRIM_CYLINDER, PRIM_DISK, PRIM_ELLIPSOID, PRIM_INSTANCE,
    PRIM_LINEAR_CURVE, PRIM_SDFGRID, PRIM_SPHERE, PRIM_TRIANGLE,
};
use crate::scene::{Mesh, Quadric};

/// Entries in the traversal stack of `shaders/accel/bvh.glsl` (`#define
/// BVH_STACK_SIZE`, checked by a test). The build keeps every leaf at depth
/// `<= BVH_STACK_SIZE` (root = depth 0), which is what a traversal that pushes one
/// child per level needs.
pub const BVH_STACK_SIZE: usize = 32;

/// Most primitives in one leaf. Child references on the traversal stack pack the count
/// in [`BVH_COUNT_BITS`] bits, so this must stay below `1 << BVH_COUNT_BITS`.
pub const BVH_MAX_LEAF_SIZE: usize = 8;

/// Low bits of a packed child reference `(index << BVH_COUNT_BITS) | count` holding the
/// leaf count (`#define BVH_COUNT_BITS` in bvh.glsl).
pub const BVH_COUNT_BITS: u32 = 4;

const _: () = assert!(BVH_MAX_LEAF_SIZE < 1 << BVH_COUNT_BITS);

/// Primitives a flat traversal tests each for its own kind (`#define BVH_FLAT_CAPACITY`
/// in bvh.glsl). Their kinds take two bits each of one word; any further primitives
/// of a flat traversal are triangles.
pub const FLAT_CAPACITY: usize = 16;

/// Most primitives of a scene that the kernels trace without its BVH, testing each in
/// turn ([`FlatPrims`], bvh.glsl's `bvh_trace_flat`): up to here that costs llvmpipe
/// fewer instructions than the tree, beyond it more (docs/performance.md, "Small
/// scenes without a tree").
pub const FLAT_PRIMS_MAX: usize = 8;

/// [`FLAT_PRIMS_MAX`] on devices that load what every lane reads from one address
/// once for all of them, and run 16 lanes or more (lavapipe from Mesa 26 reading the
/// scene from storage buffers, at 512 bits: `render::plan`): a flat test is then
/// arithmetic alone, where the tree gathers every node and primitive lane by lane and
/// its lanes diverge; the Cornell box (32 triangles) renders 19% faster flat, a scene
/// of 44 as fast either way (docs/performance.md, "Small scenes without a tree").
pub const FLAT_PRIMS_MAX_WIDE: usize = 40;

/// Most primitives a flat traversal may hold: bvh.glsl's `bvh_trace_flat` writes out a
/// step for each (checked by a test), each taking a triangle's vertices from the
/// kernel's constants where [`FlatPrims::vertices`].
pub const FLAT_STEPS: usize = FLAT_PRIMS_MAX_WIDE;

const _: () = assert!(FLAT_PRIMS_MAX <= FLAT_CAPACITY);
const _: () = assert!(FLAT_CAPACITY <= FLAT_STEPS);

/// Most quadrics (spheres, disks, cylinders) of a scene with triangles that the build
/// keeps out of the tree ([`Bvh::apart`]): the traversals test them in turn, each for
/// its own kind, and the tree then holds triangles alone: on llvmpipe a leaf's test runs
/// the code of every kind the tree holds for every lane, so one sphere among triangles
/// made every triangle test pay for a sphere test too (docs/performance.md, "Quadrics
/// apart from the tree").
pub const APART_QUADRICS_MAX: usize = 8;

const _: () = assert!(APART_QUADRICS_MAX <= FLAT_CAPACITY);

/// Bit of the first specialization constant of [`FlatPrims::constants`] (`#define
/// BVH_FLAT_ONLY` in bvh.glsl): no tree follows the primitives tested in turn.
pub const FLAT_ONLY: u32 = 1 << 16;

/// Bit of the same constant (`#define BVH_FLAT_VERTEX_CONSTANTS` in bvh.glsl): the
/// vertices of the triangles tested in turn are constants of the kernel
/// (`gpu::spec_ids::flat_vertex`, [`FlatPrims::vertex_words`]), not loads.
pub const FLAT_VERTEX_CONSTANTS: u32 = 1 << 17;

/// A scene's primitives as the traversal kernels see them: how many lead
/// [`Bvh::prims`] to be tested in turn, the `PRIM_*` kind of primitive k at bits
/// `2k..2k+2` of `kinds` (the first [`FLAT_CAPACITY`]; any after them are
/// triangles), and whether the tree follows (it holds the rest). Two
/// specialization constants of the kernels that trace rays. The default is the tree
/// alone, right for a [`Bvh`] with nothing apart.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FlatPrims {
    pub count: u32,
    pub kinds: u32,
    /// Only the primitives tested in turn: every one of the scene's.
    pub flat_only: bool,
    /// The vertices of its triangles are constants of the kernels
    /// ([`FLAT_VERTEX_CONSTANTS`]).
    pub vertices: bool,
}

impl FlatPrims {
    /// How the kernels trace `bvh`: every primitive in turn where there are at most
    /// `max` (itself at most [`FLAT_STEPS`]) and those after the first
    /// [`FLAT_CAPACITY`] are triangles, else the primitives apart ([`Bvh::apart`]) in
    /// turn, then the tree.
    pub fn of(bvh: &Bvh, max: usize) -> FlatPrims {
        let max = max.min(FLAT_STEPS);
        // (Sdfgrids and curves take more than the two bits of a kind: they stay in the
        // tree.)
        let all = !bvh.prims.is_empty()
            && bvh.prims.len() <= max
            && bvh.prims.iter().all(|p| {
                !matches!(
                    p.kind,
                    PRIM_SDFGRID | PRIM_LINEAR_CURVE | PRIM_BSPLINE_CURVE | PRIM_ELLIPSOID
                )
            })
            && bvh.prims[FLAT_CAPACITY.min(bvh.prims.len())..]
                .iter()
                .all(|p| p.kind == PRIM_TRIANGLE);
        let count = if all {
            bvh.prims.len()
        } else {
            bvh.apart as usize
        };
        FlatPrims {
            count: count as u32,
            kinds: bvh.prims[..count.min(FLAT_CAPACITY)]
                .iter()
                .enumerate()
                .fold(0, |m, (k, p)| m | (p.kind & 3) << (2 * k)),
            flat_only: all,
            vertices: false,
        }
    }

    /// [`FlatPrims::of`], the vertices of the primitives tested in turn given to the
    /// kernels as constants ([`FlatPrims::vertex_words`]) where they are the whole
    /// scene (the quadrics apart from a tree are loaded: bvh.glsl takes constants for
    /// triangles alone).
    pub fn with_vertex_constants(bvh: &Bvh, max: usize) -> FlatPrims {
        let flat = FlatPrims::of(bvh, max);
        FlatPrims {
            vertices: flat.flat_only,
            ..flat
        }
    }

    /// The vertex words of the primitives tested in turn, as f32 bits: p0, p1, p2 (x,
    /// y, z each) of primitive k at `9 k`; empty unless [`FlatPrims::vertices`].
    pub fn vertex_words(&self, bvh: &Bvh) -> Vec<u32> {
        if !self.vertices {
            return Vec::new();
        }
        let n = (self.count as usize).min(FLAT_STEPS).min(bvh.prims.len());
        bvh.prims[..n]
            .iter()
            .flat_map(|p| [p.p0, p.p1, p.p2])
            .flatten()
            .map(f32::to_bits)
            .collect()
    }

    /// As specialization constants: count (with [`FLAT_ONLY`]), kinds.
    pub fn constants(&self) -> [u32; 2] {
        [
            self.count
                | if self.flat_only { FLAT_ONLY } else { 0 }
                | if self.vertices {
                    FLAT_VERTEX_CONSTANTS
                } else {
                    0
                },
            self.kinds,
        ]
    }
}

/// Most primitives a BVH may hold: packed child references keep indices in
/// `32 - BVH_COUNT_BITS` bits.
pub const BVH_MAX_PRIMS: usize = (1 << (32 - BVH_COUNT_BITS)) - 1;

/// Bins per axis of the SAH build (Wald 2007 finds 16 to 32 as good as a full sweep).
pub const SAH_BINS: usize = 16;

/// SAH cost of visiting one inner node (fetching it and testing both child boxes).
pub const SAH_TRAVERSAL_COST: f64 = 1.0;

/// SAH cost of one ray/primitive test, relative to [`SAH_TRAVERSAL_COST`].
pub const SAH_INTERSECTION_COST: f64 = 1.0;

/// Leaf size of [`SplitMethod::Median`] builds.
pub(super) const MEDIAN_LEAF_SIZE: usize = 4;

/// `1 + 2 gamma(3)`, `gamma(n) = n eps / (1 - n eps)`, `eps = 2^-24` (Ize 2013, sec. 3;
/// pbrt-v4 `Bounds3::IntersectP`), which is `1 + 3.58e-7`, rounded up to the next
/// float `1 + 4 * 2^-23`: scales a box's far distance so that the three roundings in
/// `(b - o) * inv_d` never make it smaller than the near one when the exact interval is
/// non-empty. `#define BVH_TFAR_SCALE` in bvh.glsl.
pub const BOX_TFAR_SCALE: f32 = 1.0 + 4.0 * f32::EPSILON;

/// How [`Bvh::build_with`] chooses splits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SplitMethod {
    /// Binned SAH (the default, [`Bvh::build`]).
    Sah,
    /// Object median along the longest centroid axis, leaves of up to 4: a baseline.
    Median,
}

/// Numbers describing a built tree.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BvhStats {
    /// Wall time of the build, seconds (bounds, binning, partitioning, reordering).
    pub build_seconds: f64,
    /// Inner nodes, `nodes.len()`.
    pub node_count: usize,
    /// Non-empty leaves.
    pub leaf_count: usize,
    /// Deepest leaf; the root node is depth 0, its children depth 1.
    pub max_depth: usize,
    /// Most primitives in one leaf.
    pub max_leaf_size: usize,
    /// Surface area heuristic cost of the tree: the sum over inner nodes of
    /// [`SAH_TRAVERSAL_COST`] `A(node)/A(root)` plus over leaves of
    /// [`SAH_INTERSECTION_COST`] `count A(leaf)/A(root)` (MacDonald, Booth 1990).
    pub sah_cost: f64,
}

impl BvhStats {
    /// Entries a traversal stack of this tree needs: one per level above the deepest
    /// leaf (a node at depth d has at most d deferred siblings), at least 1 and at
    /// most [`BVH_STACK_SIZE`]. The GLSL traversal is specialized to it (bvh.glsl's
    /// `BVH_STACK_DEPTH`), since its stack shifts through every entry.
    pub fn stack_depth(&self) -> u32 {
        self.max_depth.clamp(1, BVH_STACK_SIZE) as u32
    }
}

/// A ray hit from [`Bvh::closest`]: distance, barycentrics (`p = (1-u-v) p0 + u p1 +
/// v p2` for a triangle; 0 for a sphere) and the primitive, an index into
/// [`Bvh::prims`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub u: f32,
    pub v: f32,
    pub prim: u32,
}

/// A BVH ready for upload: `nodes` and `prims` go to set 0 bindings 0 and 1.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    pub nodes: Vec<BvhNode>,
    /// The primitives: the `apart` ones, then those of the tree in leaf order.
    pub prims: Vec<Prim>,
    /// How many primitives lead `prims` outside the tree: a scene's few quadrics
    /// ([`APART_QUADRICS_MAX`]), tested in turn before the tree, which then holds
    /// triangles alone; 0 when the tree holds every primitive.
    pub apart: u32,
    pub stats: BvhStats,
    /// A scene with instances: the top-level tree at node 0, the groups' trees and
    /// the instances' transforms after it ([`super::instance`]).
    pub two_level: Option<super::instance::TwoLevel>,
}

/// An axis-aligned box; `EMPTY` has min = +inf, max = -inf.
#[derive(Clone, Copy, Debug)]
pub(super) struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    #[cfg(test)]
    const EMPTY: Aabb = Aabb {
        min: Vec3::INFINITY,
        max: Vec3::NEG_INFINITY,
    };

    #[inline]
    fn grow(&mut self, b: &Aabb) {
        self.min = self.min.min(b.min);
        self.max = self.max.max(b.max);
    }

    /// Surface area in f64: finite for any finite f32 box; 0 for the empty box.
    fn area(&self) -> f64 {
        let e = self.max - self.min;
        if e.x < 0.0 || e.y < 0.0 || e.z < 0.0 {
            return 0.0;
        }
        let (x, y, z) = (e.x as f64, e.y as f64, e.z as f64);
        2.0 * (x * y + y * z + z * x)
    }
}

/// The boxes of a node's two children (the empty box for an absent one).
fn child_boxes(n: &BvhNode) -> (Aabb, Aabb) {
    let l = Aabb {
        min: n.left_min.into(),
        max: n.left_max.into(),
    };
    let r = Aabb {
        min: n.right_min.into(),
        max: n.right_max.into(),
    };
    (l, r)
}

/// The bounds of one primitive (layouts in [`Prim`]).
pub(super) fn prim_bounds(p: &Prim) -> Aabb {
    let (p0, p1, p2) = (Vec3::from(p.p0), Vec3::from(p.p1), Vec3::from(p.p2));
    // Half-extents of the ellipse c + cos φ a1 + sin φ a2 per axis: sqrt(a1² + a2²).
    let ellipse = |a1: Vec3, a2: Vec3| (a1 * a1 + a2 * a2).map(f32::sqrt);
    match p.kind {
        PRIM_SPHERE => {
            let r = Vec3::splat(p1.length());
            Aabb {
                min: p0 - r,
                max: p0 + r,
            }
        }
        PRIM_DISK => {
            let e = ellipse(p1, p2);
            Aabb {
                min: p0 - e,
                max: p0 + e,
            }
        }
        PRIM_INSTANCE | PRIM_SDFGRID | PRIM_BSPLINE_CURVE | PRIM_ELLIPSOID => {
            Aabb { min: p0, max: p1 }
        }
        // The two end spheres' boxes hold the cone between them.
        PRIM_LINEAR_CURVE => Aabb {
            min: (p0 - Vec3::splat(p2.x)).min(p1 - Vec3::splat(p2.y)),
            max: (p0 + Vec3::splat(p2.x)).max(p1 + Vec3::splat(p2.y)),
        },
        PRIM_CYLINDER => {
            // The end circles: radius |a1| in the plane normal to the axis p2.
            let a2 = p2.normalize_or_zero().cross(p1);
            let e = ellipse(p1, a2);
            let top = p0 + p2;
            Aabb {
                min: (p0 - e).min(top - e),
                max: (p0 + e).max(top + e),
            }
        }
        _ => Aabb {
            min: p0.min(p1).min(p2),
            max: p0.max(p1).max(p2),
        },
    }
}

impl Bvh {
    /// Builds a binned-SAH BVH over `prims`, reordering them into leaf order.
    ///
    /// Every leaf ends at depth `<= BVH_STACK_SIZE` and holds at most
    /// [`BVH_MAX_LEAF_SIZE`] primitives; at most [`BVH_MAX_PRIMS`] primitives are
    /// supported (the packed stack entries). Inputs must be NaN-free; degenerate and
    /// coincident primitives are fine.
    pub fn build(prims: Vec<Prim>) -> Bvh {
        Bvh::build_with(prims, SplitMethod::Sah)
    }

    /// [`Bvh::build`] with a choice of split method.
    pub fn build_with(prims: Vec<Prim>, method: SplitMethod) -> Bvh {
        Bvh::build_from(&prims[..], method)
    }

    /// The BVH of a scene's shapes, made without first copying them all into
    /// [`Prim`]s: for scenes of tens of millions of triangles (see
    /// [`super::bvh_build`] for time and memory).
    pub fn for_shapes(meshes: &[Mesh], quadrics: &[Quadric]) -> Bvh {
        Bvh::build_from(&ShapePrims::new(meshes, quadrics), SplitMethod::Sah)
    }

    /// Builds over the primitives `source` gives, in parallel.
    pub fn build_from<S: PrimSource + ?Sized>(source: &S, method: SplitMethod) -> Bvh {
        Bvh::build_tree(source, method, true)
    }

    /// [`Bvh::build_from`] with every primitive in the tree (none apart).
    pub fn build_whole<S: PrimSource + ?Sized>(source: &S) -> Bvh {
        Bvh::build_tree(source, SplitMethod::Sah, false)
    }

    fn build_tree<S: PrimSource + ?Sized>(source: &S, method: SplitMethod, apart: bool) -> Bvh {
        let start = Instant::now();
        let n = source.len();
        assert!(
            n <= BVH_MAX_PRIMS,
            "BVH over {n} primitives: at most {BVH_MAX_PRIMS} supported"
        );
        let (nodes, prims, apart) = super::bvh_build::build(source, method, apart);
        let mut bvh = Bvh {
            nodes,
            prims,
            apart: apart as u32,
            stats: BvhStats::default(),
            two_level: None,
        };
        bvh.stats = bvh.compute_stats();
        bvh.stats.build_seconds = start.elapsed().as_secs_f64();
        bvh
    }

    /// Walks the tree for [`BvhStats`] (all but `build_seconds`).
    fn compute_stats(&self) -> BvhStats {
        let mut s = BvhStats {
            node_count: self.nodes.len(),
            ..BvhStats::default()
        };
        let (l, r) = child_boxes(&self.nodes[0]);
        let mut root = l;
        root.grow(&r);
        let root_area = root.area();
        let rel = |a: f64| if root_area > 0.0 { a / root_area } else { 1.0 };
        let mut todo = vec![(0u32, 0usize, root)];
        while let Some((index, depth, bounds)) = todo.pop() {
            s.sah_cost += SAH_TRAVERSAL_COST * rel(bounds.area());
            let n = &self.nodes[index as usize];
            let (l, r) = child_boxes(n);
            for (b, index, count) in [
                (l, n.left_index, n.left_count),
                (r, n.right_index, n.right_count),
            ] {
                if b.min.x > b.max.x {
                    continue; // absent child
                }
                if count == 0 {
                    todo.push((index, depth + 1, b));
                } else {
                    s.leaf_count += 1;
                    s.max_depth = s.max_depth.max(depth + 1);
                    s.max_leaf_size = s.max_leaf_size.max(count as usize);
                    s.sah_cost += SAH_INTERSECTION_COST * count as f64 * rel(b.area());
                }
            }
        }
        s
    }

    /// The primitive records that are primitives (with a `kind`): all but a two-level
    /// tree's records from `slots` on, which hold the instances (`accel::instance`).
    pub fn shape_prims(&self) -> &[Prim] {
        let n = self
            .two_level
            .map_or(self.prims.len(), |t| t.slots as usize);
        &self.prims[..n]
    }

    /// The box around every primitive (the root's and those apart), `None` for an
    /// empty scene.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut b = Aabb {
            min: Vec3::INFINITY,
            max: Vec3::NEG_INFINITY,
        };
        if let Some(n) = self.nodes.first() {
            let (l, r) = child_boxes(n);
            b.grow(&l);
            b.grow(&r);
        }
        for p in &self.prims[..self.apart as usize] {
            b.grow(&prim_bounds(p));
        }
        b.min.cmple(b.max).all().then_some((b.min, b.max))
    }

    /// The closest hit of `o + t d` with `tmin < t < tmax` (`0 <= tmin`, `d != 0`),
    /// as `bvh_closest` in bvh.glsl. Of hits at equal `t`, the first in traversal order.
    pub fn closest(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> Option<Hit> {
        self.trace(o, d, tmin, tmax, false)
    }

    /// Whether anything is hit with `tmin < t < tmax`, stopping at the first hit
    /// found, as `bvh_any` in bvh.glsl.
    pub fn any(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> bool {
        self.trace(o, d, tmin, tmax, true).is_some()
    }

    /// The traversal loop shared by `closest` and `any`; `bvh_trace` in bvh.glsl.
    fn trace(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, any_hit: bool) -> Option<Hit> {
        let br = BoxRay::new(o, d);
        let tr = triangle::TriangleRay::new(d);
        let mut hit: Option<Hit> = None;
        let mut t_hit = tmax;
        // The primitives apart first, in turn.
        for i in 0..self.apart {
            if let Some((t, u, v)) = intersect_prim(&self.prims[i as usize], &tr, o, d, tmin, t_hit)
            {
                t_hit = t;
                hit = Some(Hit { t, u, v, prim: i });
                if any_hit {
                    return hit;
                }
            }
        }
        let mut stack = [0u32; BVH_STACK_SIZE];
        let mut sp = 0usize;
        // The current child reference, packed as (index << BVH_COUNT_BITS) | count.
        let mut item = 0u32; // inner node 0
        loop {
            let index = item >> BVH_COUNT_BITS;
            let count = item & ((1 << BVH_COUNT_BITS) - 1);
            if count == 0 {
                let n = &self.nodes[index as usize];
                let (hit_l, tl) = br.slab(n.left_min, n.left_max, tmin, t_hit);
                let (hit_r, tr_) = br.slab(n.right_min, n.right_max, tmin, t_hit);
                let l = (n.left_index << BVH_COUNT_BITS) | n.left_count;
                let r = (n.right_index << BVH_COUNT_BITS) | n.right_count;
                if hit_l && hit_r {
                    // Both: go to the nearer, push the other.
                    let (near, far) = if tl <= tr_ { (l, r) } else { (r, l) };
                    stack[sp] = far;
                    sp += 1;
                    item = near;
                    continue;
                }
                if hit_l || hit_r {
                    item = if hit_l { l } else { r };
                    continue;
                }
            } else {
                // A leaf from `slots` on names instance records (accel::instance).
                let slots = self.two_level.map_or(u32::MAX, |t| t.slots);
                for i in index..index + count {
                    let found = if i >= slots {
                        // An instance's box stands for it (intersect_prim).
                        let (lo, hi) = super::instance::instance_world_box(self, i - slots);
                        let (hit, tn) = br.slab(lo.to_array(), hi.to_array(), tmin, t_hit);
                        hit.then_some((tn, 0.0, 0.0))
                    } else {
                        intersect_prim(&self.prims[i as usize], &tr, o, d, tmin, t_hit)
                    };
                    if let Some((t, u, v)) = found {
                        t_hit = t;
                        hit = Some(Hit { t, u, v, prim: i });
                        if any_hit {
                            return hit;
                        }
                    }
                }
            }
            if sp == 0 {
                return hit;
            }
            sp -= 1;
            item = stack[sp];
        }
    }
}

/// The per-ray part of the slab test (Ize 2013).
struct BoxRay {
    o: Vec3,
    /// `1 / d`, or +-inf for a zero (or denormal) component.
    inv: Vec3,
    /// Direction sign per axis: the near plane is `max` where set, `min` otherwise.
    neg: [bool; 3],
}

impl BoxRay {
    fn new(o: Vec3, d: Vec3) -> BoxRay {
        // Vulkan only bounds the error of x / y for |y| in [2^-126, 2^126]; below
        // that the GLSL uses an explicit infinity, and so does this.
        let inv = Vec3::from_array(d.to_array().map(|c| {
            if c.abs() >= f32::MIN_POSITIVE {
                1.0 / c
            } else if c < 0.0 {
                f32::NEG_INFINITY
            } else {
                f32::INFINITY
            }
        }));
        BoxRay {
            o,
            inv,
            neg: [inv.x < 0.0, inv.y < 0.0, inv.z < 0.0],
        }
    }

    /// Whether the box is entered within `[tmin, tmax]`, and the entry distance.
    #[inline]
    fn slab(&self, bmin: [f32; 3], bmax: [f32; 3], tmin: f32, tmax: f32) -> (bool, f32) {
        let mut tn = tmin;
        let mut tf = tmax;
        for a in 0..3 {
            let (near, far) = if self.neg[a] {
                (bmax[a], bmin[a])
            } else {
                (bmin[a], bmax[a])
            };
            let t0 = (near - self.o[a]) * self.inv[a];
            let t1 = (far - self.o[a]) * self.inv[a];
            // Written as compare-and-select, not min/max: a NaN (0 * inf, the origin
            // on a slab plane of a zero direction component) fails the comparison and
            // leaves the interval unchanged. GLSL min/max are undefined on NaN.
            tn = if t0 > tn { t0 } else { tn };
            tf = if t1 < tf { t1 } else { tf };
        }
        (tn <= tf * BOX_TFAR_SCALE, tn)
    }
}

/// Where `o + t d` first meets primitive `p` with `tmin < t < tmax`: `(t, u, v)`, with
/// `u, v` a triangle's barycentrics or a disk's object-space (x, y), else 0. The
/// primitive test of `bvh_trace` in bvh.glsl.
#[inline]
pub fn intersect_prim(
    p: &Prim,
    tr: &triangle::TriangleRay,
    o: Vec3,
    d: Vec3,
    tmin: f32,
    tmax: f32,
) -> Option<(f32, f32, f32)> {
    let (p0, p1, p2) = (Vec3::from(p.p0), Vec3::from(p.p1), Vec3::from(p.p2));
    match p.kind {
        PRIM_SPHERE => sphere::intersect(o, d, p0, p1.length(), tmin, tmax).map(|t| (t, 0.0, 0.0)),
        PRIM_DISK => disk::intersect(o, d, p0, p1, p2, tmin, tmax),
        PRIM_CYLINDER => {
            cylinder::intersect(o, d, p0, p2, p1.length(), tmin, tmax).map(|t| (t, 0.0, 0.0))
        }
        PRIM_LINEAR_CURVE => {
            super::curve::intersect_linear(o, d, p0, p1, p2.x, p2.y, p2.z < 0.0, tmin, tmax)
                .map(|(t, v)| (t, v, 0.0))
        }
        // An instance's box stands for it (the CPU traversal serves estimates such
        // as the render plan's camera misses; the kernels trace the group's tree).
        // So does an sdfgrid's (its voxels are walked on the GPU alone) and a B-spline
        // segment's (its control points are in the grid buffer: accel::bspline
        // intersects them given those), and an ellipsoid's (its map is there too:
        // scene::shape::ellipsoids::Ellipsoid::intersect).
        PRIM_INSTANCE | PRIM_SDFGRID | PRIM_BSPLINE_CURVE | PRIM_ELLIPSOID => {
            let (hit, tn) = BoxRay::new(o, d).slab(p.p0, p.p1, tmin, tmax);
            hit.then_some((tn, 0.0, 0.0))
        }
        _ => triangle::intersect(tr, o, p0, p1, p2, tmin, tmax).map(|h| (h.t, h.u, h.v)),
    }
}

/// The closest hit by testing every primitive in order, for tests. Same intersection
/// routines as the traversal; of hits at equal `t`, the lowest index.
pub fn brute_force_closest(prims: &[Prim], o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> Option<Hit> {
    let tr = triangle::TriangleRay::new(d);
    let mut hit = None;
    let mut t_hit = tmax;
    for (i, p) in prims.iter().enumerate() {
        let found = intersect_prim(p, &tr, o, d, tmin, t_hit);
        if let Some((t, u, v)) = found {
            t_hit = t;
            hit = Some(Hit {
                t,
                u,
                v,
                prim: i as u32,
            });
        }
    }
    hit
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::layout::PRIM_TRIANGLE;
    use std::collections::HashMap;

    /// splitmix64: a small deterministic generator for test inputs.
    struct Rng(u64);

    impl Rng {
        fn next_u64(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^ (z >> 31)
        }
        /// Uniform in [0, 1).
        fn f(&mut self) -> f32 {
            (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
        }
        fn range(&mut self, lo: f32, hi: f32) -> f32 {
            lo + (hi - lo) * self.f()
        }
        fn vec_in(&mut self, lo: Vec3, hi: Vec3) -> Vec3 {
            Vec3::new(
                self.range(lo.x, hi.x),
                self.range(lo.y, hi.y),
                self.range(lo.z, hi.z),
            )
        }
        fn dir(&mut self) -> Vec3 {
            loop {
                let v = self.vec_in(Vec3::splat(-1.0), Vec3::ONE);
                let l = v.length_squared();
                if l > 1e-4 && l <= 1.0 {
                    return v / l.sqrt();
                }
            }
        }
        fn below(&mut self, n: usize) -> usize {
            (self.next_u64() % n as u64) as usize
        }
    }

    fn tri(p0: Vec3, p1: Vec3, p2: Vec3) -> Prim {
        Prim {
            p0: p0.into(),
            shape: 0,
            p1: p1.into(),
            index: 0,
            p2: p2.into(),
            kind: PRIM_TRIANGLE,
        }
    }

    fn sphere(c: Vec3, r: f32) -> Prim {
        Prim {
            p0: c.into(),
            shape: 1,
            p1: [r, 0.0, 0.0],
            index: 0,
            p2: [0.0; 3],
            kind: PRIM_SPHERE,
        }
    }

    /// Triangles of an indexed mesh; shared vertices stay bit-identical.
    fn mesh_prims(positions: &[Vec3], indices: &[[u32; 3]]) -> Vec<Prim> {
        let mut prims: Vec<Prim> = indices
            .iter()
            .map(|ix| {
                let [a, b, c] = ix.map(|i| positions[i as usize]);
                tri(a, b, c)
            })
            .collect();
        for (i, p) in prims.iter_mut().enumerate() {
            p.index = i as u32;
        }
        prims
    }

    fn load_bunny() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../shared/scenes/nori/bunny/bunny.obj"
        );
        let opts = tobj::LoadOptions {
            triangulate: true,
            single_index: true,
            ..Default::default()
        };
        let (models, _) = tobj::load_obj(path, &opts).expect("bunny.obj");
        let mut positions = Vec::new();
        let mut indices = Vec::new();
        for m in &models {
            let base = positions.len() as u32;
            positions.extend(
                m.mesh
                    .positions
                    .chunks(3)
                    .map(|p| Vec3::new(p[0], p[1], p[2])),
            );
            indices.extend(
                m.mesh
                    .indices
                    .chunks(3)
                    .map(|t| [base + t[0], base + t[1], base + t[2]]),
            );
        }
        (positions, indices)
    }

    /// Icosphere of radius 1 around the origin, `levels` midpoint subdivisions of an
    /// icosahedron, vertices shared between faces.
    fn icosphere(levels: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let g = (1.0 + 5f32.sqrt()) / 2.0;
        let mut pos: Vec<Vec3> = [
            (-1.0, g, 0.0),
            (1.0, g, 0.0),
            (-1.0, -g, 0.0),
            (1.0, -g, 0.0),
            (0.0, -1.0, g),
            (0.0, 1.0, g),
            (0.0, -1.0, -g),
            (0.0, 1.0, -g),
            (g, 0.0, -1.0),
            (g, 0.0, 1.0),
            (-g, 0.0, -1.0),
            (-g, 0.0, 1.0),
        ]
        .iter()
        .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
        .collect();
        let mut idx: Vec<[u32; 3]> = vec![
            [0, 11, 5],
            [0, 5, 1],
            [0, 1, 7],
            [0, 7, 10],
            [0, 10, 11],
            [1, 5, 9],
            [5, 11, 4],
            [11, 10, 2],
            [10, 7, 6],
            [7, 1, 8],
            [3, 9, 4],
            [3, 4, 2],
            [3, 2, 6],
            [3, 6, 8],
            [3, 8, 9],
            [4, 9, 5],
            [2, 4, 11],
            [6, 2, 10],
            [8, 6, 7],
            [9, 8, 1],
        ];
        for _ in 0..levels {
            let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
            let mut next = Vec::with_capacity(idx.len() * 4);
            for [a, b, c] in idx {
                let mut m = |i: u32, j: u32| {
                    *mid.entry((i.min(j), i.max(j))).or_insert_with(|| {
                        pos.push((pos[i as usize] + pos[j as usize]).normalize());
                        pos.len() as u32 - 1
                    })
                };
                let (ab, bc, ca) = (m(a, b), m(b, c), m(c, a));
                next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
            }
            idx = next;
        }
        (pos, idx)
    }

    /// The cube [-1, 1]^3, two triangles per face.
    fn cube() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let pos = (0..8)
            .map(|i| {
                Vec3::new(
                    if i & 1 != 0 { 1.0 } else { -1.0 },
                    if i & 2 != 0 { 1.0 } else { -1.0 },
                    if i & 4 != 0 { 1.0 } else { -1.0 },
                )
            })
            .collect();
        let quads = [
            [0, 2, 6, 4],
            [1, 5, 7, 3],
            [0, 4, 5, 1],
            [2, 3, 7, 6],
            [0, 1, 3, 2],
            [4, 6, 7, 5],
        ];
        let idx = quads
            .iter()
            .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
            .collect();
        (pos, idx)
    }

    /// An `n` x `n` quad grid over [0, 1]^2 at z = 0, two triangles per quad.
    fn grid(n: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let mut pos = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                pos.push(Vec3::new(i as f32 / n as f32, j as f32 / n as f32, 0.0));
            }
        }
        let mut idx = Vec::new();
        let v = |i: u32, j: u32| j * (n + 1) + i;
        for j in 0..n {
            for i in 0..n {
                // Alternate the diagonal so both orientations of shared edges occur.
                if (i + j) % 2 == 0 {
                    idx.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
                    idx.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
                } else {
                    idx.push([v(i, j), v(i + 1, j), v(i, j + 1)]);
                    idx.push([v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)]);
                }
            }
        }
        (pos, idx)
    }

    fn contains(outer: &Aabb, inner: &Aabb) -> bool {
        outer.min.cmple(inner.min).all() && outer.max.cmpge(inner.max).all()
    }

    /// Checks the tree's structure: node 0 inner, every child box encloses what it
    /// holds, each primitive in exactly one leaf, depth and leaf-size bounds, stats.
    fn validate(bvh: &Bvh) {
        assert!(!bvh.nodes.is_empty(), "node 0 must exist");
        let mut seen = vec![0u32; bvh.prims.len()];
        let mut visited = vec![false; bvh.nodes.len()];
        let mut todo = vec![(0u32, 0usize)];
        let (mut leaves, mut max_depth, mut max_leaf) = (0, 0, 0);
        while let Some((ni, depth)) = todo.pop() {
            assert!(!visited[ni as usize], "node {ni} reached twice");
            visited[ni as usize] = true;
            let n = bvh.nodes[ni as usize];
            for (min, max, index, count) in [
                (n.left_min, n.left_max, n.left_index, n.left_count),
                (n.right_min, n.right_max, n.right_index, n.right_count),
            ] {
                let b = Aabb {
                    min: min.into(),
                    max: max.into(),
                };
                if b.min.x > b.max.x {
                    assert_eq!(b.min, Vec3::INFINITY, "empty child box");
                    assert_eq!(b.max, Vec3::NEG_INFINITY, "empty child box");
                    assert_eq!(count, 0);
                    continue;
                }
                if count > 0 {
                    leaves += 1;
                    max_depth = max_depth.max(depth + 1);
                    max_leaf = max_leaf.max(count as usize);
                    assert!(count as usize <= BVH_MAX_LEAF_SIZE);
                    for i in index..index + count {
                        seen[i as usize] += 1;
                        assert!(contains(&b, &prim_bounds(&bvh.prims[i as usize])));
                    }
                } else {
                    let c = bvh.nodes[index as usize];
                    for (cmin, cmax) in [(c.left_min, c.left_max), (c.right_min, c.right_max)] {
                        let cb = Aabb {
                            min: cmin.into(),
                            max: cmax.into(),
                        };
                        assert!(cb.min.x > cb.max.x || contains(&b, &cb));
                    }
                    todo.push((index, depth + 1));
                }
            }
        }
        assert!(visited.iter().all(|&v| v), "unreachable nodes");
        // The primitives apart: the few quadrics, in no leaf.
        let apart = bvh.apart as usize;
        assert!(apart <= APART_QUADRICS_MAX);
        for (p, s) in bvh.prims[..apart].iter().zip(&mut seen[..apart]) {
            assert_ne!(p.kind, PRIM_TRIANGLE, "a triangle apart");
            *s += 1;
        }
        assert!(
            apart == 0 || bvh.prims[apart..].iter().all(|p| p.kind == PRIM_TRIANGLE),
            "a quadric in the tree beside the ones apart"
        );
        assert!(
            seen.iter().all(|&s| s == 1),
            "each primitive in exactly one leaf"
        );
        assert!(max_depth <= BVH_STACK_SIZE, "depth {max_depth}");
        let s = bvh.stats;
        assert_eq!(s.node_count, bvh.nodes.len());
        assert_eq!(s.leaf_count, leaves);
        assert_eq!(s.max_depth, max_depth);
        assert_eq!(s.max_leaf_size, max_leaf);
        assert!(s.sah_cost.is_finite() && s.sah_cost >= 0.0);
    }

    /// Whether a brute-force hit is a rounding artifact of the intersection test: its
    /// point `o + t d` lies outside the primitive's own bounding box, i.e. the
    /// conservative slab test says the ray has not entered that box by `t`. This
    /// happens when the test's error exceeds the distance along the ray: numerically
    /// degenerate triangles (zero area, collinear, slivers seen edge-on), whose edge
    /// functions are rounding noise, and coplanar overlapping triangles with vertices
    /// far from the hit, whose `t` errs by more than the box test's `1 + 2 gamma(3)`.
    ///
    /// Any other hit a BVH must reproduce exactly: every ancestor box contains the
    /// primitive's box, so the traversal enters each of them before `t` (the slab test
    /// is monotone in the box and in `tmax`) and tests the primitive with the same code.
    fn is_artifact(bvh: &Bvh, h: &Hit, o: Vec3, d: Vec3, tmin: f32) -> bool {
        let b = prim_bounds(&bvh.prims[h.prim as usize]);
        !BoxRay::new(o, d)
            .slab(b.min.into(), b.max.into(), tmin, h.t)
            .0
    }

    /// Closest and any hit through the BVH against brute force over `bvh.prims`:
    /// exactly the same `t` (the same intersection code runs on the same primitive) and
    /// the same primitive unless another ties at that `t`; the one exception is a
    /// closer brute-force hit that `is_artifact`. `any` must agree with `closest`; no
    /// NaN or infinity in a hit. Returns (rays that hit, artifacts).
    fn check_rays(bvh: &Bvh, rays: &[(Vec3, Vec3, f32, f32)]) -> (usize, usize) {
        let (mut hits, mut artifacts) = (0, 0);
        for &(o, d, tmin, tmax) in rays {
            let a = bvh.closest(o, d, tmin, tmax);
            let b = brute_force_closest(&bvh.prims, o, d, tmin, tmax);
            assert_eq!(bvh.any(o, d, tmin, tmax), a.is_some(), "any: {o} {d}");
            if let Some(a) = a {
                hits += 1;
                let finite = a.t.is_finite() && a.u.is_finite() && a.v.is_finite();
                assert!(finite && a.t > tmin && a.t < tmax, "{a:?}");
            }
            match (a, b) {
                (None, None) => {}
                (Some(a), Some(b)) if a.t == b.t => {}
                (_, Some(b)) if is_artifact(bvh, &b, o, d, tmin) => artifacts += 1,
                _ => panic!("bvh {a:?} vs brute force {b:?} for {o} {d}"),
            }
        }
        (hits, artifacts)
    }

    /// `n` rays: half from outside the box aimed at points inside it, half from inside
    /// in random directions; a few with axis-aligned or zero-component directions.
    fn rays_for(rng: &mut Rng, lo: Vec3, hi: Vec3, n: usize) -> Vec<(Vec3, Vec3, f32, f32)> {
        let c = 0.5 * (lo + hi);
        let r = (hi - lo).length().max(f32::MIN_POSITIVE);
        (0..n)
            .map(|i| {
                let (o, mut d) = if i % 2 == 0 {
                    let o = c + rng.dir() * r * rng.range(0.6, 2.0);
                    (o, rng.vec_in(lo, hi) - o)
                } else {
                    (rng.vec_in(lo, hi), rng.dir() * r)
                };
                if i % 16 == 1 {
                    d[rng.below(3)] = 0.0; // a zero component
                }
                if i % 16 == 3 {
                    let k = rng.below(3);
                    d = Vec3::ZERO;
                    d[k] = if rng.f() < 0.5 { -r } else { r };
                }
                let tmax = if i % 8 == 5 {
                    rng.range(0.1, 1.0)
                } else {
                    f32::INFINITY
                };
                (o, d, 0.0, tmax)
            })
            .collect()
    }

    fn bounds_of(prims: &[Prim]) -> (Vec3, Vec3) {
        let mut b = Aabb::EMPTY;
        prims.iter().for_each(|p| b.grow(&prim_bounds(p)));
        (b.min, b.max)
    }

    fn random_soup(rng: &mut Rng, n: usize, scale: f32, offset: Vec3) -> Vec<Prim> {
        (0..n)
            .map(|i| {
                let c = rng.vec_in(Vec3::splat(-1.0), Vec3::ONE);
                let s = 0.2 * rng.f() * rng.f();
                let mut p = [c + rng.dir() * s, c + rng.dir() * s, c + rng.dir() * s];
                if i % 17 == 0 {
                    p[2] = p[1]; // zero area
                }
                if i % 23 == 0 {
                    p[2] = 0.5 * (p[0] + p[1]); // collinear
                }
                tri(
                    p[0] * scale + offset,
                    p[1] * scale + offset,
                    p[2] * scale + offset,
                )
            })
            .collect()
    }

    #[test]
    fn stack_size_and_constants_match_glsl() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders/accel/bvh.glsl");
        let src = std::fs::read_to_string(path).expect("bvh.glsl");
        let define = |name: &str| -> String {
            src.lines()
                .find_map(|l| {
                    let mut w = l.split_whitespace();
                    (w.next() == Some("#define") && w.next() == Some(name))
                        .then(|| w.next().unwrap_or("").to_string())
                })
                .unwrap_or_else(|| panic!("#define {name} missing in bvh.glsl"))
        };
        assert_eq!(
            define("BVH_STACK_SIZE").parse::<usize>().unwrap(),
            BVH_STACK_SIZE
        );
        assert_eq!(define("BVH_COUNT_BITS"), format!("{BVH_COUNT_BITS}u"));
        assert_eq!(
            define("BVH_FLAT_CAPACITY").parse::<usize>().unwrap(),
            FLAT_CAPACITY
        );
        assert_eq!(define("BVH_FLAT_ONLY"), format!("{FLAT_ONLY:#x}u"));
        // One BVH_FLAT_STEP per primitive it can hold, in order.
        let body = &src[src.find("void bvh_trace_flat").expect("bvh_trace_flat")..];
        let body = &body[..body.find("\n}").expect("end of bvh_trace_flat")];
        let steps: Vec<&str> = body
            .split("BVH_FLAT_STEP(")
            .skip(1)
            .map(|rest| rest.split(')').next().unwrap_or(""))
            .collect();
        let want: Vec<String> = (0..FLAT_STEPS).map(|k| format!("{k}")).collect();
        assert_eq!(steps, want);
        assert_eq!(
            define("BVH_FLAT_VERTEX_CONSTANTS"),
            format!("{FLAT_VERTEX_CONSTANTS:#x}u")
        );
        assert_eq!(FLAT_STEPS as u32, crate::gpu::spec_ids::FLAT_VERTEX_PRIMS);
        assert_eq!(
            define("BVH_COUNT_MASK"),
            format!("{}u", (1u32 << BVH_COUNT_BITS) - 1)
        );
        assert_eq!(
            define("BVH_TFAR_SCALE").parse::<f32>().unwrap(),
            BOX_TFAR_SCALE
        );
        // BOX_TFAR_SCALE is 1 + 2 gamma(3) rounded up.
        let eps = f64::from(f32::EPSILON) / 2.0;
        let gamma3 = 3.0 * eps / (1.0 - 3.0 * eps);
        assert!(f64::from(BOX_TFAR_SCALE) >= 1.0 + 2.0 * gamma3);
        assert!(f64::from(BOX_TFAR_SCALE) < 1.0 + 2.0 * gamma3 + f64::from(f32::EPSILON));
    }

    /// Compiles a kernel that includes bvh.glsl and calls both entry points, when the
    /// system glslangValidator is installed (the build uses it for real kernels); on CI
    /// (`CI` set) it must be.
    #[test]
    fn glsl_compiles() {
        let shaders = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders");
        let dir = std::env::temp_dir().join(format!("wavetrace-bvhcheck-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let comp = dir.join("bvhcheck.comp");
        std::fs::write(
            &comp,
            r#"#version 460
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;
#include "scene/scene_bindings.glsl"
#include "accel/bvh.glsl"
layout(std430, set = 1, binding = 0) buffer Io { vec4 io[]; };
void main() {
    uint i = gl_GlobalInvocationID.x;
    Hit h = bvh_closest(io[2 * i].xyz, io[2 * i + 1].xyz, io[2 * i].w, io[2 * i + 1].w);
    bool a = bvh_any(io[2 * i].xyz, io[2 * i + 1].xyz, io[2 * i].w, io[2 * i + 1].w);
    io[2 * i] = vec4(h.t, h.u, h.v, uintBitsToFloat(h.prim + (a ? 1u : 0u)));
}
"#,
        )
        .unwrap();
        let out = std::process::Command::new("glslangValidator")
            .args(["-V", "--target-env", "vulkan1.2"])
            .arg(format!("-I{shaders}"))
            // The headers build.rs generates (records, specialization constants).
            .arg(format!("-I{}/glsl", env!("OUT_DIR")))
            .arg(&comp)
            .arg("-o")
            .arg(dir.join("bvhcheck.spv"))
            .output();
        let _ = std::fs::remove_dir_all(&dir);
        match out {
            // CI installs glslang: there a missing compiler fails the test.
            Err(e) if std::env::var_os("CI").is_some() => {
                panic!("glslangValidator not run on CI ({e})")
            }
            Err(e) => eprintln!("glslangValidator not run ({e}); skipping"),
            Ok(o) => assert!(
                o.status.success(),
                "bvh.glsl does not compile:\n{}{}",
                String::from_utf8_lossy(&o.stdout),
                String::from_utf8_lossy(&o.stderr)
            ),
        }
    }

    #[test]
    fn bunny_matches_brute_force() {
        let (pos, idx) = load_bunny();
        let bvh = Bvh::build(mesh_prims(&pos, &idx));
        validate(&bvh);
        let (lo, hi) = bounds_of(&bvh.prims);
        let mut rng = Rng(1);
        let rays = rays_for(&mut rng, lo, hi, 100_000);
        let (hits, artifacts) = check_rays(&bvh, &rays);
        assert_eq!(artifacts, 0);
        assert!(
            hits > 30_000,
            "{hits} hits: rays should mostly hit the bunny"
        );
    }

    #[test]
    fn random_soups_match_brute_force() {
        let mut rng = Rng(2);
        // Scales from tiny to huge, offset far from the origin for one of them. Beyond
        // ~1e18 the edge functions (products of two coordinates) overflow f32: the
        // test then finds nothing, but builds, agrees with brute force and makes no NaN.
        for (n, scale, offset, hits_expected) in [
            (400, 1.0, Vec3::ZERO, true),
            (300, 1e-3, Vec3::ZERO, true),
            (300, 1e-12, Vec3::new(1e-11, 0.0, 0.0), true),
            (300, 1e12, Vec3::ZERO, true),
            (300, 1e17, Vec3::ZERO, true),
            (300, 1e-2, Vec3::new(1e4, -2e4, 3e3), true),
            (300, 1e30, Vec3::ZERO, false),
        ] {
            let bvh = Bvh::build(random_soup(&mut rng, n, scale, offset));
            validate(&bvh);
            let (lo, hi) = bounds_of(&bvh.prims);
            let rays = rays_for(&mut rng, lo, hi, 20_000);
            let (hits, artifacts) = check_rays(&bvh, &rays);
            println!("soup x{scale}: {hits} hits, {artifacts} artifacts (degenerate triangles)");
            // At most 1%: the 1e-2 soup at 1e4 is numerically degenerate throughout
            // (ulp 1e-3); the others stay below 0.1%.
            assert!(artifacts * 100 < rays.len(), "{artifacts}");
            assert_eq!(hits > 500, hits_expected, "scale {scale}: {hits} hits");
        }
    }

    #[test]
    fn slivers_and_coplanar_overlaps_match_brute_force() {
        let mut rng = Rng(3);
        let mut prims = Vec::new();
        // Slivers: long and a millionth as wide, fanned around the origin.
        for i in 0..300 {
            let a = rng.dir();
            let b = rng.dir() * 2.0;
            let w = rng.dir() * 1e-6 * (1 + i % 7) as f32;
            prims.push(tri(a, b, b + w));
        }
        // Coplanar overlapping triangles in z = 0.25 and in a tilted plane.
        let (u, v) = (
            Vec3::new(1.0, 0.0, 0.3).normalize(),
            Vec3::new(0.0, 1.0, -0.2).normalize(),
        );
        for _ in 0..300 {
            let p = |r: &mut Rng| Vec3::new(r.range(-1.0, 1.0), r.range(-1.0, 1.0), 0.25);
            prims.push(tri(p(&mut rng), p(&mut rng), p(&mut rng)));
            let q = |r: &mut Rng| r.range(-1.0, 1.0) * u + r.range(-1.0, 1.0) * v;
            prims.push(tri(q(&mut rng), q(&mut rng), q(&mut rng)));
        }
        // The same triangle several times.
        for _ in 0..5 {
            prims.push(tri(
                Vec3::new(-1.0, -1.0, -0.5),
                Vec3::new(1.0, -1.0, -0.5),
                Vec3::new(0.0, 1.0, -0.5),
            ));
        }
        let bvh = Bvh::build(prims);
        validate(&bvh);
        let (lo, hi) = bounds_of(&bvh.prims);
        let rays = rays_for(&mut rng, lo, hi, 100_000);
        let (hits, artifacts) = check_rays(&bvh, &rays);
        println!("slivers, coplanar: {hits} hits, {artifacts} artifacts (edge-on slivers)");
        assert!(artifacts * 1000 < rays.len(), "{artifacts}");
        assert!(hits > 10_000, "{hits}");
    }

    /// Rays aimed exactly at vertices and at points on edges of closed meshes, from
    /// inside (they must leave) and from outside along the inward normal (they must
    /// enter there): every one hits, at the target or before it (rounding makes the
    /// tiny icosphere far from the origin slightly non-convex).
    #[test]
    fn closed_meshes_do_not_leak() {
        let mut rng = Rng(4);
        let (ipos, iidx) = icosphere(3);
        let (cpos, cidx) = cube();
        let mut total = 0;
        for (pos, idx, scale, offset) in [
            (&ipos, &iidx, 1.0, Vec3::ZERO),
            (&ipos, &iidx, 1e-3, Vec3::new(1e3, 0.0, -5e2)),
            (&ipos, &iidx, 1e4, Vec3::new(0.0, 3e4, 0.0)),
            (&cpos, &cidx, 1.0, Vec3::ZERO),
            (&cpos, &cidx, 0.37, Vec3::new(-3.0, 1e2, 0.5)),
        ] {
            let pos: Vec<Vec3> = pos.iter().map(|&p| p * scale + offset).collect();
            let bvh = Bvh::build(mesh_prims(&pos, idx));
            validate(&bvh);
            let mut targets: Vec<Vec3> = pos.clone();
            for &[a, b, c] in idx.iter() {
                for (i, j) in [(a, b), (b, c), (c, a)] {
                    let (p, q) = (pos[i as usize], pos[j as usize]);
                    targets.push(0.5 * (p + q));
                    for _ in 0..4 {
                        targets.push(p.lerp(q, rng.f()));
                    }
                }
            }
            // Face centers of the cube lie on the diagonals: hit with axis-aligned rays.
            let mut inside = vec![offset, offset + Vec3::new(0.1, -0.2, 0.3) * scale];
            for _ in 0..6 {
                inside.push(offset + rng.dir() * 0.5 * scale * rng.f());
            }
            for &t in &targets {
                for &o in &inside {
                    let d = t - o;
                    let h = bvh.closest(o, d, 0.0, f32::INFINITY);
                    let h = h.unwrap_or_else(|| panic!("leak from inside: {o} -> {t}"));
                    // An edge point computed in f32 may sit a few ulps off the surface.
                    let slack = 4.0 * f32::EPSILON * t.abs().max_element() / d.length();
                    assert!(h.t <= 1.0 + 1e-4 + slack, "{h:?} {o} -> {t}");
                    assert!(bvh.any(o, d, 0.0, f32::INFINITY));
                    total += 1;
                }
                // From outside, roughly along the inward normal.
                let n = (t - offset).normalize();
                let o = t + (n * 2.0 + rng.dir() * 0.3) * scale;
                let h = bvh.closest(o, t - o, 0.0, f32::INFINITY);
                let h = h.unwrap_or_else(|| panic!("leak from outside: {o} -> {t}"));
                // An edge point computed in f32 may sit a few ulps off the surface.
                let slack = 4.0 * f32::EPSILON * t.abs().max_element() / (t - o).length();
                assert!(h.t <= 1.0 + 1e-4 + slack, "{h:?} {o} -> {t}");
                total += 1;
            }
            // Axis-aligned rays from the center through face centers, edges, corners.
            for d in [
                Vec3::X,
                Vec3::NEG_X,
                Vec3::Y,
                Vec3::NEG_Y,
                Vec3::Z,
                Vec3::NEG_Z,
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, -1.0, 1.0),
                Vec3::ONE,
                -Vec3::ONE,
            ] {
                assert!(
                    bvh.closest(offset, d, 0.0, f32::INFINITY).is_some(),
                    "leak along {d}"
                );
            }
        }
        assert!(total > 100_000, "{total} rays");
    }

    /// A fine open grid: rays aimed exactly at interior vertices and edge points, from
    /// above and below, including axis-aligned rays whose origin lies on the slab
    /// planes of the leaf boxes (0 * inf in the slab test).
    #[test]
    fn grid_vertices_and_edges_do_not_leak() {
        let mut rng = Rng(5);
        let n = 64;
        let (pos, idx) = grid(n);
        let tilt = glam::Mat3::from_rotation_x(0.3) * glam::Mat3::from_rotation_z(0.2);
        for transform in [glam::Mat3::IDENTITY, tilt] {
            let pos: Vec<Vec3> = pos.iter().map(|&p| transform * p).collect();
            let bvh = Bvh::build(mesh_prims(&pos, &idx));
            validate(&bvh);
            let up = transform * Vec3::Z;
            let mut count = 0;
            for j in 1..n {
                for i in 1..n {
                    let v = |i: u32, j: u32| pos[(j * (n + 1) + i) as usize];
                    let p = v(i, j);
                    let mut targets = vec![p, 0.5 * (p + v(i + 1, j)), 0.5 * (p + v(i, j + 1))];
                    targets.push(p.lerp(v(i + 1, j), rng.f()));
                    targets.push(p.lerp(v(i, j + 1), rng.f()));
                    targets.push(p.lerp(v(i + 1, j + 1), rng.f()));
                    targets.push(p.lerp(v(i - 1, j + 1), rng.f()));
                    for t in targets {
                        for o in [t + up, t - up * 0.5, t + up * 0.7 + rng.dir() * 0.5] {
                            let h = bvh.closest(o, t - o, 0.0, f32::INFINITY);
                            let h = h.unwrap_or_else(|| panic!("leak: {o} -> {t}"));
                            assert!((h.t - 1.0).abs() < 1e-4, "{h:?}");
                            assert!(bvh.any(o, t - o, 0.0, 2.0));
                            count += 1;
                        }
                    }
                }
            }
            assert!(count > 50_000);
            let (lo, hi) = bounds_of(&bvh.prims);
            let (_, artifacts) = check_rays(&bvh, &rays_for(&mut rng, lo, hi, 10_000));
            assert_eq!(artifacts, 0);
        }
    }

    #[test]
    fn spheres_mixed_with_triangles() {
        let mut rng = Rng(6);
        let mut prims = random_soup(&mut rng, 300, 1.0, Vec3::ZERO);
        for _ in 0..60 {
            prims.push(sphere(
                rng.vec_in(Vec3::splat(-1.0), Vec3::ONE),
                0.15 * rng.f(),
            ));
        }
        let far = Vec3::new(1e4, 2e3, -5e3);
        prims.push(sphere(far, 1e-3)); // tiny and far from the origin
        let far_big = Vec3::new(-1e4, 3e3, 2e3);
        prims.push(sphere(far_big, 0.1)); // far from the origin
        prims.push(sphere(Vec3::new(0.0, -1e4, 0.0), 1e4 - 2.0)); // huge ground
        prims.push(sphere(Vec3::new(0.3, 0.2, 0.1), 1e-3)); // tiny
        let bvh = Bvh::build(prims);
        validate(&bvh);
        let rays = rays_for(&mut rng, Vec3::splat(-1.5), Vec3::splat(1.5), 60_000);
        let (_, artifacts) = check_rays(&bvh, &rays);
        assert!(artifacts * 1000 < rays.len(), "{artifacts}");
        let prim_at = |c: Vec3| {
            bvh.prims
                .iter()
                .position(|p| Vec3::from(p.p0) == c)
                .unwrap()
        };
        let mut rays = Vec::new();
        for _ in 0..2000 {
            let o = rng.vec_in(Vec3::splat(-3.0), Vec3::splat(3.0)) + Vec3::Y * 5.0;
            // The tiny far sphere, aimed at exactly: f = o - c and d = c - o round
            // alike, so the closest-point vector l is exactly 0. (With a normalized d,
            // f32 direction error alone, 6e-8 x 1e4, is most of the radius 1e-3.)
            let d = far - o;
            let h = bvh
                .closest(o, d, 0.0, f32::INFINITY)
                .expect("far tiny sphere");
            assert_eq!(h.prim as usize, prim_at(far));
            let dist = d.length();
            assert!((h.t * dist - (dist - 1e-3)).abs() <= 1e-6 * dist, "{}", h.t);
            rays.push((o, d, 0.0, f32::INFINITY));
            // The r = 0.1 far sphere with normalized directions anywhere within 0.9 r
            // of its center: the textbook discriminant b^2 - 4ac (b^2 ~ 4e8, ulp 32)
            // cannot resolve 4 a r^2 = 0.04 here.
            let target = far_big + rng.dir() * 0.09 * rng.f();
            let d = (target - o).normalize();
            let h = bvh.closest(o, d, 0.0, f32::INFINITY).expect("far sphere");
            assert_eq!(h.prim as usize, prim_at(far_big));
            let q = o + h.t * d;
            assert!(((q - far_big).length() - 0.1).abs() < 1e-6 * 1e4, "{q}");
            rays.push((o, d, 0.0, f32::INFINITY));
        }
        let (_, artifacts) = check_rays(&bvh, &rays);
        assert_eq!(artifacts, 0);
        // And at the tiny one near the origin, from inside the scene.
        let tiny = Vec3::new(0.3, 0.2, 0.1);
        for _ in 0..1000 {
            let o = tiny + rng.dir() * 0.01;
            let h = bvh
                .closest(o, tiny - o, 0.0, f32::INFINITY)
                .expect("tiny sphere");
            assert_eq!(Vec3::from(bvh.prims[h.prim as usize].p0), tiny);
        }
    }

    /// A few quadrics among triangles stay out of the tree (Bvh::apart), tested first;
    /// closest and any-hit still match the brute force, and the scene's bounds hold them.
    #[test]
    fn a_few_quadrics_are_tested_apart() {
        let mut rng = Rng(7);
        let mut prims = random_soup(&mut rng, 300, 1.0, Vec3::ZERO);
        let spheres = [
            sphere(Vec3::new(0.3, 0.2, 0.1), 0.4),
            sphere(Vec3::new(-0.5, 0.1, 0.6), 0.2),
            sphere(Vec3::new(0.0, -1e4, 0.0), 1e4 - 1.0), // a huge ground
            sphere(Vec3::new(0.9, 0.9, 0.9), 1e-3),
            sphere(Vec3::new(5.0, 0.0, 0.0), 0.5), // beyond the triangles
        ];
        // Spread among the triangles, as a scene file would give them.
        for (k, q) in spheres.iter().enumerate() {
            prims.insert(50 * k + 7, *q);
        }
        let bvh = Bvh::build(prims.clone());
        validate(&bvh);
        assert_eq!(bvh.apart as usize, spheres.len());
        let (lo, hi) = bvh.bounds().expect("bounds");
        assert!(lo.y <= -2e4 + 1.0 && hi.x >= 5.5, "{lo} {hi}");
        let rays = rays_for(&mut rng, Vec3::splat(-1.5), Vec3::splat(1.5), 40_000);
        let (_, artifacts) = check_rays(&bvh, &rays);
        assert!(artifacts * 1000 < rays.len(), "{artifacts}");
        // More than APART_QUADRICS_MAX quadrics, or no triangle: the tree holds them all.
        prims.extend((0..APART_QUADRICS_MAX).map(|k| sphere(Vec3::splat(k as f32), 0.1)));
        assert_eq!(Bvh::build(prims).apart, 0);
        assert_eq!(Bvh::build(spheres.to_vec()).apart, 0);
    }

    #[test]
    fn empty_single_and_coincident_inputs() {
        let empty = Bvh::build(Vec::new());
        validate(&empty);
        assert_eq!(empty.nodes.len(), 1);
        assert_eq!(empty.stats.leaf_count, 0);
        assert!(empty
            .closest(Vec3::ZERO, Vec3::X, 0.0, f32::INFINITY)
            .is_none());
        assert!(!empty.any(Vec3::ZERO, Vec3::X, 0.0, f32::INFINITY));

        let one = Bvh::build(vec![tri(
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(1.0, 1.0, -1.0),
            Vec3::new(1.0, 0.0, 1.0),
        )]);
        validate(&one);
        assert_eq!(one.nodes.len(), 1);
        assert_eq!(one.stats.max_depth, 1);
        let h = one
            .closest(Vec3::ZERO, Vec3::X, 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!((h.t, h.prim), (1.0, 0));
        let ball = Bvh::build(vec![sphere(Vec3::new(0.0, 0.0, 5.0), 1.0)]);
        validate(&ball);
        assert_eq!(
            ball.closest(Vec3::ZERO, Vec3::Z, 0.0, f32::INFINITY)
                .unwrap()
                .t,
            4.0
        );

        let mut rng = Rng(7);
        let same = tri(Vec3::ZERO, Vec3::X, Vec3::Y);
        // Identical copies; then same centroid, different sizes; then identical points.
        // Each set: primitives, whether coplanar overlaps make artifacts expected.
        let nested = |tilt: f32| -> Vec<Prim> {
            (0..1000)
                .map(|i| {
                    let s = 1.0 + i as f32;
                    let a = s * tilt * ((i % 7) as f32 - 3.0);
                    let p0 = Vec3::new(-s, -s, a);
                    tri(p0, Vec3::new(s, -s, -a), Vec3::new(-s, s, 0.0))
                })
                .collect()
        };
        let sets = [
            (vec![same; 1000], false),
            (nested(0.0), true),
            (nested(0.05), true),
            (vec![tri(Vec3::ONE, Vec3::ONE, Vec3::ONE); 100], false),
            (
                (0..500)
                    .map(|i| sphere(Vec3::ONE, 0.1 + i as f32))
                    .collect(),
                false,
            ),
        ];
        for (prims, overlapping) in sets {
            let bvh = Bvh::build(prims);
            validate(&bvh);
            let (lo, hi) = bounds_of(&bvh.prims);
            let rays = rays_for(&mut rng, lo - 0.5, hi + 0.5, 4000);
            let (hits, artifacts) = check_rays(&bvh, &rays);
            println!("coincident centroids: {hits} hits, {artifacts} artifacts");
            if !overlapping {
                assert_eq!(artifacts, 0);
            }
        }
    }

    /// Exponentially spaced triangles make SAH peel off one per level; the build must
    /// still keep every leaf within the traversal stack.
    #[test]
    fn depth_bound_holds_on_pathological_input() {
        let prims: Vec<Prim> = (0..1000)
            .map(|i| {
                let x = 1.09f32.powi(i);
                tri(
                    Vec3::new(x, 0.0, 0.0),
                    Vec3::new(x * 1.01, 1.0, 0.0),
                    Vec3::new(x, 0.0, 1.0),
                )
            })
            .collect();
        for method in [SplitMethod::Sah, SplitMethod::Median] {
            let bvh = Bvh::build_with(prims.clone(), method);
            validate(&bvh);
            assert!(bvh.stats.max_depth <= BVH_STACK_SIZE);
            let mut rng = Rng(8);
            let mut rays = Vec::new();
            for _ in 0..5000 {
                let x = 1.09f32.powf(rng.range(-5.0, 1005.0));
                let o = Vec3::new(x, rng.range(-0.5, 1.5), rng.range(-0.5, 1.5));
                rays.push((
                    o,
                    Vec3::new(rng.range(-1.0, 1.0), 0.0, 1.0),
                    0.0,
                    f32::INFINITY,
                ));
                rays.push((Vec3::new(-1.0, 0.1, 0.1), Vec3::X, 0.0, f32::INFINITY));
                rays.push((
                    o - Vec3::Z,
                    Vec3::new(1.0, 0.0, x * 1e-3),
                    0.0,
                    f32::INFINITY,
                ));
            }
            let (_, artifacts) = check_rays(&bvh, &rays);
            assert_eq!(artifacts, 0);
        }
    }

    /// Subdivides each triangle into `k^2`.
    fn subdivide(pos: &[Vec3], idx: &[[u32; 3]], k: u32) -> Vec<Prim> {
        let mut prims = Vec::with_capacity(idx.len() * (k * k) as usize);
        for &[a, b, c] in idx {
            let (a, b, c) = (pos[a as usize], pos[b as usize], pos[c as usize]);
            let p = |i: u32, j: u32| {
                a + (b - a) * (i as f32 / k as f32) + (c - a) * (j as f32 / k as f32)
            };
            for j in 0..k {
                for i in 0..k - j {
                    prims.push(tri(p(i, j), p(i + 1, j), p(i, j + 1)));
                    if i + j + 1 < k {
                        prims.push(tri(p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)));
                    }
                }
            }
        }
        prims
    }

    #[test]
    fn sah_beats_median_and_builds_fast() {
        let (pos, idx) = load_bunny();
        let prims = mesh_prims(&pos, &idx);
        let sah = Bvh::build(prims.clone());
        let median = Bvh::build_with(prims, SplitMethod::Median);
        validate(&sah);
        validate(&median);
        println!("bunny {} tris, SAH: {:?}", sah.prims.len(), sah.stats);
        println!(
            "bunny {} tris, median: {:?}",
            median.prims.len(),
            median.stats
        );
        assert!(sah.stats.sah_cost < median.stats.sah_cost);
        assert!(sah.stats.leaf_count >= sah.prims.len() / BVH_MAX_LEAF_SIZE);

        // The shipped bunny has 2k triangles; 36 per triangle makes it 72k.
        let big = subdivide(&pos, &idx, 6);
        assert_eq!(big.len(), idx.len() * 36);
        let bvh = Bvh::build(big);
        println!("bunny x36 {} tris, SAH: {:?}", bvh.prims.len(), bvh.stats);
        validate(&bvh);
        // Measured about 0.1 s alone (opt-level 1); the bound leaves room for a loaded
        // machine running the other tests in parallel.
        assert!(bvh.stats.build_seconds < 1.0, "{:?}", bvh.stats);
        let mut rng = Rng(9);
        let (lo, hi) = bounds_of(&bvh.prims);
        let (_, artifacts) = check_rays(&bvh, &rays_for(&mut rng, lo, hi, 2000));
        assert_eq!(artifacts, 0);
    }
}
