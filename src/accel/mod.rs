//! Acceleration structures: the BVH built on the host and flattened for the kernels.
//!
//! [`prims_from_scene`] turns a [`Scene`] into [`Prim`]s, [`Bvh::build`] sorts them
//! into a binned-SAH tree of [`BvhNode`](crate::gpu::layout::BvhNode)s
//! ([`bvh_build`]; [`Bvh::for_shapes`] builds a scene's without the copy), and
//! [`Bvh::closest`] / [`Bvh::any`] traverse it on the CPU exactly as
//! `shaders/accel/bvh.glsl` does on the GPU. [`triangle`], [`sphere`], [`disk`] and
//! [`cylinder`] hold the intersection routines, mirrored by `intersect_*.glsl`.

pub mod bspline;
pub mod bvh;
pub mod bvh_build;
pub mod curve;
pub mod cylinder;
pub mod disk;
pub mod instance;
pub mod sphere;
pub mod triangle;

pub use bvh::{
    brute_force_closest, Bvh, BvhStats, FlatPrims, Hit, SplitMethod, APART_QUADRICS_MAX,
    BVH_MAX_LEAF_SIZE, BVH_MAX_PRIMS, BVH_STACK_SIZE, FLAT_CAPACITY, FLAT_ONLY, FLAT_PRIMS_MAX,
    FLAT_PRIMS_MAX_WIDE, FLAT_STEPS, FLAT_VERTEX_CONSTANTS,
};

use bvh_build::PrimSource;

use crate::gpu::layout::{
    Prim, PRIM_CYLINDER, PRIM_DISK, PRIM_LINEAR_CURVE, PRIM_SDFGRID, PRIM_SPHERE, PRIM_TRIANGLE,
};
use crate::scene::{Mesh, Quadric, QuadricKind, Scene};

/// Every primitive of `scene`, in shape order: each triangle of each mesh, then each
/// quadric.
///
/// Shape numbering, which the renderer relies on: shape `i` is `scene.meshes[i]` for
/// `i < meshes.len()`, then the quadrics in order. A triangle's `index` is its global
/// triangle number (a running count over the meshes in order), a quadric's its
/// position in `scene.quadrics`. Mesh indices must be in range (the scene loader
/// checks).
pub fn prims_from_scene(scene: &Scene) -> Vec<Prim> {
    prims_from_shapes(&scene.meshes, &scene.quadrics)
}

/// The primitive of quadric number `index`, shape `shape` (layout in [`Prim`]).
pub fn quadric_prim(q: &Quadric, shape: u32, index: u32) -> Prim {
    if let QuadricKind::SdfGrid(place) = q.kind {
        let (lo, hi) = q.bounds();
        return Prim {
            p0: lo.to_array(),
            shape,
            p1: hi.to_array(),
            index,
            p2: [f32::from_bits(place.offset), 0.0, 0.0],
            kind: PRIM_SDFGRID,
        };
    }
    let m = q.to_world;
    let col = |k: usize| m.col(k).truncate().to_array();
    let (kind, p2) = match q.kind {
        QuadricKind::Sphere => (PRIM_SPHERE, col(1)),
        QuadricKind::Disk => (PRIM_DISK, col(1)),
        QuadricKind::Cylinder => (PRIM_CYLINDER, col(2)),
        QuadricKind::SdfGrid(_) => unreachable!("handled above"),
    };
    Prim {
        p0: col(3),
        shape,
        p1: col(0),
        index,
        p2,
        kind,
    }
}

/// [`prims_from_scene`] over the shape lists alone.
pub fn prims_from_shapes(meshes: &[Mesh], quadrics: &[Quadric]) -> Vec<Prim> {
    let source = bvh_build::ShapePrims::new(meshes, quadrics);
    (0..source.len()).map(|i| source.prim(i)).collect()
}

/// Triangle `k` of `mesh`, shape `shape`, global triangle number `index`; segment `k`
/// of curves ([`curve_prim`]).
pub fn triangle_prim(mesh: &Mesh, k: usize, shape: u32, index: u32) -> Prim {
    if mesh.is_ellipsoids() {
        return ellipsoid_prim(mesh, k, shape);
    }
    if mesh.is_bspline() {
        return bspline_prim(mesh, k, shape);
    }
    if mesh.is_curves() {
        return curve_prim(mesh, k, shape);
    }
    let p = mesh.indices[k].map(|v| mesh.positions[v as usize].to_array());
    Prim {
        p0: p[0],
        shape,
        p1: p[1],
        index,
        p2: p[2],
        kind: PRIM_TRIANGLE,
    }
}

/// Ellipsoid `k` of the `ellipsoids` shape `mesh`, shape `shape` (layout in
/// [`crate::gpu::layout::PRIM_ELLIPSOID`]).
pub fn ellipsoid_prim(mesh: &Mesh, k: usize, shape: u32) -> Prim {
    let (lo, hi) = mesh.ellipsoids[k].bounds();
    Prim {
        p0: lo.to_array(),
        shape,
        p1: hi.to_array(),
        index: k as u32,
        p2: [f32::from_bits(mesh.indices[k][2]), 0.0, 0.0],
        kind: crate::gpu::layout::PRIM_ELLIPSOID,
    }
}

/// Segment `k` of the B-spline curves `mesh`, shape `shape` (layout in
/// [`crate::gpu::layout::PRIM_BSPLINE_CURVE`]).
pub fn bspline_prim(mesh: &Mesh, k: usize, shape: u32) -> Prim {
    let (lo, hi) = crate::scene::shape::bsplinecurve::segment_box(mesh, k);
    Prim {
        p0: lo.to_array(),
        shape,
        p1: hi.to_array(),
        index: k as u32,
        p2: [
            f32::from_bits(mesh.indices[k][2]),
            mesh.indices.len() as f32,
            0.0,
        ],
        kind: crate::gpu::layout::PRIM_BSPLINE_CURVE,
    }
}

/// Segment `k` of the curves `mesh`, shape `shape` (layout in
/// [`PRIM_LINEAR_CURVE`]).
pub fn curve_prim(mesh: &Mesh, k: usize, shape: u32) -> Prim {
    let i = mesh.indices[k][0] as usize;
    // A curve's first segment: no segment ends at its start.
    let first = k == 0 || mesh.indices[k - 1][0] as usize + 1 != i;
    let n = mesh.indices.len() as f32;
    Prim {
        p0: mesh.positions[i].to_array(),
        shape,
        p1: mesh.positions[i + 1].to_array(),
        index: k as u32,
        p2: [mesh.radii[i], mesh.radii[i + 1], if first { -n } else { n }],
        kind: PRIM_LINEAR_CURVE,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn shapes_number_meshes_then_spheres() {
        let quad = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::ONE, Vec3::Y],
            indices: vec![[0, 1, 2], [0, 2, 3]],
            ..Mesh::default()
        };
        let tri = Mesh {
            positions: vec![Vec3::Z, Vec3::X, Vec3::Y],
            indices: vec![[2, 1, 0]],
            ..Mesh::default()
        };
        let ball = |x: f32| Quadric::sphere(Vec3::new(x, 0.0, 0.0), 0.5, 0);
        let prims = prims_from_shapes(&[quad, tri], &[ball(3.0), ball(5.0)]);
        let key: Vec<(u32, u32, u32)> = prims.iter().map(|p| (p.kind, p.shape, p.index)).collect();
        assert_eq!(
            key,
            [
                (PRIM_TRIANGLE, 0, 0),
                (PRIM_TRIANGLE, 0, 1),
                (PRIM_TRIANGLE, 1, 2),
                (PRIM_SPHERE, 2, 0),
                (PRIM_SPHERE, 3, 1)
            ]
        );
        assert_eq!(prims[1].p2, [0.0, 1.0, 0.0]);
        assert_eq!(prims[2].p0, [0.0, 1.0, 0.0]);
        assert_eq!(prims[4].p0, [5.0, 0.0, 0.0]);
        assert_eq!(prims[4].p1, [0.5, 0.0, 0.0]);
        assert_eq!(prims[4].p2, [0.0, 0.5, 0.0]);
    }
}
