//! The BVH: a binned-SAH build on the host, flattened to [`BvhNode`]s, and a CPU
//! traversal that mirrors `shaders/common/bvh.glsl` step for step.
//!
//! Build: binned SAH over all three axes (Wald 2007, "On fast Construction of
//! SAH-based Bounding Volume Hierarchies", section 3), [`SAH_BINS`] bins over the
//! centroid bounds of each node, the cheapest of the `3 (SAH_BINS - 1)` planes wins. A
//! node becomes a leaf when it holds one primitive, or at most [`BVH_MAX_LEAF_SIZE`]
//! and the SAH says splitting does not pay. When every centroid coincides on every axis
//! the index range is split in half. Depth is bounded by [`BVH_STACK_SIZE`] (see
//! [`Bvh::build`]).
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

use super::{sphere, triangle};
use crate::gpu::layout::{BvhNode, Prim, PRIM_SPHERE};

/// Entries in the traversal stack of `shaders/common/bvh.glsl` (`#define
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

/// Bins per axis of the SAH build (Wald 2007 finds 16 to 32 as good as a full sweep).
pub const SAH_BINS: usize = 16;

/// SAH cost of visiting one inner node (fetching it and testing both child boxes).
pub const SAH_TRAVERSAL_COST: f64 = 1.0;

/// SAH cost of one ray/primitive test, relative to [`SAH_TRAVERSAL_COST`].
pub const SAH_INTERSECTION_COST: f64 = 1.0;

/// Leaf size of [`SplitMethod::Median`] builds.
const MEDIAN_LEAF_SIZE: usize = 4;

/// `1 + 2 gamma(3)`, `gamma(n) = n eps / (1 - n eps)`, `eps = 2^-24` (Ize 2013, sec. 3;
/// pbrt-v4 `Bounds3::IntersectP`), which is `1 + 3.58e-7`, rounded up to the next
/// float `1 + 4 * 2^-23`: scales a box's far distance so that the three roundings in
/// `(b - o) * inv_d` never make it smaller than the near one when the exact interval is
/// non-empty. `#define BVH_TFAR_SCALE` in bvh.glsl.
pub const BOX_TFAR_SCALE: f32 = 1.000_000_48;

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
    /// The primitives in leaf order.
    pub prims: Vec<Prim>,
    pub stats: BvhStats,
}

/// An axis-aligned box; `EMPTY` has min = +inf, max = -inf.
#[derive(Clone, Copy, Debug)]
struct Aabb {
    min: Vec3,
    max: Vec3,
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        min: Vec3::INFINITY,
        max: Vec3::NEG_INFINITY,
    };

    #[inline]
    fn grow(&mut self, b: &Aabb) {
        self.min = self.min.min(b.min);
        self.max = self.max.max(b.max);
    }

    #[inline]
    fn grow_point(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
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

/// The bounds of one primitive.
fn prim_bounds(p: &Prim) -> Aabb {
    let p0 = Vec3::from(p.p0);
    if p.kind == PRIM_SPHERE {
        let r = Vec3::splat(p.p1[0].abs());
        Aabb {
            min: p0 - r,
            max: p0 + r,
        }
    } else {
        let (p1, p2) = (Vec3::from(p.p1), Vec3::from(p.p2));
        Aabb {
            min: p0.min(p1).min(p2),
            max: p0.max(p1).max(p2),
        }
    }
}

/// `ceil(log2(m))` for `m >= 1`.
fn ceil_log2(m: usize) -> usize {
    (usize::BITS - (m - 1).leading_zeros()) as usize
}

/// Build state: per-primitive boxes and centroids, and the permutation being sorted.
struct Builder {
    bounds: Vec<Aabb>,
    centroids: Vec<Vec3>,
    order: Vec<u32>,
    nodes: Vec<BvhNode>,
    method: SplitMethod,
}

/// A finished subtree as its parent sees it: box and `(index, count)` as in [`BvhNode`].
#[derive(Clone, Copy)]
struct ChildRef {
    bounds: Aabb,
    index: u32,
    count: u32,
}

impl ChildRef {
    const EMPTY: ChildRef = ChildRef {
        bounds: Aabb::EMPTY,
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

#[derive(Clone, Copy)]
struct Bin {
    bounds: Aabb,
    count: u32,
}

impl Builder {
    /// Builds the subtree over `order[begin..end]` (non-empty), whose top sits at
    /// `depth`. Invariant: `depth + ceil_log2(end - begin) <= BVH_STACK_SIZE`.
    fn build(&mut self, begin: usize, end: usize, depth: usize) -> ChildRef {
        let m = end - begin;
        let mut bounds = Aabb::EMPTY;
        let mut cbounds = Aabb::EMPTY;
        for &i in &self.order[begin..end] {
            bounds.grow(&self.bounds[i as usize]);
            cbounds.grow_point(self.centroids[i as usize]);
        }
        let leaf = ChildRef {
            bounds,
            index: begin as u32,
            count: m as u32,
        };
        if m == 1 {
            return leaf;
        }
        // Splitting by SAH can peel off a single primitive per level; near the stack
        // limit only median splits, which halve the count, are allowed.
        let forced_median = depth + 1 + ceil_log2(m) > BVH_STACK_SIZE;
        let mid = if forced_median || self.method == SplitMethod::Median {
            let leaf_size = if forced_median {
                BVH_MAX_LEAF_SIZE
            } else {
                MEDIAN_LEAF_SIZE
            };
            if m <= leaf_size {
                return leaf;
            }
            self.split_median(begin, end, &cbounds)
        } else {
            match self.split_sah(begin, end, &bounds, &cbounds) {
                Some(mid) => mid,
                None if m <= BVH_MAX_LEAF_SIZE => return leaf,
                None => self.split_median(begin, end, &cbounds),
            }
        };
        let slot = self.nodes.len();
        self.nodes.push(BvhNode::default());
        let l = self.build(begin, mid, depth + 1);
        let r = self.build(mid, end, depth + 1);
        self.nodes[slot] = make_node(&l, &r);
        ChildRef {
            bounds,
            index: slot as u32,
            count: 0,
        }
    }

    /// Binned SAH (Wald 2007): the split position, or `None` if no plane separates
    /// the centroids or (for at most `BVH_MAX_LEAF_SIZE` primitives) a leaf is cheaper.
    fn split_sah(&mut self, begin: usize, end: usize, bounds: &Aabb, cb: &Aabb) -> Option<usize> {
        let m = end - begin;
        let extent = cb.max - cb.min;
        // Bin index k = floor((c - cmin) * K / extent), clamped: the largest centroid
        // lands in the last bin. An axis with zero (or overflowing) extent is skipped.
        let scale = Vec3::select(
            extent.cmpgt(Vec3::ZERO),
            Vec3::splat(SAH_BINS as f32) / extent,
            Vec3::ZERO,
        );
        let bin_of = |c: f32, axis: usize| -> usize {
            (((c - cb.min[axis]) * scale[axis]) as usize).min(SAH_BINS - 1)
        };
        let empty = Bin {
            bounds: Aabb::EMPTY,
            count: 0,
        };
        let mut bins = [[empty; SAH_BINS]; 3];
        for &i in &self.order[begin..end] {
            let c = self.centroids[i as usize];
            let b = &self.bounds[i as usize];
            for (axis, axis_bins) in bins.iter_mut().enumerate() {
                let bin = &mut axis_bins[bin_of(c[axis], axis)];
                bin.count += 1;
                bin.bounds.grow(b);
            }
        }
        // Sweep each axis right to left for the right-side areas, then left to right
        // evaluating the plane after each bin: cost ~ A_L n_L + A_R n_R.
        let mut best = (f64::INFINITY, 0usize, 0usize);
        for (axis, axis_bins) in bins.iter().enumerate() {
            if scale[axis] == 0.0 {
                continue;
            }
            let mut right_cost = [0.0f64; SAH_BINS];
            let mut acc = Aabb::EMPTY;
            let mut n = 0u32;
            for k in (1..SAH_BINS).rev() {
                acc.grow(&axis_bins[k].bounds);
                n += axis_bins[k].count;
                right_cost[k] = acc.area() * n as f64;
            }
            let mut acc = Aabb::EMPTY;
            let mut n = 0u32;
            for k in 1..SAH_BINS {
                acc.grow(&axis_bins[k - 1].bounds);
                n += axis_bins[k - 1].count;
                if n == 0 || n as usize == m {
                    continue;
                }
                let cost = acc.area() * n as f64 + right_cost[k];
                if cost < best.0 {
                    best = (cost, axis, k);
                }
            }
        }
        let (cost, axis, plane) = best;
        if !cost.is_finite() {
            return None;
        }
        let area = bounds.area();
        let split_cost = SAH_TRAVERSAL_COST * area + SAH_INTERSECTION_COST * cost;
        let leaf_cost = SAH_INTERSECTION_COST * m as f64 * area;
        if m <= BVH_MAX_LEAF_SIZE && leaf_cost <= split_cost {
            return None;
        }
        // Partition order[begin..end] so bins < plane come first.
        let (mut lo, mut hi) = (begin, end);
        while lo < hi {
            let c = self.centroids[self.order[lo] as usize][axis];
            if bin_of(c, axis) < plane {
                lo += 1;
            } else {
                hi -= 1;
                self.order.swap(lo, hi);
            }
        }
        debug_assert!(lo > begin && lo < end);
        Some(lo)
    }

    /// Object median along the longest centroid axis; the middle of the index range
    /// if all centroids coincide.
    fn split_median(&mut self, begin: usize, end: usize, cb: &Aabb) -> usize {
        let mid = begin + (end - begin) / 2;
        let extent = cb.max - cb.min;
        if extent.max_element() > 0.0 {
            let axis = extent.max_position();
            let centroids = &self.centroids;
            self.order[begin..end].select_nth_unstable_by(mid - begin, |&a, &b| {
                centroids[a as usize][axis].total_cmp(&centroids[b as usize][axis])
            });
        }
        mid
    }
}

impl Bvh {
    /// Builds a binned-SAH BVH over `prims`, reordering them into leaf order.
    ///
    /// Every leaf ends at depth `<= BVH_STACK_SIZE` and holds at most
    /// [`BVH_MAX_LEAF_SIZE`] primitives; fewer than `2^28` primitives are supported
    /// (the packed stack entries; a 128 MiB binding holds 2.8 M anyway). Inputs must be
    /// NaN-free; degenerate and coincident primitives are fine.
    pub fn build(prims: Vec<Prim>) -> Bvh {
        Bvh::build_with(prims, SplitMethod::Sah)
    }

    /// [`Bvh::build`] with a choice of split method.
    pub fn build_with(prims: Vec<Prim>, method: SplitMethod) -> Bvh {
        let start = Instant::now();
        let n = prims.len();
        assert!(
            n < 1 << (32 - BVH_COUNT_BITS),
            "BVH over {n} primitives: at most 2^28 supported"
        );
        let bounds: Vec<Aabb> = prims.iter().map(prim_bounds).collect();
        // Box centers, not vertex means: 0.5 min + 0.5 max cannot overflow.
        let centroids = bounds
            .iter()
            .map(|b| 0.5 * b.min + 0.5 * b.max)
            .collect();
        let mut builder = Builder {
            bounds,
            centroids,
            order: (0..n as u32).collect(),
            nodes: Vec::with_capacity(n / 2 + 1),
            method,
        };
        if n == 0 {
            builder
                .nodes
                .push(make_node(&ChildRef::EMPTY, &ChildRef::EMPTY));
        } else {
            let root = builder.build(0, n, 0);
            if root.count > 0 {
                // A single leaf: the root must still be an inner node.
                builder.nodes.push(make_node(&root, &ChildRef::EMPTY));
            }
        }
        let prims = builder.order.iter().map(|&i| prims[i as usize]).collect();
        let mut bvh = Bvh {
            nodes: builder.nodes,
            prims,
            stats: BvhStats::default(),
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
        let boxes = |n: &BvhNode| {
            let l = Aabb {
                min: n.left_min.into(),
                max: n.left_max.into(),
            };
            let r = Aabb {
                min: n.right_min.into(),
                max: n.right_max.into(),
            };
            (l, r)
        };
        let (l, r) = boxes(&self.nodes[0]);
        let mut root = l;
        root.grow(&r);
        let root_area = root.area();
        let rel = |a: f64| if root_area > 0.0 { a / root_area } else { 1.0 };
        let mut todo = vec![(0u32, 0usize, root)];
        while let Some((index, depth, bounds)) = todo.pop() {
            s.sah_cost += SAH_TRAVERSAL_COST * rel(bounds.area());
            let n = &self.nodes[index as usize];
            let (l, r) = boxes(n);
            for (b, index, count) in [(l, n.left_index, n.left_count), (r, n.right_index, n.right_count)] {
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
                for i in index..index + count {
                    let p = &self.prims[i as usize];
                    let p0 = Vec3::from(p.p0);
                    let found = if p.kind == PRIM_SPHERE {
                        sphere::intersect(o, d, p0, p.p1[0], tmin, t_hit).map(|t| (t, 0.0, 0.0))
                    } else {
                        let (p1, p2) = (Vec3::from(p.p1), Vec3::from(p.p2));
                        triangle::intersect(&tr, o, p0, p1, p2, tmin, t_hit).map(|h| (h.t, h.u, h.v))
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

/// The closest hit by testing every primitive in order, for tests. Same intersection
/// routines as the traversal; of hits at equal `t`, the lowest index.
pub fn brute_force_closest(prims: &[Prim], o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> Option<Hit> {
    let tr = triangle::TriangleRay::new(d);
    let mut hit = None;
    let mut t_hit = tmax;
    for (i, p) in prims.iter().enumerate() {
        let p0 = Vec3::from(p.p0);
        let found = if p.kind == PRIM_SPHERE {
            sphere::intersect(o, d, p0, p.p1[0], tmin, t_hit).map(|t| (t, 0.0, 0.0))
        } else {
            let (p1, p2) = (Vec3::from(p.p1), Vec3::from(p.p2));
            triangle::intersect(&tr, o, p0, p1, p2, tmin, t_hit).map(|h| (h.t, h.u, h.v))
        };
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
