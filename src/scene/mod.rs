//! The scene description: what a scene file says, resolved to world space.
//!
//! Plain Rust that knows nothing of Vulkan; everything here is tested without a GPU.
//! Both scene dialects (Mitsuba 3 and Nori XML) load into the same [`Scene`].

pub mod bsdf;
mod builder;
pub mod camera;
pub mod emitter;
pub mod error;
pub mod integrator;
pub mod mesh;
mod mitsuba;
mod nori;
mod obj;
mod ply;
pub mod properties;
pub mod shape;
pub mod spectrum;
pub mod transform;
pub mod xml;

pub use bsdf::Bsdf;
pub use camera::Camera;
pub use emitter::Emitter;
pub use error::Error;
pub use integrator::IntegratorSpec;
pub use shape::{Mesh, Sphere};

use std::path::{Path, PathBuf};

/// A loaded scene, every shape in world space.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The file it was read from (relative paths inside it resolve against its folder).
    pub path: PathBuf,
    pub camera: Camera,
    /// Samples per pixel the scene asks for (Mitsuba `sample_count`, Nori `sampleCount`).
    pub spp: u32,
    /// The integrator the scene names, with its parameters still unread.
    pub integrator: IntegratorSpec,
    pub meshes: Vec<Mesh>,
    pub spheres: Vec<Sphere>,
    /// Every BSDF, indexed by `Mesh::bsdf` / `Sphere::bsdf`.
    pub bsdfs: Vec<Bsdf>,
    /// Every emitter; area emitters are referenced by the shape that carries them.
    pub emitters: Vec<Emitter>,
}

impl Scene {
    /// Total number of triangles over all meshes.
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.indices.len()).sum()
    }
}

/// Loads a scene file, Mitsuba 3 or Nori (told apart by the root `<scene>`: Mitsuba's
/// carries `version="3.x.y"`). `defines` are `-D name=value` overrides of Mitsuba
/// `<default>` parameters. Every problem is an [`Error`] naming the file and, where
/// there is one, the line; nothing a user wrote makes this panic.
pub fn load(path: &Path, defines: &[(String, String)]) -> Result<Scene, Error> {
    let doc = xml::read(path, defines)?;
    match doc.dialect {
        xml::Dialect::Mitsuba => mitsuba::load(&doc),
        xml::Dialect::Nori => nori::load(&doc),
    }
}
