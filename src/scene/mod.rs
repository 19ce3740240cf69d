//! The scene description: what a scene file says, resolved to world space.
//!
//! Plain Rust that knows nothing of Vulkan; everything here is tested without a GPU.
//! Both scene dialects (Mitsuba 3 and Nori XML) load into the same [`Scene`].

pub mod bsdf;
pub mod camera;
pub mod emitter;
pub mod error;
pub mod integrator;
pub mod shape;

pub use bsdf::Bsdf;
pub use camera::Camera;
pub use emitter::Emitter;
pub use error::Error;
pub use integrator::IntegratorSpec;
pub use shape::{Mesh, Sphere};

use std::path::PathBuf;

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
