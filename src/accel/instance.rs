//! The two-level tree of a scene with shape groups and instances (Mitsuba 3's
//! `shapegroup` / `instance`, [`crate::scene::shape::instance`]).
//!
//! One [`Bvh`] holds it all, as the kernels read it (`shaders/accel/bvh.glsl`,
//! `shaders/accel/instance.glsl`):
//! - node 0 is the root of the top-level tree, over the scene's own primitives and one
//!   [`PRIM_INSTANCE`] record per instance: built over its world box, then rewritten
//!   as its world-to-object map's 3×3 rows (`p0`, `p1`, `p2`), the root node of its
//!   group's tree (`shape`) and the instance number (`index`); its box lives in the
//!   top-level nodes only (the CPU traversal recomputes it, [`instance_world_box`]);
//! - after its nodes and primitives, each group's bottom-level tree, built once and
//!   shared by every instance of the group, its node and leaf indices shifted to where
//!   it lies;
//! - after every primitive ([`TwoLevel::slots`]), the instances' translations, one
//!   16-byte texel each (instance k's is texel `3 slots + k` of the primitives; its
//!   fourth word the position of the instance's top-level record, for shading), so
//!   that an instance costs its top-level record (48 bytes), its translation (16) and
//!   its share of the top-level nodes (about 51 bytes): 115 bytes each for 10,000
//!   instances (three 48-byte records, 195 bytes, before). The kernels recompute what
//!   they need of object to world (its 3×3 by inversion, its translation `-A⁻¹ b`,
//!   the mirror by the sign of det A).
//!
//! A traversal that meets an instance moves the ray into the group's space (an affine
//! map keeps the ray parameter t), walks the group's tree, and moves back. A hit in an
//! instance is named `(instance + 1) << shift | primitive`; primitives outside groups
//! keep their index (below `1 << shift`). Primitive records keep the shape of the
//! group's shape (its BSDF, media, flags) and its global triangle number (its vertex
//! data), so a hit shades as the group's shape, in world space by the instance's map.
//!
//! Scenes without groups get [`Bvh::for_shapes`] unchanged, and kernels specialized
//! without instances (`SCENE_INSTANCES` = 0) compile every line of this away.

use std::time::Instant;

use glam::{DMat4, Mat4, Vec3, Vec4};

use super::bvh::{Bvh, BVH_MAX_PRIMS, BVH_STACK_SIZE};
use crate::gpu::layout::{BvhNode, Prim, PRIM_INSTANCE};
use crate::scene::Scene;

/// Translations (16-byte texels) per 48-byte record after every primitive.
pub const TRANSLATIONS_PER_RECORD: u32 = 3;

/// What the kernels of a scene with instances specialize on, and what `info` reports.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TwoLevel {
    /// Instances in the top-level tree (those of empty groups are left out).
    pub instances: u32,
    /// Hit names: `(instance + 1) << shift | primitive`.
    pub shift: u32,
    /// Index of the first record after the primitives: instance k's translation is
    /// texel `3 slots + k`.
    pub slots: u32,
    /// Entries the traversal stack needs: the top-level tree's deepest leaf, the
    /// bottom-level trees' deepest, and two for the way back (bvh.glsl).
    pub stack_depth: u32,
    /// Nodes and primitives of the top-level tree (the instances' share).
    pub top_nodes: u32,
    pub top_prims: u32,
}

impl TwoLevel {
    /// The specialization constants `SCENE_INSTANCES` (the shift; 0 without
    /// instances) and `SCENE_INSTANCE_SLOTS`.
    pub fn constants(two_level: Option<&TwoLevel>) -> [u32; 2] {
        two_level.map_or([0, 0], |t| [t.shift, t.slots])
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
        // The box for the build; the record is rewritten below.
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
    let mut nodes = tlas.nodes;
    let mut prims = tlas.prims;
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
    let to_object: Vec<Mat4> = placed
        .iter()
        .map(|(_, m)| {
            DMat4::from_cols_array(&m.to_cols_array().map(f64::from))
                .inverse()
                .as_mat4()
        })
        .collect();
    for p in prims[..top_prims as usize].iter_mut() {
        if p.kind == PRIM_INSTANCE {
            let k = p.index as usize;
            let row = |r: usize| to_object[k].row(r).truncate().to_array();
            *p = Prim {
                p0: row(0),
                shape: roots[placed[k].0 as usize],
                p1: row(1),
                index: k as u32,
                p2: row(2),
                kind: PRIM_INSTANCE,
            };
        }
    }
    // Hit names must stay below HIT_NONE, and tree references in 28 bits.
    let slots = prims.len() as u32;
    let shift = (32 - slots.leading_zeros()).max(1);
    let instances = placed.len() as u64;
    if (instances + 1) << shift >= 1 << 32 {
        return Err(format!(
            "{instances} instances over {slots} primitives: more than 32-bit hit names hold \
             (instances + 1) x 2^{shift} must stay below 2^32"
        ));
    }
    let total = prims.len() + placed.len().div_ceil(TRANSLATIONS_PER_RECORD as usize);
    if total > BVH_MAX_PRIMS || nodes.len() > BVH_MAX_PRIMS {
        return Err(format!(
            "{total} primitive records and {} nodes: at most {BVH_MAX_PRIMS} each",
            nodes.len()
        ));
    }
    let mut position = vec![0u32; placed.len()];
    for (i, p) in prims[..top_prims as usize].iter().enumerate() {
        if p.kind == PRIM_INSTANCE {
            position[p.index as usize] = i as u32;
        }
    }
    push_translations(&mut prims, &to_object, &position);
    let stack_depth = tlas.stats.max_depth.max(1) + 2 + blas_depth;
    let two_level = TwoLevel {
        instances: placed.len() as u32,
        shift,
        slots,
        stack_depth: stack_depth.max(1) as u32,
        top_nodes,
        top_prims,
    };
    let mut stats = tlas.stats;
    stats.node_count = nodes.len();
    stats.max_depth = stats.max_depth.max(blas_depth).min(BVH_STACK_SIZE);
    stats.build_seconds = start.elapsed().as_secs_f64();
    Ok(Bvh {
        nodes,
        prims,
        apart: 0,
        stats,
        two_level: Some(two_level),
    })
}

/// The translations of the instances' world-to-object maps (`b` of `A p + b`), one
/// texel each, its fourth word the position of the instance's top-level record;
/// three to a record.
fn push_translations(prims: &mut Vec<Prim>, to_object: &[Mat4], position: &[u32]) {
    let n = TRANSLATIONS_PER_RECORD as usize;
    for (c, chunk) in to_object.chunks(n).enumerate() {
        let mut words = [0u32; 12];
        for (j, m) in chunk.iter().enumerate() {
            for (a, w) in m.w_axis.truncate().to_array().iter().enumerate() {
                words[4 * j + a] = w.to_bits();
            }
            words[4 * j + 3] = position[c * n + j];
        }
        let f = |i: usize| [0, 1, 2].map(|a| f32::from_bits(words[i + a]));
        prims.push(Prim {
            p0: f(0),
            shape: words[3],
            p1: f(4),
            index: words[7],
            p2: f(8),
            kind: words[11],
        });
    }
}

/// The top-level record of instance `k` in `bvh` and its position, as shading finds
/// it (the fourth word of its translation's texel).
fn instance_record(bvh: &Bvh, k: u32) -> (usize, &Prim) {
    let t = bvh.two_level.expect("a two-level tree");
    let texel = 3 * t.slots as usize + k as usize;
    let words: [u32; 12] = bytemuck::cast(bvh.prims[texel / 3]);
    let i = words[4 * (texel % 3) + 3] as usize;
    (i, &bvh.prims[i])
}

/// The world-to-object rows (3×4) of the instance whose top-level record is `p`, as
/// the kernels read them.
pub fn record_rows(bvh: &Bvh, p: &Prim) -> [Vec4; 3] {
    let t = bvh.two_level.expect("a two-level tree");
    let texel = 3 * t.slots as usize + p.index as usize;
    let rec = &bvh.prims[texel / 3];
    let words: [u32; 12] = bytemuck::cast(*rec);
    let b = [0, 1, 2].map(|a| f32::from_bits(words[4 * (texel % 3) + a]));
    [
        Vec3::from(p.p0).extend(b[0]),
        Vec3::from(p.p1).extend(b[1]),
        Vec3::from(p.p2).extend(b[2]),
    ]
}

/// Instance `k`'s world-to-object rows (3×4) from the records of `bvh`, as the kernels
/// read them (for tests).
pub fn to_object_rows(bvh: &Bvh, k: u32) -> [Vec4; 3] {
    record_rows(bvh, instance_record(bvh, k).1)
}

/// The world box of the instance whose top-level record is `p` (which holds its map
/// and its group's root, not its box): the group tree's root box under the inverse of
/// the record's map, as the build's box was made. The CPU traversal's instance test.
pub fn instance_world_box(bvh: &Bvh, p: &Prim) -> (Vec3, Vec3) {
    let r = record_rows(bvh, p);
    let to_object = Mat4::from_cols(r[0], r[1], r[2], Vec4::W).transpose();
    let to_world = DMat4::from_cols_array(&to_object.to_cols_array().map(f64::from))
        .inverse()
        .as_mat4();
    let n = &bvh.nodes[p.shape as usize];
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

    #[test]
    fn layout_of_the_two_levels() {
        let s = scene(5);
        let bvh = scene_bvh(&s).expect("bvh");
        let t = bvh.two_level.expect("two levels");
        assert_eq!(t.instances, 5);
        // The cube's 12 triangles and 5 instances on top, the group's 4 triangles
        // once below, and the 5 translations, three to a record.
        assert_eq!(t.top_prims, 17);
        assert_eq!(t.slots, 21);
        assert_eq!(bvh.prims.len(), 21 + 2);
        assert_eq!(t.shift, 5);
        let tops = &bvh.prims[..t.top_prims as usize];
        assert_eq!(tops.iter().filter(|p| p.kind == PRIM_INSTANCE).count(), 5);
        for (k, inst) in s.instances.iter().enumerate() {
            let (_, p) = instance_record(&bvh, k as u32);
            // Every instance's root is the group's, a node after the top level.
            assert_eq!(p.shape, t.top_nodes);
            // Its world box, recomputed, holds the group's shapes under its map.
            let (lo, hi) = instance_world_box(&bvh, p);
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
        let mut below: Vec<(u32, u32)> = bvh.prims[17..21]
            .iter()
            .map(|p| (p.shape, p.index))
            .collect();
        below.sort();
        assert_eq!(below, [(1, 12), (1, 13), (2, 14), (2, 15)]);
        for (k, inst) in s.instances.iter().enumerate() {
            let rows = to_object_rows(&bvh, k as u32);
            let p = Vec3::new(0.3, -0.2, 0.9);
            let w = inst.to_world.transform_point3(p).extend(1.0);
            let back = Vec3::new(rows[0].dot(w), rows[1].dot(w), rows[2].dot(w));
            assert!((back - p).length() < 1e-5, "{back} != {p}");
        }
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
                let r = to_object_rows(&bvh, k as u32);
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
        for (k, inst) in s.instances.iter().enumerate() {
            let (i, p) = instance_record(&bvh, k as u32);
            assert!(i < t.top_prims as usize && p.kind == PRIM_INSTANCE);
            let rows = to_object_rows(&bvh, k as u32);
            let w = inst.to_world.transform_point3(Vec3::ONE).extend(1.0);
            let back = Vec3::new(rows[0].dot(w), rows[1].dot(w), rows[2].dot(w));
            assert!((back - Vec3::ONE).length() < 1e-5, "{back}");
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
