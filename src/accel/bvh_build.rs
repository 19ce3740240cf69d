//! The BVH build: binned SAH over all three axes (Wald 2007, "On fast Construction of
//! SAH-based Bounding Volume Hierarchies", section 3), [`SAH_BINS`] bins over the
//! centroid bounds of each node, the cheapest of the `3 (SAH_BINS - 1)` planes wins. A
//! node becomes a leaf when it holds one primitive, or at most [`BVH_MAX_LEAF_SIZE`]
//! and the SAH says splitting does not pay. When every centroid coincides on every axis
//! the range is split in half. Depth is bounded by [`BVH_STACK_SIZE`]: near that limit
//! only median splits, which halve the count, are allowed.
//!
//! Memory and time, for scenes of tens of millions of triangles:
//! - The input is read through a [`PrimSource`] (a scene's meshes, [`ShapePrims`]),
//!   never copied whole: the build sorts 28-byte [`BuildPrim`]s (box and input index)
//!   in place, and the output [`Prim`]s (48 bytes) are made once, in leaf order, at the
//!   end. Peak: the build primitives with the nodes (64 bytes per inner node, about
//!   one per two triangles) twice over while they are gathered, or with the nodes and
//!   the output primitives: about 110 bytes a triangle besides the input meshes.
//! - Each node's box and centroid box are gathered by its parent's partition, so a
//!   level costs one binning pass and one partition over its primitives; small nodes
//!   (most of them) look only at their occupied bins.
//! - Both halves of a large node are built in parallel (`rayon::join`), and the
//!   binning of a large node runs over chunks in parallel; subtrees below
//!   [`PARALLEL_MIN`] primitives are built sequentially, each into its own node list,
//!   and the lists are joined at the end.
//!
//! The tree does not depend on the parallel schedule: bins merge by exact min/max and
//! integer counts, so every decision is the one a sequential build makes.

use glam::{Vec3, Vec3A};
use rayon::prelude::*;

use super::bvh::{
    prim_bounds, SplitMethod, APART_QUADRICS_MAX, BVH_MAX_LEAF_SIZE, BVH_STACK_SIZE,
    MEDIAN_LEAF_SIZE, SAH_BINS, SAH_INTERSECTION_COST, SAH_TRAVERSAL_COST,
};
use super::{quadric_prim, triangle_prim};
use crate::gpu::layout::{
    BvhNode, Prim, PRIM_CYLINDER, PRIM_DISK, PRIM_LINEAR_CURVE, PRIM_SPHERE, PRIM_TRIANGLE,
};
use crate::scene::{Mesh, Quadric};

/// Subtrees over fewer primitives are built by one thread into one node list.
pub const PARALLEL_MIN: usize = 1 << 15;

/// Nodes over at least this many primitives bin them in parallel chunks.
const PARALLEL_BINNING_MIN: usize = 1 << 17;

/// Where a build reads its input primitives: how many, and each by index. Indices run
/// over `0..len()`; the built [`super::Bvh`] holds the same primitives in leaf order.
pub trait PrimSource: Sync {
    fn len(&self) -> usize;
    fn prim(&self, i: usize) -> Prim;
    /// The `PRIM_*` kind of primitive `i` (a source may know it without making it).
    fn kind(&self, i: usize) -> u32 {
        self.prim(i).kind
    }
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl PrimSource for [Prim] {
    fn len(&self) -> usize {
        <[Prim]>::len(self)
    }
    fn prim(&self, i: usize) -> Prim {
        self[i]
    }
}

/// The primitives of a list of meshes and quadrics, made on demand: each triangle of
/// each mesh in order, then each quadric, numbered as [`super::prims_from_shapes`]
/// numbers them (shape `i` is mesh `i`, then the quadrics; a triangle's `index` is its
/// global triangle number, a quadric's its position in the list).
pub struct ShapePrims<'a> {
    meshes: &'a [Mesh],
    quadrics: &'a [Quadric],
    /// Global number of each mesh's first triangle, and the total at the end.
    first: Vec<usize>,
    /// Whether some mesh is curves ([`Mesh::is_curves`]).
    curves: bool,
}

impl<'a> ShapePrims<'a> {
    pub fn new(meshes: &'a [Mesh], quadrics: &'a [Quadric]) -> ShapePrims<'a> {
        let mut first = Vec::with_capacity(meshes.len() + 1);
        let mut n = 0;
        for m in meshes {
            first.push(n);
            n += m.indices.len();
        }
        first.push(n);
        ShapePrims {
            meshes,
            quadrics,
            first,
            curves: meshes.iter().any(Mesh::is_curves),
        }
    }

    fn triangles(&self) -> usize {
        self.first[self.meshes.len()]
    }
}

impl PrimSource for ShapePrims<'_> {
    fn len(&self) -> usize {
        self.triangles() + self.quadrics.len()
    }

    fn prim(&self, i: usize) -> Prim {
        let triangles = self.triangles();
        if i < triangles {
            // The mesh whose triangles hold i: the last with first <= i.
            let shape = self.first.partition_point(|&f| f <= i) - 1;
            let mesh = &self.meshes[shape];
            triangle_prim(mesh, i - self.first[shape], shape as u32, i as u32)
        } else {
            let k = i - triangles;
            quadric_prim(&self.quadrics[k], (self.meshes.len() + k) as u32, k as u32)
        }
    }

    fn kind(&self, i: usize) -> u32 {
        if i < self.triangles() {
            if self.curves {
                let mesh = &self.meshes[self.first.partition_point(|&f| f <= i) - 1];
                if mesh.is_ellipsoids() {
                    return crate::gpu::layout::PRIM_ELLIPSOID;
                }
                if mesh.is_bspline() {
                    return crate::gpu::layout::PRIM_BSPLINE_CURVE;
                }
                if mesh.is_curves() {
                    return PRIM_LINEAR_CURVE;
                }
            }
            PRIM_TRIANGLE
        } else {
            self.prim(i).kind
        }
    }
}

/// An axis-aligned box in SIMD registers (`Vec3A`), the build's working form of
/// [`super::bvh::Aabb`]: the same arithmetic lane by lane, so the same tree.
#[derive(Clone, Copy, Debug)]
struct Box3 {
    min: Vec3A,
    max: Vec3A,
}

impl Box3 {
    const EMPTY: Box3 = Box3 {
        min: Vec3A::INFINITY,
        max: Vec3A::NEG_INFINITY,
    };

    #[inline]
    fn grow(&mut self, b: &Box3) {
        self.min = self.min.min(b.min);
        self.max = self.max.max(b.max);
    }

    #[inline]
    fn grow_point(&mut self, p: Vec3A) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    /// Surface area in f64, as [`super::bvh::Aabb::area`].
    #[inline]
    fn area(&self) -> f64 {
        let e = self.max - self.min;
        if e.x < 0.0 || e.y < 0.0 || e.z < 0.0 {
            return 0.0;
        }
        let (x, y, z) = (e.x as f64, e.y as f64, e.z as f64);
        2.0 * (x * y + y * z + z * x)
    }
}

/// A primitive while the tree is built: its box and its index in the input.
#[derive(Clone, Copy)]
struct BuildPrim {
    min: Vec3,
    index: u32,
    max: Vec3,
}

const _: () = assert!(std::mem::size_of::<BuildPrim>() == 28);

impl BuildPrim {
    /// Box center, not vertex mean: 0.5 min + 0.5 max cannot overflow.
    #[inline]
    fn centroid(&self) -> Vec3A {
        0.5 * Vec3A::from(self.min) + 0.5 * Vec3A::from(self.max)
    }

    #[inline]
    fn aabb(&self) -> Box3 {
        Box3 {
            min: self.min.into(),
            max: self.max.into(),
        }
    }
}

/// The box of a set of primitives and the box of their centroids.
#[derive(Clone, Copy)]
struct Extent {
    bounds: Box3,
    centroids: Box3,
}

impl Extent {
    const EMPTY: Extent = Extent {
        bounds: Box3::EMPTY,
        centroids: Box3::EMPTY,
    };

    #[inline]
    fn add(&mut self, p: &BuildPrim) {
        self.bounds.grow(&p.aabb());
        self.centroids.grow_point(p.centroid());
    }

    fn merge(mut self, o: &Extent) -> Extent {
        self.bounds.grow(&o.bounds);
        self.centroids.grow(&o.centroids);
        self
    }

    fn of(prims: &[BuildPrim]) -> Extent {
        if prims.len() < PARALLEL_BINNING_MIN {
            let mut e = Extent::EMPTY;
            prims.iter().for_each(|p| e.add(p));
            return e;
        }
        prims
            .par_chunks(PARALLEL_BINNING_MIN / 4)
            .map(|c| {
                let mut e = Extent::EMPTY;
                c.iter().for_each(|p| e.add(p));
                e
            })
            .reduce(|| Extent::EMPTY, |a, b| a.merge(&b))
    }
}

/// A finished subtree as its parent sees it: box and `(index, count)` as in [`BvhNode`].
#[derive(Clone, Copy)]
struct ChildRef {
    bounds: Box3,
    index: u32,
    count: u32,
}

impl ChildRef {
    const EMPTY: ChildRef = ChildRef {
        bounds: Box3::EMPTY,
        index: 0,
        count: 0,
    };
}

fn make_node(l: &ChildRef, r: &ChildRef) -> BvhNode {
    BvhNode {
        left_min: l.bounds.min.into(),
        left_index: l.index,
        left_max: l.bounds.max.into(),
        left_count: l.count,
        right_min: r.bounds.min.into(),
        right_index: r.index,
        right_max: r.bounds.max.into(),
        right_count: r.count,
    }
}

/// `ceil(log2(m))` for `m >= 1`.
fn ceil_log2(m: usize) -> usize {
    (usize::BITS - (m - 1).leading_zeros()) as usize
}

/// One SAH bin: the box of its primitives and their count.
#[derive(Clone, Copy)]
struct Bin {
    bounds: Box3,
    count: u32,
}

/// The bins of all three axes.
type Bins = [[Bin; SAH_BINS]; 3];

const EMPTY_BINS: Bins = [[Bin {
    bounds: Box3::EMPTY,
    count: 0,
}; SAH_BINS]; 3];

fn merge_bins(mut a: Bins, b: &Bins) -> Bins {
    for axis in 0..3 {
        for k in 0..SAH_BINS {
            a[axis][k].bounds.grow(&b[axis][k].bounds);
            a[axis][k].count += b[axis][k].count;
        }
    }
    a
}

/// Nodes of at most this many primitives find their best plane from their few
/// occupied bins ([`Binning::best_plane_sparse`]) instead of filling and sweeping all
/// `3 SAH_BINS`: the same plane, found without the fixed cost that dominated the
/// build (most nodes are small).
const SPARSE_MAX: usize = 32;

/// The cheapest plane of a sweep: (cost, axis, plane), cost `A_L n_L + A_R n_R`, the
/// plane `k` sending bins `< k` left; infinite cost if no plane separates anything.
type Plane = (f64, usize, usize);

/// Bin index k = floor((c - cmin) * K / extent), clamped: the largest centroid lands in
/// the last bin. An axis with zero (or overflowing) extent has scale 0 and is skipped.
#[derive(Clone, Copy)]
struct Binning {
    min: Vec3A,
    scale: Vec3A,
}

impl Binning {
    fn new(cb: &Box3) -> Binning {
        let extent = cb.max - cb.min;
        Binning {
            min: cb.min,
            scale: Vec3A::select(
                extent.cmpgt(Vec3A::ZERO),
                Vec3A::splat(SAH_BINS as f32) / extent,
                Vec3A::ZERO,
            ),
        }
    }

    #[inline]
    fn bin(&self, c: f32, axis: usize) -> usize {
        (((c - self.min[axis]) * self.scale[axis]) as usize).min(SAH_BINS - 1)
    }

    fn fill(&self, prims: &[BuildPrim]) -> Bins {
        let mut bins = EMPTY_BINS;
        for p in prims {
            // bin() for all three axes at once, lane by lane.
            let k = (p.centroid() - self.min) * self.scale;
            let b = p.aabb();
            for (axis, axis_bins) in bins.iter_mut().enumerate() {
                let bin = &mut axis_bins[(k[axis] as usize).min(SAH_BINS - 1)];
                bin.bounds.grow(&b);
                bin.count += 1;
            }
        }
        bins
    }

    fn fill_parallel(&self, prims: &[BuildPrim]) -> Bins {
        if prims.len() < PARALLEL_BINNING_MIN {
            return self.fill(prims);
        }
        prims
            .par_chunks(PARALLEL_BINNING_MIN / 4)
            .map(|c| self.fill(c))
            .reduce(|| EMPTY_BINS, |a, b| merge_bins(a, &b))
    }

    /// Sweeps each axis right to left for the right-side costs, then left to right
    /// evaluating the plane after each bin (Wald 2007); ties keep the first plane.
    fn best_plane(&self, bins: &Bins, m: usize) -> Plane {
        let mut best = (f64::INFINITY, 0, 0);
        for (axis, bins) in bins.iter().enumerate() {
            if self.scale[axis] == 0.0 {
                continue;
            }
            let mut right_cost = [0.0f64; SAH_BINS];
            let mut acc = Box3::EMPTY;
            let mut n = 0u32;
            for k in (1..SAH_BINS).rev() {
                acc.grow(&bins[k].bounds);
                n += bins[k].count;
                right_cost[k] = acc.area() * n as f64;
            }
            let mut acc = Box3::EMPTY;
            let mut n = 0u32;
            for k in 1..SAH_BINS {
                acc.grow(&bins[k - 1].bounds);
                n += bins[k - 1].count;
                if n == 0 || n as usize == m {
                    continue;
                }
                let cost = acc.area() * n as f64 + right_cost[k];
                if cost < best.0 {
                    best = (cost, axis, k);
                }
            }
        }
        best
    }

    /// [`Binning::best_plane`] for a few primitives, bit for bit: planes between two
    /// occupied bins split alike, so of each run only the first (just after an
    /// occupied bin) is evaluated, and each side's box is the union of the same
    /// primitive boxes (exact in any order).
    fn best_plane_sparse(&self, prims: &[BuildPrim]) -> Plane {
        let m = prims.len();
        debug_assert!(m <= SPARSE_MAX);
        let mut best = (f64::INFINITY, 0, 0);
        let mut order = [(0u8, 0u8); SPARSE_MAX];
        for axis in 0..3 {
            if self.scale[axis] == 0.0 {
                continue;
            }
            for (i, p) in prims.iter().enumerate() {
                order[i] = (self.bin(p.centroid()[axis], axis) as u8, i as u8);
            }
            let order = &mut order[..m];
            order.sort_unstable();
            // Right-side costs after each run of one bin, right to left.
            let mut right_cost = [0.0f64; SPARSE_MAX];
            let mut acc = Box3::EMPTY;
            for j in (1..m).rev() {
                acc.grow(&prims[order[j].1 as usize].aabb());
                right_cost[j] = acc.area() * (m - j) as f64;
            }
            let mut acc = Box3::EMPTY;
            for j in 1..m {
                acc.grow(&prims[order[j - 1].1 as usize].aabb());
                if order[j].0 == order[j - 1].0 {
                    continue; // the same bin: no plane between them
                }
                let cost = acc.area() * j as f64 + right_cost[j];
                let plane = order[j - 1].0 as usize + 1;
                if cost < best.0 {
                    best = (cost, axis, plane);
                }
            }
        }
        best
    }
}

/// Sorts `prims` so that those `left` accepts come first; returns how many, and the
/// extents of both sides. The same swaps as a plain partition, tracking extents.
fn partition(
    prims: &mut [BuildPrim],
    left: impl Fn(&BuildPrim) -> bool,
) -> (usize, Extent, Extent) {
    let (mut lo, mut hi) = (0, prims.len());
    let (mut l, mut r) = (Extent::EMPTY, Extent::EMPTY);
    while lo < hi {
        if left(&prims[lo]) {
            l.add(&prims[lo]);
            lo += 1;
        } else {
            hi -= 1;
            prims.swap(lo, hi);
            r.add(&prims[hi]);
        }
    }
    (lo, l, r)
}

/// What to do with a node.
enum Decision {
    Leaf,
    /// Split after `mid` primitives, with the two halves' extents.
    Split {
        mid: usize,
        left: Extent,
        right: Extent,
    },
}

/// Decides a node over `prims` (non-empty, sorted in place by the split) at `depth`.
/// Invariant: `depth + ceil_log2(prims.len()) <= BVH_STACK_SIZE`.
fn decide(
    prims: &mut [BuildPrim],
    extent: &Extent,
    depth: usize,
    method: SplitMethod,
    parallel: bool,
) -> Decision {
    let m = prims.len();
    if m == 1 {
        return Decision::Leaf;
    }
    // Splitting by SAH can peel off a single primitive per level; near the stack
    // limit only median splits, which halve the count, are allowed.
    let forced_median = depth + 1 + ceil_log2(m) > BVH_STACK_SIZE;
    if forced_median || method == SplitMethod::Median {
        let leaf_size = if forced_median {
            BVH_MAX_LEAF_SIZE
        } else {
            MEDIAN_LEAF_SIZE
        };
        if m <= leaf_size {
            return Decision::Leaf;
        }
        return split_median(prims, &extent.centroids, parallel);
    }
    match split_sah(prims, extent, parallel) {
        Some(d) => d,
        None if m <= BVH_MAX_LEAF_SIZE => Decision::Leaf,
        None => split_median(prims, &extent.centroids, parallel),
    }
}

/// Binned SAH (Wald 2007): the split, or `None` if no plane separates the centroids
/// or (for at most `BVH_MAX_LEAF_SIZE` primitives) a leaf is cheaper.
fn split_sah(prims: &mut [BuildPrim], extent: &Extent, parallel: bool) -> Option<Decision> {
    let m = prims.len();
    let binning = Binning::new(&extent.centroids);
    let (cost, axis, plane) = if m <= SPARSE_MAX {
        binning.best_plane_sparse(prims)
    } else if parallel {
        binning.best_plane(&binning.fill_parallel(prims), m)
    } else {
        binning.best_plane(&binning.fill(prims), m)
    };
    if !cost.is_finite() {
        return None;
    }
    let area = extent.bounds.area();
    let split_cost = SAH_TRAVERSAL_COST * area + SAH_INTERSECTION_COST * cost;
    let leaf_cost = SAH_INTERSECTION_COST * m as f64 * area;
    if m <= BVH_MAX_LEAF_SIZE && leaf_cost <= split_cost {
        return None;
    }
    let (mid, left, right) = partition(prims, |p| binning.bin(p.centroid()[axis], axis) < plane);
    debug_assert!(mid > 0 && mid < m);
    Some(Decision::Split { mid, left, right })
}

/// Object median along the longest centroid axis; the middle of the range if all
/// centroids coincide.
fn split_median(prims: &mut [BuildPrim], cb: &Box3, parallel: bool) -> Decision {
    let mid = prims.len() / 2;
    let extent = cb.max - cb.min;
    if extent.max_element() > 0.0 {
        let axis = extent.max_position();
        prims.select_nth_unstable_by(mid, |a, b| {
            a.centroid()[axis].total_cmp(&b.centroid()[axis])
        });
    }
    let (l, r) = prims.split_at(mid);
    let (left, right) = if parallel {
        rayon::join(|| Extent::of(l), || Extent::of(r))
    } else {
        (Extent::of(l), Extent::of(r))
    };
    Decision::Split { mid, left, right }
}

/// Builds the subtree over `prims` (non-empty, at global position `begin`) into
/// `nodes`, one thread.
fn build_sequential(
    prims: &mut [BuildPrim],
    begin: usize,
    extent: &Extent,
    depth: usize,
    method: SplitMethod,
    nodes: &mut Vec<BvhNode>,
) -> ChildRef {
    let Decision::Split { mid, left, right } = decide(prims, extent, depth, method, false) else {
        return ChildRef {
            bounds: extent.bounds,
            index: begin as u32,
            count: prims.len() as u32,
        };
    };
    let slot = nodes.len();
    nodes.push(BvhNode::default());
    let (lo, hi) = prims.split_at_mut(mid);
    let l = build_sequential(lo, begin, &left, depth + 1, method, nodes);
    let r = build_sequential(hi, begin + mid, &right, depth + 1, method, nodes);
    nodes[slot] = make_node(&l, &r);
    ChildRef {
        bounds: extent.bounds,
        index: slot as u32,
        count: 0,
    }
}

/// A subtree built in parallel, before its nodes are gathered into one list.
enum Subtree {
    /// A leaf: `index` is the global position of its first primitive.
    Leaf(ChildRef),
    /// Inner nodes built by one thread, root first; inner-node references are indices
    /// into `nodes`.
    Local { bounds: Box3, nodes: Vec<BvhNode> },
    /// A node whose halves were built in parallel.
    Split {
        bounds: Box3,
        left: Box<Subtree>,
        right: Box<Subtree>,
    },
}

fn build_parallel(
    prims: &mut [BuildPrim],
    begin: usize,
    extent: &Extent,
    depth: usize,
    method: SplitMethod,
) -> Subtree {
    let m = prims.len();
    if m < PARALLEL_MIN {
        // About one inner node per two primitives under the SAH's small leaves.
        let mut nodes = Vec::with_capacity(m / 2 + 1);
        let root = build_sequential(prims, begin, extent, depth, method, &mut nodes);
        return if root.count > 0 {
            Subtree::Leaf(root)
        } else {
            Subtree::Local {
                bounds: root.bounds,
                nodes,
            }
        };
    }
    let Decision::Split { mid, left, right } = decide(prims, extent, depth, method, true) else {
        return Subtree::Leaf(ChildRef {
            bounds: extent.bounds,
            index: begin as u32,
            count: m as u32,
        });
    };
    let (lo, hi) = prims.split_at_mut(mid);
    let (l, r) = rayon::join(
        || build_parallel(lo, begin, &left, depth + 1, method),
        || build_parallel(hi, begin + mid, &right, depth + 1, method),
    );
    Subtree::Split {
        bounds: extent.bounds,
        left: Box::new(l),
        right: Box::new(r),
    }
}

/// Appends `tree`'s nodes to `out` (pre-order, as a sequential build lays them out)
/// and returns its reference.
fn gather(tree: Subtree, out: &mut Vec<BvhNode>) -> ChildRef {
    match tree {
        Subtree::Leaf(r) => r,
        Subtree::Local { bounds, nodes } => {
            let offset = out.len() as u32;
            out.extend(nodes.into_iter().map(|mut n| {
                if n.left_count == 0 {
                    n.left_index += offset;
                }
                if n.right_count == 0 {
                    n.right_index += offset;
                }
                n
            }));
            ChildRef {
                bounds,
                index: offset,
                count: 0,
            }
        }
        Subtree::Split {
            bounds,
            left,
            right,
        } => {
            let slot = out.len();
            out.push(BvhNode::default());
            let l = gather(*left, out);
            let r = gather(*right, out);
            out[slot] = make_node(&l, &r);
            ChildRef {
                bounds,
                index: slot as u32,
                count: 0,
            }
        }
    }
}

/// Inner nodes in a gathered-to-be tree.
fn node_count(tree: &Subtree) -> usize {
    match tree {
        Subtree::Leaf(_) => 0,
        Subtree::Local { nodes, .. } => nodes.len(),
        Subtree::Split { left, right, .. } => 1 + node_count(left) + node_count(right),
    }
}

/// Builds the nodes over `source` and returns them with the primitives in leaf order,
/// and how many primitives lead that order outside the tree: a scene's quadrics, where
/// it has triangles and at most [`APART_QUADRICS_MAX`] quadrics (the traversals test
/// those in turn before the tree, which then holds triangles alone; `Bvh::apart`).
/// Node 0 is the root and always an inner node.
/// `apart_allowed`: false for the trees of a scene with instances, which hold every
/// primitive (`accel::instance`).
pub(super) fn build<S: PrimSource + ?Sized>(
    source: &S,
    method: SplitMethod,
    apart_allowed: bool,
) -> (Vec<BvhNode>, Vec<Prim>, usize) {
    let n = source.len();
    let quadrics: Vec<usize> = if apart_allowed {
        (0..n)
            .into_par_iter()
            .filter(|&i| matches!(source.kind(i), PRIM_SPHERE | PRIM_DISK | PRIM_CYLINDER))
            .collect()
    } else {
        Vec::new()
    };
    let apart =
        if !quadrics.is_empty() && quadrics.len() <= APART_QUADRICS_MAX && quadrics.len() < n {
            quadrics
        } else {
            Vec::new()
        };
    let build_prim = |i: usize| {
        let b = prim_bounds(&source.prim(i));
        BuildPrim {
            min: b.min,
            index: i as u32,
            max: b.max,
        }
    };
    let mut prims: Vec<BuildPrim> = if apart.is_empty() {
        (0..n).into_par_iter().map(build_prim).collect()
    } else {
        // A few quadrics: the triangles are all the rest.
        (0..n)
            .into_par_iter()
            .filter(|i| apart.binary_search(i).is_err())
            .map(build_prim)
            .collect()
    };
    if prims.is_empty() {
        return (
            vec![make_node(&ChildRef::EMPTY, &ChildRef::EMPTY)],
            Vec::new(),
            0,
        );
    }
    let extent = Extent::of(&prims);
    let tree = build_parallel(&mut prims, 0, &extent, 0, method);
    // Gathering holds the nodes twice over, so it comes before the output primitives
    // (48 bytes each, against 28 for the build primitives still held).
    let mut nodes = Vec::with_capacity(node_count(&tree).max(1));
    let root = gather(tree, &mut nodes);
    if root.count > 0 {
        // A single leaf: the root must still be an inner node.
        nodes.push(make_node(&root, &ChildRef::EMPTY));
    }
    // The leaves index the output, where the primitives apart come first.
    if !apart.is_empty() {
        let shift = apart.len() as u32;
        for node in &mut nodes {
            if node.left_count > 0 {
                node.left_index += shift;
            }
            if node.right_count > 0 {
                node.right_index += shift;
            }
        }
    }
    let mut out: Vec<Prim> = Vec::with_capacity(apart.len() + prims.len());
    out.extend(apart.iter().map(|&i| source.prim(i)));
    out.par_extend(prims.par_iter().map(|p| source.prim(p.index as usize)));
    (nodes, out, apart.len())
}
