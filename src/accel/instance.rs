//! The two-level tree of a scene with shape groups and instances (Mitsuba 3's
//! `shapegroup` / `instance`, [`crate::scene::shape::instance`]).
//!
//! One [`Bvh`] holds it all, as the kernels read it (`shaders/accel/bvh.glsl`,
//! `shaders/accel/instance.glsl`):
//! - node 0 is the root of the top-level tree, over the scene's own primitives and the
//!   instances. Its leaves hold either primitives (indices below [`TwoLevel::slots`])
//!   or instances: a leaf `(slots + k, count)` names instance records `k .. k + count`
//!   directly, with no record of its own in between. A subtree of at most
//!   [`INSTANCE_LEAF_SIZE`] instances (and nothing else) is one leaf: a ray that enters
//!   its box tries each of them (an instance's world box is not stored: its group's
//!   root box, met in the instance's space, culls it), so the top level has a node for
//!   about every five instances instead of one for each;
//! - after its nodes and primitives, each group's bottom-level tree, built once and
//!   shared by every instance of the group, its node and leaf indices shifted to where
//!   it lies;
//! - after every primitive, the instance records, in top-level leaf order, each
//!   [`TwoLevel::texels`] 16-byte texels from texel `3 slots`: where every instance's
//!   map is a similarity (a turn, a uniform scale, a mirror, a move: a forest, a crowd),
//!   two texels ([`COMPACT_TEXELS`]): its world-to-object 3×3 as a quaternion whose
//!   squared norm is the scale (the mirror in the sign bit of w), then its translation
//!   and its group's root node; else four ([`GENERAL_TEXELS`]): the 3×4 rows, then the
//!   root. The quaternion is used only where the 3×3 the kernels rebuild from it
//!   ([`compact_rows`]) lies within [`COMPACT_TOLERANCE`] of the exact inverse, so
//!   images change by float rounding alone.
//!
//! An instance then costs its record (32 or 64 bytes) and its share of the top-level
//! nodes (64 bytes a node): 10,000 instances of a similarity (tools/make_instances.py),
//! 1,824 top-level nodes, about 44 bytes an instance (115 before: a 48-byte top-level
//! record with the 3×3, a 16-byte translation, a node for every 1.25 instances). The
//! kernels recompute what they need of object to world (its 3×3 by inversion, its
//! translation `-A⁻¹ b`, the mirror by the sign of det A).
//!
//! A traversal that meets an instance leaf takes its instances in turn: the ray moves
//! into the group's space (an affine map keeps the ray parameter t) and meets the
//! group's root box there or goes on to the next, with no stack traffic; into the
//! first it meets, it walks the group's tree, moves back, and goes on with the rest of
//! the leaf. A hit in an instance is named `(k + 1) << shift | primitive`, k its
//! record's position; primitives outside groups keep their index (below
//! `1 << shift`). Primitive records keep the shape of the group's shape (its BSDF,
//! media, flags) and its global triangle number (its vertex data), so a hit shades as
//! the group's shape, in world space by the instance's map.
//!
//! Scenes without groups get [`Bvh::for_shapes`] unchanged, and kernels specialized
//! without instances (`SCENE_INSTANCES` = 0) compile every line of this away.

use std::time::Instant;

use glam::{DMat4, Mat4, Vec3, Vec4};

use super::bvh::{prim_bounds, Bvh, BVH_MAX_PRIMS, BVH_STACK_SIZE};
use crate::gpu::layout::{BvhNode, Prim, PRIM_INSTANCE};
use crate::scene::Scene;

/// Texels of an instance record where every instance's map is a similarity: the
/// quaternion, then the translation and the group's root.
pub const COMPACT_TEXELS: u32 = 2;

/// Texels of an instance record otherwise: the 3×4 world-to-object rows, then the
/// group's root.
pub const GENERAL_TEXELS: u32 = 4;

/// The most instances one top-level leaf holds (a subtree of instances alone with at
/// most this many becomes a leaf). 1 would keep the binned-SAH tree's leaves.
pub const INSTANCE_LEAF_SIZE: u32 = 8;

/// How far (in units of the scale's float epsilon) an element of the 3×3 the kernels
/// rebuild from a quaternion may lie from the exact world-to-object map's for the
/// compact records: a few roundings, as the f32 matrix itself has.
pub const COMPACT_TOLERANCE: f64 = 8.0;

/// Bit of `SCENE_INSTANCES` that says the instance records are compact (below it: the
/// shift of the hit names, at most 31).
pub const COMPACT_BIT: u32 = 32;

/// What the kernels of a scene with instances specialize on, and what `info` reports.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TwoLevel {
    /// Instances in the top-level tree (those of empty groups are left out).
    pub instances: u32,
    /// Hit names: `(instance + 1) << shift | primitive`.
    pub shift: u32,
    /// Index of the first record after the primitives: instance record k starts at
    /// texel `3 slots + texels k`; a top-level leaf `(slots + k, count)` holds
    /// instances `k .. k + count`.
    pub slots: u32,
    /// Texels (16 bytes) of an instance record: [`COMPACT_TEXELS`] or
    /// [`GENERAL_TEXELS`].
    pub texels: u32,
    /// Entries the traversal stack needs: the top-level tree's deepest leaf, the
    /// bottom-level trees' deepest, and two for the way back (bvh.glsl).
    pub stack_depth: u32,
    /// Nodes of the top-level tree, and the scene's own primitives in it.
    pub top_nodes: u32,
    pub top_prims: u32,
}

impl TwoLevel {
    /// The specialization constants `SCENE_INSTANCES` (the shift, plus
    /// [`COMPACT_BIT`] for compact records; 0 without instances) and
    /// `SCENE_INSTANCE_SLOTS`.
    pub fn constants(two_level: Option<&TwoLevel>) -> [u32; 2] {
        two_level.map_or([0, 0], |t| {
            let compact = if t.texels == COMPACT_TEXELS {
                COMPACT_BIT
            } else {
                0
            };
            [t.shift | compact, t.slots]
        })
    }

    /// Bytes of device memory an instance record takes.
    pub fn record_bytes(&self) -> u32 {
        16 * self.texels
    }
}

/// The primitives of shape `s` (meshes, then quadrics), numbered as
/// [`super::prims_from_shapes`] numbers them.
struct ShapeIndex {
    /// Global number of each mesh's first triangle, then the total.
    first: Vec<u32>,
}

impl ShapeIndex {
    fn new(scene: &Scene) -> ShapeIndex {
        let mut first = Vec::with_capacity(scene.meshes.len() + 1);
        let mut n = 0u32;
        for m in &scene.meshes {
            first.push(n);
            n += m.indices.len() as u32;
        }
        first.push(n);
        ShapeIndex { first }
    }

    fn mesh_prims<'s>(&self, scene: &'s Scene, m: usize) -> impl Iterator<Item = Prim> + 's {
        let mesh = &scene.meshes[m];
        let first = self.first[m];
        (0..mesh.indices.len())
            .map(move |k| super::triangle_prim(mesh, k, m as u32, first + k as u32))
    }

    fn quadric_prim(&self, scene: &Scene, q: usize) -> Prim {
        super::quadric_prim(
            &scene.quadrics[q],
            (scene.meshes.len() + q) as u32,
            q as u32,
        )
    }
}

/// The box of `b` mapped by `m` (its eight corners).
fn transformed_box(m: &Mat4, (lo, hi): (Vec3, Vec3)) -> (Vec3, Vec3) {
    let mut out = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for c in 0..8 {
        let p = Vec3::new(
            if c & 1 == 0 { lo.x } else { hi.x },
            if c & 2 == 0 { lo.y } else { hi.y },
            if c & 4 == 0 { lo.z } else { hi.z },
        );
        let w = m.transform_point3(p);
        out = (out.0.min(w), out.1.max(w));
    }
    // Widen by the rounding of the map (a few ulps of the largest coordinate), so a
    // ray that meets the group's box in its space enters this one.
    let slack = 8.0 * f32::EPSILON * (out.0.abs().max(out.1.abs()));
    (out.0 - slack, out.1 + slack)
}

/// The world-to-object 3×3 the kernels rebuild from a compact record's quaternion
/// (x, y, z, w; w's sign bit: the map mirrors), its squared norm the scale: as
/// `instance_to_object` in instance.glsl computes it, operation for operation.
pub fn compact_rows(q: [f32; 4]) -> [Vec3; 3] {
    let [x, y, z, w] = q;
    let mirror = w.is_sign_negative();
    let w = w.abs();
    let (xx, yy, zz, ww) = (x * x, y * y, z * z, w * w);
    let (xy, xz, yz) = (x * y, x * z, y * z);
    let (wx, wy, wz) = (w * x, w * y, w * z);
    let rows = [
        Vec3::new(ww + xx - yy - zz, 2.0 * (xy - wz), 2.0 * (xz + wy)),
        Vec3::new(2.0 * (xy + wz), ww - xx + yy - zz, 2.0 * (yz - wx)),
        Vec3::new(2.0 * (xz - wy), 2.0 * (yz + wx), ww - xx - yy + zz),
    ];
    if mirror {
        rows.map(|r| -r)
    } else {
        rows
    }
}

/// The compact quaternion of the world-to-object 3×3 `a` (rows, exact), if the rows
/// the kernels rebuild from it ([`compact_rows`]) lie within [`COMPACT_TOLERANCE`]
/// epsilons of the scale of `a`: `a` is a similarity, `± n R` with R a rotation.
fn compact_quaternion(a: [[f64; 3]; 3]) -> Option<[f32; 4]> {
    let det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    if !(det.is_finite() && det != 0.0) {
        return None;
    }
    let sign = det.signum();
    let n = det.abs().cbrt();
    let m = a.map(|r| r.map(|v| sign * v / n)); // a rotation if `a` is a similarity
                                                // Shepperd's method: the largest of w, x, y, z from the diagonal first.
    let tr = m[0][0] + m[1][1] + m[2][2];
    let q = if tr > 0.0 {
        let s = 2.0 * (tr + 1.0).sqrt();
        [
            (m[2][1] - m[1][2]) / s,
            (m[0][2] - m[2][0]) / s,
            (m[1][0] - m[0][1]) / s,
            s / 4.0,
        ]
    } else if m[0][0] > m[1][1] && m[0][0] > m[2][2] {
        let s = 2.0 * (1.0 + m[0][0] - m[1][1] - m[2][2]).sqrt();
        [
            s / 4.0,
            (m[0][1] + m[1][0]) / s,
            (m[0][2] + m[2][0]) / s,
            (m[2][1] - m[1][2]) / s,
        ]
    } else if m[1][1] > m[2][2] {
        let s = 2.0 * (1.0 + m[1][1] - m[0][0] - m[2][2]).sqrt();
        [
            (m[0][1] + m[1][0]) / s,
            s / 4.0,
            (m[1][2] + m[2][1]) / s,
            (m[0][2] - m[2][0]) / s,
        ]
    } else {
        let s = 2.0 * (1.0 + m[2][2] - m[0][0] - m[1][1]).sqrt();
        [
            (m[0][2] + m[2][0]) / s,
            (m[1][2] + m[2][1]) / s,
            s / 4.0,
            (m[1][0] - m[0][1]) / s,
        ]
    };
    let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    let flip = if q[3] < 0.0 { -1.0 } else { 1.0 };
    let mut out = q.map(|v| (flip * v / norm * n.sqrt()) as f32);
    if sign < 0.0 {
        out[3] = -out[3].abs(); // the sign bit, even of w = 0
        if out[3] == 0.0 {
            out[3] = -0.0;
        }
    }
    let rows = compact_rows(out);
    let limit = COMPACT_TOLERANCE * f64::from(f32::EPSILON) * n;
    let close = (0..3).all(|r| (0..3).all(|c| (f64::from(rows[r][c]) - a[r][c]).abs() <= limit));
    close.then_some(out)
}

/// The top-level tree as the kernels read it, made from the binned-SAH tree over the
/// scene's own primitives and one box record per instance ([`PRIM_INSTANCE`], `index`
/// its number in `placed`): leaves hold primitives or instances, never both (a leaf
/// with both becomes a node over two leaves), and a subtree of at most
/// [`INSTANCE_LEAF_SIZE`] instances becomes one leaf.
struct TopLevel<'a> {
    old_nodes: &'a [BvhNode],
    old_prims: &'a [Prim],
    /// Instances under each old node.
    census: Vec<(u32, bool)>,
    nodes: Vec<BvhNode>,
    /// The scene's own primitives, in leaf order.
    own: Vec<Prim>,
    /// Instances (numbers into `placed`) in record order.
    order: Vec<u32>,
    slots: u32,
    max_depth: usize,
    leaves: usize,
    largest_leaf: usize,
}

impl TopLevel<'_> {
    /// The top level of `tlas` (over `own` primitives, then instances), rewritten.
    fn of(tlas: &Bvh, own: usize, slots: u32) -> TopLevel<'_> {
        let mut top = TopLevel {
            old_nodes: &tlas.nodes,
            old_prims: &tlas.prims,
            census: vec![(0, false); tlas.nodes.len()],
            nodes: Vec::with_capacity(tlas.nodes.len()),
            own: Vec::with_capacity(own),
            order: Vec::with_capacity(tlas.prims.len() - own),
            slots,
            max_depth: 0,
            leaves: 0,
            largest_leaf: 0,
        };
        top.count(0);
        top.node(0, 0);
        top
    }

    /// Instances under old node `i`, and whether anything else is: filled in `census`.
    fn count(&mut self, i: u32) -> (u32, bool) {
        let n = self.old_nodes[i as usize];
        let mut out = (0u32, false);
        for (index, count, empty) in [
            (n.left_index, n.left_count, n.left_min[0] > n.left_max[0]),
            (
                n.right_index,
                n.right_count,
                n.right_min[0] > n.right_max[0],
            ),
        ] {
            if empty {
                continue;
            }
            let (k, other) = if count == 0 {
                self.count(index)
            } else {
                let prims = &self.old_prims[index as usize..(index + count) as usize];
                let k = prims.iter().filter(|p| p.kind == PRIM_INSTANCE).count() as u32;
                (k, (k as usize) < prims.len())
            };
            out = (out.0 + k, out.1 || other);
        }
        self.census[i as usize] = out;
        out
    }

    /// The instances under the old child `(index, count)`, in depth-first order.
    fn gather(&self, index: u32, count: u32, out: &mut Vec<u32>) {
        if count > 0 {
            let prims = &self.old_prims[index as usize..(index + count) as usize];
            out.extend(
                prims
                    .iter()
                    .filter(|p| p.kind == PRIM_INSTANCE)
                    .map(|p| p.index),
            );
            return;
        }
        let n = &self.old_nodes[index as usize];
        for (index, count, empty) in [
            (n.left_index, n.left_count, n.left_min[0] > n.left_max[0]),
            (
                n.right_index,
                n.right_count,
                n.right_min[0] > n.right_max[0],
            ),
        ] {
            if !empty {
                self.gather(index, count, out);
            }
        }
    }

    fn leaf(&mut self, depth: usize, count: usize) {
        self.leaves += 1;
        self.max_depth = self.max_depth.max(depth);
        self.largest_leaf = self.largest_leaf.max(count);
    }

    /// A leaf of instances `found` (numbers into `placed`): its `(index, count)`.
    fn instance_leaf(&mut self, found: &[u32], depth: usize) -> (u32, u32) {
        let first = self.order.len() as u32;
        self.order.extend_from_slice(found);
        self.leaf(depth, found.len());
        (self.slots + first, found.len() as u32)
    }

    /// The new child for old child `(index, count)` at `depth` (its box unchanged).
    fn child(&mut self, index: u32, count: u32, depth: usize) -> (u32, u32) {
        if count > 0 {
            let prims = &self.old_prims[index as usize..(index + count) as usize];
            let (inst, own): (Vec<Prim>, Vec<Prim>) =
                prims.iter().partition(|p| p.kind == PRIM_INSTANCE);
            let found: Vec<u32> = inst.iter().map(|p| p.index).collect();
            if own.is_empty() {
                return self.instance_leaf(&found, depth);
            }
            let first = self.own.len() as u32;
            self.own.extend_from_slice(&own);
            if found.is_empty() {
                self.leaf(depth, own.len());
                return (first, own.len() as u32);
            }
            // Both: a node over a leaf of each.
            let bounds = |ps: &[Prim]| {
                ps.iter()
                    .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
                        let b = prim_bounds(p);
                        (lo.min(b.min), hi.max(b.max))
                    })
            };
            let ((own_lo, own_hi), (inst_lo, inst_hi)) = (bounds(&own), bounds(&inst));
            self.leaf(depth + 1, own.len());
            let (k, c) = self.instance_leaf(&found, depth + 1);
            self.nodes.push(BvhNode {
                left_min: own_lo.to_array(),
                left_index: first,
                left_max: own_hi.to_array(),
                left_count: own.len() as u32,
                right_min: inst_lo.to_array(),
                right_index: k,
                right_max: inst_hi.to_array(),
                right_count: c,
            });
            return (self.nodes.len() as u32 - 1, 0);
        }
        let (k, other) = self.census[index as usize];
        if !other && k <= INSTANCE_LEAF_SIZE {
            let mut found = Vec::new();
            self.gather(index, 0, &mut found);
            return self.instance_leaf(&found, depth);
        }
        (self.node(index, depth), 0)
    }

    /// Old inner node `i` at `depth`, rewritten: its new index.
    fn node(&mut self, i: u32, depth: usize) -> u32 {
        let n = self.old_nodes[i as usize];
        let at = self.nodes.len();
        self.nodes.push(n);
        let mut out = n;
        if n.left_min[0] <= n.left_max[0] {
            (out.left_index, out.left_count) = self.child(n.left_index, n.left_count, depth + 1);
        }
        if n.right_min[0] <= n.right_max[0] {
            (out.right_index, out.right_count) =
                self.child(n.right_index, n.right_count, depth + 1);
        }
        self.nodes[at] = out;
        at as u32
    }
}

/// The tree `scene` is traced with: [`Bvh::for_shapes`] without shape groups, else
/// the two-level tree of the module doc. Err: the scene's instances and primitives do
/// not fit the 32-bit hit names or the packed tree references.
pub fn scene_bvh(scene: &Scene) -> Result<Bvh, String> {
    if scene.groups.is_empty() {
        return Ok(Bvh::for_shapes(&scene.meshes, &scene.quadrics));
    }
    let start = Instant::now();
    let index = ShapeIndex::new(scene);
    let grouped = scene.grouped_shapes();
    let mut used = vec![false; scene.groups.len()];
    for i in &scene.instances {
        used[i.group as usize] = true;
    }
    // The groups' trees, over their shapes as the group's space holds them.
    let blas: Vec<Option<Bvh>> = scene
        .groups
        .iter()
        .zip(&used)
        .map(|(g, &used)| {
            let mut prims: Vec<Prim> = Vec::new();
            for &m in &g.meshes {
                prims.extend(index.mesh_prims(scene, m as usize));
            }
            for &q in &g.quadrics {
                prims.push(index.quadric_prim(scene, q as usize));
            }
            (used && !prims.is_empty()).then(|| Bvh::build_whole(&prims[..]))
        })
        .collect();
    // The top-level primitives: the shapes outside groups, then the instances.
    let mut top: Vec<Prim> = Vec::new();
    for (m, _) in scene.meshes.iter().enumerate() {
        if !grouped[m] {
            top.extend(index.mesh_prims(scene, m));
        }
    }
    for q in 0..scene.quadrics.len() {
        if !grouped[scene.meshes.len() + q] {
            top.push(index.quadric_prim(scene, q));
        }
    }
    let own_count = top.len();
    // Instances in the top-level tree, numbered in scene order: (group, to_world).
    let mut placed: Vec<(u32, Mat4)> = Vec::new();
    for inst in &scene.instances {
        let Some(tree) = &blas[inst.group as usize] else {
            continue; // an empty group: nothing to see
        };
        let Some(bounds) = tree.bounds() else {
            continue;
        };
        let (lo, hi) = transformed_box(&inst.to_world, bounds);
        // Its box, for the build; its leaf names its record (TopLevel).
        top.push(Prim {
            p0: lo.to_array(),
            shape: 0,
            p1: hi.to_array(),
            index: placed.len() as u32,
            p2: [0.0; 3],
            kind: PRIM_INSTANCE,
        });
        placed.push((inst.group, inst.to_world));
    }
    let tlas = Bvh::build_whole(&top[..]);
    // The groups' trees go after the scene's own primitives: records from `slots`.
    let group_prims: usize = blas.iter().flatten().map(|t| t.prims.len()).sum();
    let slots = (own_count + group_prims) as u32;
    let top_level = TopLevel::of(&tlas, own_count, slots);
    let TopLevel {
        mut nodes,
        own: mut prims,
        order,
        max_depth,
        leaves,
        largest_leaf,
        ..
    } = top_level;
    let (top_nodes, top_prims) = (nodes.len() as u32, prims.len() as u32);
    // Each group's tree after the top level, its references shifted.
    let mut roots = vec![0u32; scene.groups.len()];
    let mut blas_depth = 0;
    for (g, tree) in blas.iter().enumerate() {
        let Some(tree) = tree else { continue };
        let (node_base, prim_base) = (nodes.len() as u32, prims.len() as u32);
        roots[g] = node_base;
        blas_depth = blas_depth.max(tree.stats.max_depth);
        let shift = |index: u32, count: u32| {
            if count == 0 {
                index + node_base
            } else {
                index + prim_base
            }
        };
        nodes.extend(tree.nodes.iter().map(|n| BvhNode {
            left_index: shift(n.left_index, n.left_count),
            right_index: shift(n.right_index, n.right_count),
            ..*n
        }));
        prims.extend_from_slice(&tree.prims);
    }
    debug_assert_eq!(prims.len(), slots as usize);
    // Hit names must stay below HIT_NONE, and tree references in 28 bits.
    let shift = (32 - slots.leading_zeros()).max(1);
    let instances = placed.len() as u64;
    if (instances + 1) << shift >= 1 << 32 {
        return Err(format!(
            "{instances} instances over {slots} primitives: more than 32-bit hit names hold \
             (instances + 1) x 2^{shift} must stay below 2^32"
        ));
    }
    // The instance records, in leaf order.
    let maps: Vec<(Mat4, u32)> = order
        .iter()
        .map(|&k| {
            let (group, to_world) = placed[k as usize];
            (to_world, roots[group as usize])
        })
        .collect();
    let (texels, words) = instance_records(&maps);
    let total = prims.len() + words.len() / 12;
    if total > BVH_MAX_PRIMS || nodes.len() > BVH_MAX_PRIMS {
        return Err(format!(
            "{total} primitive records and {} nodes: at most {BVH_MAX_PRIMS} each",
            nodes.len()
        ));
    }
    prims.extend(words.chunks(12).map(|c| {
        let w: [u32; 12] = c.try_into().expect("12 words");
        bytemuck::cast::<[u32; 12], Prim>(w)
    }));
    let stack_depth = max_depth.max(1) + 2 + blas_depth;
    let two_level = TwoLevel {
        instances: placed.len() as u32,
        shift,
        slots,
        texels,
        stack_depth: stack_depth.max(1) as u32,
        top_nodes,
        top_prims,
    };
    let mut stats = tlas.stats;
    stats.node_count = nodes.len();
    stats.leaf_count = leaves;
    stats.max_leaf_size = largest_leaf;
    stats.max_depth = max_depth.max(blas_depth).min(BVH_STACK_SIZE);
    stats.build_seconds = start.elapsed().as_secs_f64();
    Ok(Bvh {
        nodes,
        prims,
        apart: 0,
        stats,
        two_level: Some(two_level),
    })
}

/// The records of instances `(to_world, root of its group's tree)`, in order: their
/// texels ([`COMPACT_TEXELS`] where every map is a similarity, else
/// [`GENERAL_TEXELS`]) and their words, padded to whole primitive records (12 words).
fn instance_records(maps: &[(Mat4, u32)]) -> (u32, Vec<u32>) {
    // The world-to-object maps, exact, then rounded.
    let to_object: Vec<DMat4> = maps
        .iter()
        .map(|(m, _)| DMat4::from_cols_array(&m.to_cols_array().map(f64::from)).inverse())
        .collect();
    let compact: Option<Vec<[f32; 4]>> = to_object
        .iter()
        .map(|m| compact_quaternion([0, 1, 2].map(|r| m.row(r).truncate().to_array())))
        .collect();
    let texels = if compact.is_some() {
        COMPACT_TEXELS
    } else {
        GENERAL_TEXELS
    };
    let mut words: Vec<u32> = Vec::with_capacity(maps.len() * 4 * texels as usize + 12);
    for (i, (m, &(_, root))) in to_object.iter().zip(maps).enumerate() {
        let b = m.w_axis.truncate().as_vec3();
        match &compact {
            Some(q) => {
                words.extend(q[i].map(f32::to_bits));
                words.extend(b.to_array().map(f32::to_bits));
                words.push(root);
            }
            None => {
                for r in 0..3 {
                    words.extend(m.row(r).as_vec4().to_array().map(f32::to_bits));
                }
                words.extend([root, 0, 0, 0]);
            }
        }
    }
    words.resize(words.len().div_ceil(12) * 12, 0);
    (texels, words)
}

/// The words of instance record `k` (in leaf order) in `bvh`.
fn record_words(bvh: &Bvh, k: u32) -> Vec<u32> {
    let t = bvh.two_level.expect("a two-level tree");
    let first = 3 * t.slots as usize + (t.texels * k) as usize;
    (first..first + t.texels as usize)
        .flat_map(|texel| {
            let words: [u32; 12] = bytemuck::cast(bvh.prims[texel / 3]);
            let i = 4 * (texel % 3);
            [words[i], words[i + 1], words[i + 2], words[i + 3]]
        })
        .collect()
}

/// Instance record `k`'s world-to-object rows (3×4) and its group's root node, as
/// the kernels read them (`instance_to_object`, `instance_root`).
pub fn record_map(bvh: &Bvh, k: u32) -> ([Vec4; 3], u32) {
    let w = record_words(bvh, k);
    let f = |i: usize| f32::from_bits(w[i]);
    if w.len() == COMPACT_TEXELS as usize * 4 {
        let a = compact_rows([f(0), f(1), f(2), f(3)]);
        let rows = [0, 1, 2].map(|r| a[r].extend(f(4 + r)));
        (rows, w[7])
    } else {
        let rows = [0, 1, 2].map(|r| Vec4::new(f(4 * r), f(4 * r + 1), f(4 * r + 2), f(4 * r + 3)));
        (rows, w[12])
    }
}

/// The world box of instance record `k` (the records hold its map and its group's
/// root, not its box): the group tree's root box under the inverse of the record's
/// map, as the build's box was made. The CPU traversal's instance test.
pub fn instance_world_box(bvh: &Bvh, k: u32) -> (Vec3, Vec3) {
    let (r, root) = record_map(bvh, k);
    let to_object = Mat4::from_cols(r[0], r[1], r[2], Vec4::W).transpose();
    let to_world = DMat4::from_cols_array(&to_object.to_cols_array().map(f64::from))
        .inverse()
        .as_mat4();
    let n = &bvh.nodes[root as usize];
    let lo = Vec3::from(n.left_min).min(Vec3::from(n.right_min));
    let hi = Vec3::from(n.left_max).max(Vec3::from(n.right_max));
    transformed_box(&to_world, (lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::{brute_force_closest, prims_from_shapes};
    use crate::scene::{Instance, Mesh, ShapeGroup};
    use glam::{Quat, Vec4Swizzles};

    /// A scene of `n` instances of a small mesh group, and one mesh of its own.
    fn scene(n: usize) -> Scene {
        let tri = |o: Vec3| Mesh {
            positions: vec![o, o + Vec3::X, o + Vec3::Y, o + Vec3::ONE],
            indices: vec![[0, 1, 2], [1, 3, 2]],
            ..Mesh::default()
        };
        let mut s = crate::scene::testutil::load(
            &[(
                "s.xml",
                &crate::scene::testutil::mitsuba(r#"<shape type="cube"/>"#),
            )],
            &[],
        )
        .expect("scene");
        s.meshes.push(tri(Vec3::ZERO));
        s.meshes.push(tri(Vec3::Z));
        s.groups.push(ShapeGroup {
            name: "g".into(),
            meshes: vec![1, 2],
            quadrics: vec![],
        });
        for k in 0..n {
            let to_world = Mat4::from_scale_rotation_translation(
                Vec3::new(1.0 + k as f32 * 0.1, 0.7, 1.3),
                Quat::from_rotation_y(0.3 * k as f32),
                Vec3::new(3.0 * k as f32, 0.5, -2.0),
            );
            s.instances.push(Instance { group: 0, to_world });
        }
        s
    }

    /// The record (in leaf order) that holds scene instance `inst`'s map: the one
    /// that takes its world points back to the group's.
    fn record_of(bvh: &Bvh, inst: &Instance) -> u32 {
        let t = bvh.two_level.expect("two levels");
        (0..t.instances)
            .find(|&k| {
                let rows = record_map(bvh, k).0;
                [Vec3::ZERO, Vec3::ONE, Vec3::new(0.3, -0.2, 0.9)]
                    .iter()
                    .all(|&p| {
                        let w = inst.to_world.transform_point3(p).extend(1.0);
                        let back = Vec3::new(rows[0].dot(w), rows[1].dot(w), rows[2].dot(w));
                        let size = w.length() * rows[0].truncate().length();
                        (back - p).length() < 1e-5 * (1.0 + size)
                    })
            })
            .expect("a record for every instance")
    }

    #[test]
    fn layout_of_the_two_levels() {
        let s = scene(5);
        let bvh = scene_bvh(&s).expect("bvh");
        let t = bvh.two_level.expect("two levels");
        assert_eq!(t.instances, 5);
        // The cube's 12 triangles on top, the group's 4 triangles once below, and the
        // 5 instance records: the instances scale unevenly, so four texels each.
        assert_eq!(t.top_prims, 12);
        assert_eq!(t.slots, 16);
        assert_eq!(t.texels, GENERAL_TEXELS);
        assert_eq!(bvh.prims.len(), 16 + (5 * 4usize).div_ceil(3));
        assert_eq!(t.shift, 5);
        assert!(bvh.shape_prims().iter().all(|p| p.kind != PRIM_INSTANCE));
        // Top-level leaves name primitives or instance records, never both.
        for n in &bvh.nodes[..t.top_nodes as usize] {
            for (index, count) in [(n.left_index, n.left_count), (n.right_index, n.right_count)] {
                if count > 0 && index >= t.slots {
                    assert!(index + count <= t.slots + t.instances);
                    assert!(count <= INSTANCE_LEAF_SIZE);
                } else if count > 0 {
                    assert!(index + count <= t.top_prims);
                }
            }
        }
        let mut seen = [false; 5];
        for inst in &s.instances {
            let k = record_of(&bvh, inst);
            assert!(!std::mem::replace(&mut seen[k as usize], true));
            // Every instance's root is the group's, a node after the top level.
            assert_eq!(record_map(&bvh, k).1, t.top_nodes);
            // Its world box, recomputed, holds the group's shapes under its map.
            let (lo, hi) = instance_world_box(&bvh, k);
            for q in [
                Vec3::ZERO,
                Vec3::ONE,
                Vec3::new(1.0, 0.0, 1.0),
                Vec3::Z + Vec3::Y,
            ] {
                let w = inst.to_world.transform_point3(q);
                assert!(
                    w.cmpge(lo - 1e-4).all() && w.cmple(hi + 1e-4).all(),
                    "{w} outside {lo} .. {hi}"
                );
            }
        }
        // Grouped shapes keep their shape and global triangle numbers.
        let mut below: Vec<(u32, u32)> = bvh.prims[12..16]
            .iter()
            .map(|p| (p.shape, p.index))
            .collect();
        below.sort();
        assert_eq!(below, [(1, 12), (1, 13), (2, 14), (2, 15)]);
    }

    /// Turns, uniform scales, mirrors and moves: two texels a record, the 3×3 the
    /// kernels rebuild from the quaternion within a few roundings of the exact inverse.
    #[test]
    fn similarities_get_compact_records() {
        let mut s = scene(0);
        let n = 200;
        for k in 0..n {
            let f = k as f32;
            let turn = Quat::from_rotation_y(0.37 * f)
                * Quat::from_rotation_x(0.11 * f - 3.0)
                * Quat::from_rotation_z(if k % 3 == 0 { 0.0 } else { 2.9 - 0.05 * f });
            let scale = (0.2 + 0.013 * f) * if k % 4 == 1 { -1.0 } else { 1.0 };
            let to_world = Mat4::from_scale_rotation_translation(
                Vec3::splat(scale),
                turn,
                Vec3::new(2.5 * (k % 20) as f32, 0.5, 2.5 * (k / 20) as f32 - 300.0),
            );
            s.instances.push(Instance { group: 0, to_world });
        }
        let bvh = scene_bvh(&s).expect("bvh");
        let t = bvh.two_level.expect("two levels");
        assert_eq!(t.texels, COMPACT_TEXELS);
        assert_eq!(t.record_bytes(), 32);
        assert_eq!(TwoLevel::constants(Some(&t))[0], t.shift | COMPACT_BIT);
        let mut seen = vec![false; n];
        for inst in &s.instances {
            let k = record_of(&bvh, inst) as usize;
            assert!(!std::mem::replace(&mut seen[k], true));
            let (rows, root) = record_map(&bvh, k as u32);
            assert_eq!(root, t.top_nodes);
            let exact =
                DMat4::from_cols_array(&inst.to_world.to_cols_array().map(f64::from)).inverse();
            let scale = exact.determinant().abs().cbrt();
            for (r, row) in rows.iter().enumerate() {
                for c in 0..4 {
                    let e = exact.row(r)[c];
                    let bound = if c < 3 {
                        COMPACT_TOLERANCE * f64::from(f32::EPSILON) * scale
                    } else {
                        f64::from(f32::EPSILON) * e.abs() // b: rounded once
                    };
                    let got = f64::from(row[c]);
                    assert!(
                        (got - e).abs() <= bound,
                        "instance {k} [{r}][{c}]: {got} vs {e}"
                    );
                }
            }
            // The mirror survives in w's sign bit (det A < 0).
            let det = rows[0]
                .truncate()
                .dot(rows[1].truncate().cross(rows[2].truncate()));
            assert_eq!(det < 0.0, exact.determinant() < 0.0);
        }
        // One uneven scale and every record is general again.
        s.instances[7].to_world *= Mat4::from_scale(Vec3::new(1.0, 1.001, 1.0));
        let t = scene_bvh(&s).expect("bvh").two_level.expect("two levels");
        assert_eq!(t.texels, GENERAL_TEXELS);
    }

    /// The device memory an instance adds, the top-level nodes' share included: with
    /// compact records about 43 bytes (115 before). Bytes, not time: deterministic.
    #[test]
    fn memory_per_instance() {
        let bytes = |n: usize| {
            let mut s = scene(0);
            for k in 0..n {
                let to_world = Mat4::from_scale_rotation_translation(
                    Vec3::splat(0.6 + 0.0007 * k as f32),
                    Quat::from_rotation_y(0.7 * k as f32),
                    Vec3::new(3.0 * (k % 50) as f32, 0.0, 3.0 * (k / 50) as f32),
                );
                s.instances.push(Instance { group: 0, to_world });
            }
            // Every scene buffer, as `wavetrace info` sums them.
            use crate::render::scene_parts::{array_sizes, scene_arrays};
            let bvh = scene_bvh(&s).expect("bvh");
            let records = crate::render::scene_buffers::SceneRecords::new(&s, &bvh);
            let sizes = array_sizes(&scene_arrays(&bvh, &records));
            sizes.iter().sum::<u64>()
        };
        let n = 2500;
        let per = (bytes(n) - bytes(1)) as f64 / (n - 1) as f64;
        println!("{per:.1} bytes an instance");
        assert!(per <= 46.0, "{per:.1} bytes an instance");
    }

    /// What the kernels compute, on the CPU: the ray in each instance's space against
    /// the group's primitives by brute force, the same t as the flattened triangles.
    #[test]
    fn instances_hit_where_the_flattened_triangles_are() {
        let s = scene(4);
        let bvh = scene_bvh(&s).expect("bvh");
        let t = bvh.two_level.expect("two levels");
        let group: Vec<Prim> = bvh.prims[t.top_prims as usize..t.slots as usize].to_vec();
        let mut flat_meshes = Vec::new();
        for inst in &s.instances {
            for &m in &s.groups[0].meshes {
                let mut mesh = s.meshes[m as usize].clone();
                for p in &mut mesh.positions {
                    *p = inst.to_world.transform_point3(*p);
                }
                flat_meshes.push(mesh);
            }
        }
        let flat = prims_from_shapes(&flat_meshes, &[]);
        let mut hits = 0;
        for i in 0..400 {
            let (a, b) = (i as f32 * 0.618_034, i as f32 * 0.414_213);
            let o = Vec3::new(-5.0, 0.6 + (a % 1.0), -6.0);
            let d = Vec3::new(1.0 + 12.0 * (b % 1.0), 0.0, 5.0).normalize();
            let want = brute_force_closest(&flat, o, d, 0.0, f32::INFINITY);
            let mut got: Option<f32> = None;
            for k in 0..s.instances.len() {
                let r = record_map(&bvh, k as u32).0;
                let (ow, dw) = (o.extend(1.0), d.extend(0.0));
                let oo = Vec3::new(r[0].dot(ow), r[1].dot(ow), r[2].dot(ow));
                let dd = Vec3::new(
                    r[0].xyz().dot(dw.xyz()),
                    r[1].xyz().dot(dw.xyz()),
                    r[2].xyz().dot(dw.xyz()),
                );
                if let Some(h) = brute_force_closest(&group, oo, dd, 0.0, f32::INFINITY) {
                    got = Some(got.map_or(h.t, |g: f32| g.min(h.t)));
                }
            }
            match (want, got) {
                (None, None) => {}
                (Some(w), Some(g)) => {
                    hits += 1;
                    assert!((w.t - g).abs() <= 1e-4 * w.t, "ray {i}: t {} vs {g}", w.t);
                }
                (w, g) => panic!("ray {i}: flattened {w:?}, instanced {g:?}"),
            }
        }
        assert!(hits > 50, "only {hits} rays hit");
    }

    /// Hit names count instances, not top-level records: a scene with many primitives
    /// of its own beside a few instances still fits 32-bit names.
    #[test]
    fn many_own_primitives_and_a_few_instances() {
        let mut s = scene(3);
        let n = 1 << 17; // 131,072 triangles outside the group
        let positions: Vec<Vec3> = (0..n + 2)
            .map(|i| Vec3::new(i as f32 * 0.01, (i % 2) as f32, 5.0))
            .collect();
        let indices = (0..n as u32).map(|i| [i, i + 1, i + 2]).collect();
        s.meshes.push(Mesh {
            positions,
            indices,
            ..Mesh::default()
        });
        let bvh = scene_bvh(&s).expect("fits");
        let t = bvh.two_level.expect("two levels");
        assert!((t.top_prims as u64 + 1) << t.shift >= 1 << 32);
        assert!((t.instances as u64 + 1) << t.shift < 1 << 32);
        for inst in &s.instances {
            let k = record_of(&bvh, inst);
            assert!(k < t.instances);
        }
    }

    #[test]
    fn scenes_without_groups_keep_their_tree() {
        let mut s = scene(0);
        s.groups.clear();
        let bvh = scene_bvh(&s).expect("bvh");
        assert!(bvh.two_level.is_none());
        let plain = Bvh::for_shapes(&s.meshes, &s.quadrics);
        assert_eq!(bvh.nodes, plain.nodes);
        assert_eq!(bvh.prims, plain.prims);
    }
}
