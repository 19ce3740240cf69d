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

/// Helpers for tests that write scene files.
#[cfg(test)]
pub(crate) mod testutil {
    use std::path::{Path, PathBuf};
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// A fresh empty folder under the system temp dir.
    pub fn temp_dir(tag: &str) -> PathBuf {
        static N: AtomicUsize = AtomicUsize::new(0);
        let dir = std::env::temp_dir().join(format!(
            "wavetrace-scene-{}-{}-{}",
            std::process::id(),
            tag,
            N.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create temp dir");
        dir
    }

    /// Writes `files` (name, contents) into a fresh folder; returns the folder.
    pub fn write(tag: &str, files: &[(&str, &str)]) -> PathBuf {
        let dir = temp_dir(tag);
        for (name, text) in files {
            let p = dir.join(name);
            if let Some(parent) = p.parent() {
                std::fs::create_dir_all(parent).expect("mkdir");
            }
            std::fs::write(&p, text).expect("write");
        }
        dir
    }

    /// Loads `main` from a folder holding `files`.
    pub fn load(files: &[(&str, &str)], defines: &[(&str, &str)]) -> Result<super::Scene, super::Error> {
        let dir = write("load", files);
        let defines: Vec<(String, String)> = defines
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect();
        super::load(&dir.join(files[0].0), &defines)
    }

    /// The error's text, checking that it names `file` (a suffix) and `line`.
    pub fn error_at(r: Result<super::Scene, super::Error>, file: &str, line: u32) -> String {
        match r {
            Ok(_) => panic!("expected an error at {file}:{line}"),
            Err(e) => {
                let text = e.to_string();
                match &e {
                    super::Error::At { file: f, line: l, .. } => {
                        assert!(f.ends_with(Path::new(file)), "{text}: wrong file, want {file}");
                        assert_eq!(*l, line, "{text}: wrong line");
                    }
                    super::Error::File { .. } => panic!("{text}: no line, want {file}:{line}"),
                }
                text
            }
        }
    }

    /// A minimal Mitsuba scene around `body`.
    pub fn mitsuba(body: &str) -> String {
        format!(
            "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"/>\n{body}\n</scene>\n"
        )
    }

    pub const TRI_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nf 1/1/1 2/2/2 3/3/3\n";
}
