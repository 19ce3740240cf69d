//! Shapes: triangle meshes and analytic spheres, in world space.

use glam::{Vec2, Vec3};

/// A triangle mesh in world space.
///
/// Mitsuba: `obj`, `ply`, `rectangle`, `cube`, `disk` (disk is tessellated); Nori:
/// `mesh type="obj"`. `to_world` is already applied; normals are transformed by the
/// inverse transpose and renormalized. The disk is a 256-gon; `flip_normals` reverses
/// the winding and negates normals; zero-area triangles are dropped at load.
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
}

/// An analytic sphere in world space (Mitsuba `sphere`: `center`, `radius`, `to_world`
/// with uniform scale; Nori has no sphere shape).
#[derive(Debug, Clone, PartialEq)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
    /// Index into `Scene::bsdfs`.
    pub bsdf: u32,
    /// Index into `Scene::emitters` of the area emitter this sphere carries.
    pub emitter: Option<u32>,
    /// Mitsuba's `flip_normals`: normals point inwards.
    pub flip_normals: bool,
    /// As [`Mesh::interior`], [`Mesh::exterior`], [`Mesh::null_bsdf`].
    pub interior: Option<u32>,
    pub exterior: Option<u32>,
    pub null_bsdf: bool,
}
