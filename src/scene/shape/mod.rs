//! Shapes: triangle meshes and analytic quadrics (sphere, disk, cylinder), in world
//! space; the shape family, one file per plugin type (Mitsuba 3's `src/shapes/`),
//! and [`REGISTRY`], every shape type of both dialects. The mesh file formats are
//! read by [`crate::scene::obj`], [`crate::scene::ply`] and
//! [`crate::scene::serialized`]; the dialects' tree walkers attach BSDFs, emitters and
//! media and bring the shape to world space ([`crate::scene::builder`]).

pub mod bsplinecurve;
pub mod cube;
pub mod cylinder;
pub mod disk;
pub mod ellipsoids;
pub mod ellipsoidsmesh;
pub mod instance;
pub mod linearcurve;
pub mod merge;
pub mod obj;
pub mod ply;
pub mod provided;
pub mod rectangle;
pub mod sdfgrid;
pub mod serialized;
pub mod sphere;

use glam::{Mat3, Mat4, Vec2, Vec3};

use super::plugin::{self, Family, Param, PluginDoc};
use super::properties::Properties;
use super::xml::{Dialect, Element};
use super::Error;

/// Every shape type of both dialects: the supported ones with the parameters they
/// read, then the Mitsuba 3 types not supported yet.
pub const REGISTRY: &[PluginDoc] = &[
    obj::MITSUBA,
    ply::MITSUBA,
    serialized::MITSUBA,
    rectangle::MITSUBA,
    cube::MITSUBA,
    sphere::MITSUBA,
    disk::MITSUBA,
    cylinder::MITSUBA,
    linearcurve::MITSUBA,
    instance::SHAPEGROUP,
    instance::INSTANCE,
    bsplinecurve::MITSUBA,
    sdfgrid::MITSUBA,
    ellipsoids::MITSUBA,
    ellipsoidsmesh::MITSUBA,
    merge::MITSUBA,
    obj::NORI,
];

#[allow(dead_code)] // for Mitsuba shape types not supported yet (none today)
const fn not_yet(name: &'static str) -> PluginDoc {
    PluginDoc::not_yet(Family::Shape, Dialect::Mitsuba, name)
}

/// `to_world` of every Mitsuba shape.
pub const TO_WORLD: Param = Param::new(
    "to_world",
    "transform",
    "identity",
    "object to world (mirrors included)",
);
/// `flip_normals` of every Mitsuba shape.
pub const FLIP_NORMALS: Param = Param::new(
    "flip_normals",
    "boolean",
    "false",
    "turn the geometric and shading normals around",
);
/// `face_normals` of every Mitsuba mesh.
pub const FACE_NORMALS: Param = Param::new(
    "face_normals",
    "boolean",
    "false",
    "flat shading: drop the vertex normals",
);

/// What a Mitsuba shape type makes of its parameters.
pub enum Geometry {
    /// A unit quadric and its object-to-world map.
    Quadric(QuadricKind, Mat4),
    /// A mesh in object space, its `to_world` and whether its vertex normals are
    /// dropped (`face_normals`).
    Mesh {
        mesh: Mesh,
        to_world: Mat4,
        face_normals: bool,
    },
    /// A signed-distance grid on the unit cube and its object-to-world map.
    SdfGrid(Box<sdfgrid::SdfGrid>, Mat4),
    /// Curves ([`Mesh::radii`]) in object space and their `to_world`, which moves the
    /// control points and leaves the radii.
    Curves { mesh: Mesh, to_world: Mat4 },
}

/// Reads a Mitsuba shape of type `t`'s own parameters (not `flip_normals`, nor the
/// nested BSDF, emitter and media) and loads its geometry: the registry's dispatch.
pub fn mitsuba(t: &str, el: &Element, props: &Properties) -> Result<Geometry, Error> {
    match t {
        "sphere" => return sphere::mitsuba(props),
        "disk" => return disk::mitsuba(props),
        "cylinder" => return cylinder::mitsuba(props),
        "sdfgrid" => return sdfgrid::mitsuba(el, props),
        "linearcurve" => return linearcurve::mitsuba(el, props),
        "bsplinecurve" => return bsplinecurve::mitsuba(el, props),
        "ellipsoids" => return ellipsoids::mitsuba(el, props),
        "ellipsoidsmesh" => return ellipsoidsmesh::mitsuba(el, props),
        provided::TYPE if provided::active() => return provided::mitsuba(el, props),
        _ => {}
    }
    let to_world = props.transform("to_world")?;
    // Mitsuba's mesh base class reads face_normals for every mesh; the built-in
    // cube and rectangle keep their vertex normals whatever it says.
    let face_normals = props.boolean("face_normals", false)?;
    let (mesh, builtin) = match t {
        "obj" => (obj::mitsuba(el, props)?, false),
        "ply" => (ply::mitsuba(el, props)?, false),
        "serialized" => (serialized::mitsuba(el, props)?, false),
        "rectangle" => (rectangle::mesh(), true),
        "cube" => (cube::mesh(), true),
        _ => return Err(unsupported(el, Dialect::Mitsuba)),
    };
    Ok(Geometry::Mesh {
        mesh,
        to_world,
        face_normals: face_normals && !builtin,
    })
}

/// "shape type 'X' is not supported yet" or "unknown shape type 'X'" (`mesh` in Nori).
pub fn unsupported(el: &Element, dialect: Dialect) -> Error {
    plugin::unsupported(el, Family::Shape, dialect, REGISTRY)
}

/// A triangle mesh in world space.
///
/// Mitsuba: `obj`, `ply`, `serialized`, `rectangle`, `cube`; Nori: `mesh type="obj"`.
/// `to_world` is already applied (normals by the inverse transpose, renormalized), as
/// Mitsuba does at load time; the winding is the file's (or Mitsuba's table's), so a
/// mirroring `to_world` turns the geometric normal around while the vertex normals
/// keep facing where they did. Zero-area triangles are dropped at load.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// A name for messages: the file it came from, or the shape type.
    pub name: String,
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals: empty, or one per position.
    pub normals: Vec<Vec3>,
    /// Per-vertex texture coordinates: empty, or one per position.
    pub uvs: Vec<Vec2>,
    /// Triangles as indices into `positions` (and `normals`, `uvs`).
    pub indices: Vec<[u32; 3]>,
    /// Mitsuba's `flip_normals`: the geometric and shading normals are negated at
    /// every hit (the winding and the stored normals stay as they are, as in Mitsuba,
    /// so the tangent frame ∂p/∂u is unchanged).
    pub flip_normals: bool,
    /// Index into `Scene::bsdfs`.
    pub bsdf: u32,
    /// Index into `Scene::emitters` of the area emitter this mesh carries.
    pub emitter: Option<u32>,
    /// Media inside and outside (indices into `Scene::media`; Mitsuba `interior`,
    /// `exterior`): a ray leaving the surface against its normal enters `interior`.
    pub interior: Option<u32>,
    pub exterior: Option<u32>,
    /// A `null` BSDF: the surface only bounds media; rays pass straight through.
    pub null_bsdf: bool,
    /// Named per-vertex and per-triangle values (PLY properties) that
    /// `mesh_attribute` textures read.
    pub attributes: Vec<crate::scene::texture::mesh_attribute::MeshAttribute>,
    /// Per position, the radius of a curve shape ([`linearcurve`]): non-empty makes
    /// the mesh a set of curves, each entry of `indices` a segment `[its first control
    /// point, 0, 0]` from that point to the next, in the file's order.
    pub radii: Vec<f32>,
    /// The ellipsoids of an `ellipsoids` shape ([`ellipsoids`]), in world space: then
    /// `positions` are their centres, `radii` their largest semi-axes and `indices`
    /// `[number, ellipsoids::MARKER, grid-buffer offset]`.
    pub ellipsoids: Vec<ellipsoids::Ellipsoid>,
}

/// The least cosine between a vertex normal and its triangle's face normal for
/// [`Mesh::normals_agree`].
pub const NORMALS_AGREE_COS: f32 = 1e-3;

impl Mesh {
    /// Whether this is a set of curves ([`Mesh::radii`]), not triangles.
    pub fn is_curves(&self) -> bool {
        !self.radii.is_empty()
    }

    /// Whether the mesh has vertex normals and each of them lies on its triangles' side
    /// of the face normal, their cosine above [`NORMALS_AGREE_COS`]: every interpolated
    /// shading normal then lies there too (a convex combination), and the renderer,
    /// which turns the geometric normal to the shading normal's side as Mitsuba does,
    /// never turns it (shaders/shape/surface.glsl). The margin keeps that true through
    /// the kernels' rounding; degenerate triangles and zero normals do not agree.
    pub fn normals_agree(&self) -> bool {
        !self.normals.is_empty()
            && self.indices.iter().all(|t| {
                let p = t.map(|i| self.positions.get(i as usize).copied().unwrap_or_default());
                let ng = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
                t.iter().all(|&i| {
                    let n = self.normals.get(i as usize).copied().unwrap_or_default();
                    ng.dot(n.normalize_or_zero()) > NORMALS_AGREE_COS
                })
            })
    }

    /// Whether these curves are cubic B-splines ([`bsplinecurve`]): their segments
    /// are `[first control point, 3, grid-buffer offset of that point]`.
    pub fn is_bspline(&self) -> bool {
        self.is_curves() && self.indices.first().is_some_and(|s| s[1] == 3)
    }

    /// Whether this is an `ellipsoids` shape ([`Mesh::ellipsoids`]).
    pub fn is_ellipsoids(&self) -> bool {
        !self.ellipsoids.is_empty()
    }
}

/// Which unit shape a [`Quadric`] maps to world space.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum QuadricKind {
    /// The unit sphere. Mitsuba `sphere` (`center`, `radius`): uv = (φ/2π, θ/π) of the
    /// object-space point, ∂p/∂u = 2π (−y, x, 0), outward normals.
    Sphere,
    /// The unit disk in z = 0. Mitsuba `disk`: uv = (r, φ/2π), ∂p/∂u = (cos φ, sin φ, 0),
    /// normal +z (by the inverse transpose of `to_world`).
    Disk,
    /// The unit cylinder x² + y² = 1, 0 ≤ z ≤ 1, without caps. Mitsuba `cylinder`
    /// (`p0`, `p1`, `radius`): uv = (φ/2π, z), ∂p/∂u = 2π (−y, x, 0), outward normals.
    Cylinder,
    /// Mitsuba `sdfgrid`: the zero set of a grid of distances on the unit cube
    /// ([`sdfgrid`]): where its words are in the grid buffer and the box of its
    /// occupied voxels. No uvs, no area.
    SdfGrid(sdfgrid::SdfPlace),
}

/// An analytic shape: a unit [`QuadricKind`] in object space, `to_world` (which for a
/// sphere already holds `center` and `radius`, for a cylinder `p0`, `p1` and `radius`,
/// as Mitsuba composes them), intersected exactly on the GPU.
///
/// Spheres take rotations, uniform scales and translations (and mirrors); cylinders
/// also a scale along their axis; disks any affine map (an ellipse). Mitsuba's rules
/// for the side normals face ([`Quadric::normals_flipped`]) are kept, mirroring
/// included.
#[derive(Debug, Clone, PartialEq)]
pub struct Quadric {
    pub kind: QuadricKind,
    /// Object space to world space.
    pub to_world: Mat4,
    /// Mitsuba's `flip_normals` as the scene gives it.
    pub flip_normals: bool,
    /// Index into `Scene::bsdfs`.
    pub bsdf: u32,
    /// Index into `Scene::emitters` of the area emitter this shape carries.
    pub emitter: Option<u32>,
    /// As [`Mesh::interior`], [`Mesh::exterior`], [`Mesh::null_bsdf`].
    pub interior: Option<u32>,
    pub exterior: Option<u32>,
    pub null_bsdf: bool,
}

impl Quadric {
    /// A sphere of `radius` around `center` (world space), unrotated.
    pub fn sphere(center: Vec3, radius: f32, bsdf: u32) -> Quadric {
        Quadric {
            kind: QuadricKind::Sphere,
            to_world: Mat4::from_translation(center) * Mat4::from_scale(Vec3::splat(radius)),
            flip_normals: false,
            bsdf,
            emitter: None,
            interior: None,
            exterior: None,
            null_bsdf: false,
        }
    }

    /// The linear part of `to_world`.
    pub fn linear(&self) -> Mat3 {
        Mat3::from_mat4(self.to_world)
    }

    /// The object-space origin in world space: a sphere's centre, a disk's centre, the
    /// start of a cylinder's axis.
    pub fn origin(&self) -> Vec3 {
        self.to_world.w_axis.truncate()
    }

    /// The world-space radius: the length of the image of the object x axis.
    pub fn radius(&self) -> f32 {
        self.to_world.x_axis.truncate().length()
    }

    /// Whether `to_world` mirrors (negative determinant).
    pub fn mirrored(&self) -> bool {
        self.linear().determinant() < 0.0
    }

    /// Whether the normals a hit reports point the other way than the object-space
    /// outward normal would give. Mitsuba 3.9: a sphere and a disk flip with
    /// `flip_normals` xor a mirroring `to_world` (a mirrored sphere faces inwards; a
    /// disk's normal, the inverse transpose of +z, turns with the mirror, and this
    /// turns it back); a cylinder's ∂p/∂u × ∂p/∂v turns with the mirror too, so only
    /// `flip_normals` counts.
    pub fn normals_flipped(&self) -> bool {
        match self.kind {
            QuadricKind::Sphere | QuadricKind::Disk => self.flip_normals ^ self.mirrored(),
            QuadricKind::Cylinder => self.flip_normals,
            // Mitsuba's sdfgrid maps its gradient by the inverse transpose and reads no
            // flip_normals.
            QuadricKind::SdfGrid(_) => false,
        }
    }

    /// A world-space box holding the shape (lower and upper corner): the image of the
    /// unit shape's own box ([-1, 1]² by [-1, 1] for a sphere, 0 for a disk, [0, 1]
    /// for a cylinder) under `to_world`, tight for axis-aligned shapes.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let (z0, z1) = match self.kind {
            QuadricKind::Sphere => (-1.0, 1.0),
            QuadricKind::Disk => (0.0, 0.0),
            QuadricKind::Cylinder => (0.0, 1.0),
            QuadricKind::SdfGrid(place) => return place.bounds(&self.to_world),
        };
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for c in 0..8 {
            let pick = |bit: u32, a: f32, b: f32| if c & bit == 0 { a } else { b };
            let corner = Vec3::new(pick(1, -1.0, 1.0), pick(2, -1.0, 1.0), pick(4, z0, z1));
            let p = self.to_world.transform_point3(corner);
            lo = lo.min(p);
            hi = hi.max(p);
        }
        (lo, hi)
    }

    /// World-space surface area.
    pub fn area(&self) -> f32 {
        let m = self.linear();
        let r = self.radius();
        match self.kind {
            QuadricKind::Sphere => 4.0 * std::f32::consts::PI * r * r,
            QuadricKind::Disk => std::f32::consts::PI * m.x_axis.cross(m.y_axis).length(),
            QuadricKind::Cylinder => 2.0 * std::f32::consts::PI * r * m.z_axis.length(),
            // None, as in Mitsuba (an sdfgrid carries no emitter).
            QuadricKind::SdfGrid(_) => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit quad in the z = 0 plane (face normal +z) with `normals`.
    fn quad(normals: Vec<Vec3>) -> Mesh {
        Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            indices: vec![[0, 1, 2], [0, 2, 3]],
            normals,
            ..Default::default()
        }
    }

    #[test]
    fn normals_agree_only_where_each_lies_on_its_face_side() {
        let up = Vec3::Z;
        assert!(quad(vec![up; 4]).normals_agree());
        // Tilted, but on the face's side.
        let tilted = Vec3::new(0.9, 0.0, 0.1);
        assert!(quad(vec![up, tilted, up, up]).normals_agree());
        // One vertex normal in the plane or below it: a shading normal may turn the
        // geometric one there.
        assert!(!quad(vec![up, Vec3::X, up, up]).normals_agree());
        assert!(!quad(vec![up, up, up, -up]).normals_agree());
        // Inwards everywhere (the renderer turns every geometric normal): no.
        assert!(!quad(vec![-up; 4]).normals_agree());
        // No normals, a zero normal, a degenerate triangle.
        assert!(!quad(Vec::new()).normals_agree());
        assert!(!quad(vec![up, Vec3::ZERO, up, up]).normals_agree());
        let mut flat = quad(vec![up; 4]);
        flat.positions[2] = Vec3::new(2.0, 0.0, 0.0);
        assert!(!flat.normals_agree());
    }

    #[test]
    fn quadric_bounds_hold_the_shape() {
        let s = Quadric::sphere(Vec3::new(1.0, 2.0, 3.0), 2.0, 0);
        assert_eq!(
            s.bounds(),
            (Vec3::new(-1.0, 0.0, 1.0), Vec3::new(3.0, 4.0, 5.0))
        );
        // A cylinder of radius 0.5 from (0, 0, 1) along +x, length 4.
        let c = Quadric {
            kind: QuadricKind::Cylinder,
            to_world: Mat4::from_translation(Vec3::Z)
                * Mat4::from_rotation_y(std::f32::consts::FRAC_PI_2)
                * Mat4::from_scale(Vec3::new(0.5, 0.5, 4.0)),
            ..s.clone()
        };
        let (lo, hi) = c.bounds();
        let want = (Vec3::new(0.0, -0.5, 0.5), Vec3::new(4.0, 0.5, 1.5));
        assert!(
            lo.abs_diff_eq(want.0, 1e-5) && hi.abs_diff_eq(want.1, 1e-5),
            "{lo} {hi}"
        );
        // A disk has no thickness along its normal.
        let d = Quadric {
            kind: QuadricKind::Disk,
            to_world: Mat4::IDENTITY,
            ..s
        };
        assert_eq!(
            d.bounds(),
            (Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0))
        );
    }
}
