//! The scene description: what a scene file says, resolved to world space.
//!
//! Plain Rust that knows nothing of Vulkan; everything here is tested without a GPU.
//! Both scene dialects (Mitsuba 3 and Nori XML) load into the same [`Scene`].

pub mod bsdf;
mod builder;
pub mod camera;
pub mod distribution2d;
pub mod emitter;
pub mod envmap;
pub mod error;
mod file_bytes;
pub mod film;
mod inline_refs;
pub mod integrator;
pub mod medium;
pub mod mesh;
mod mitsuba;
mod nori;
pub mod obj;
pub mod plugin;
pub mod ply;
mod ply_binary;
pub mod procedural;
pub mod properties;
pub mod sampler;
pub mod sensor;
pub mod serialized;
pub mod shape;
pub mod spectrum;
pub mod texture;
pub mod textured_emitter;
pub mod transform;
pub mod vdb;
pub mod xml;

pub use bsdf::Bsdf;
pub use camera::{Camera, Projection};
pub use emitter::Emitter;
pub use error::Error;
pub use film::Film;
pub use integrator::IntegratorSpec;
pub use medium::Medium;
pub use sampler::Sampler;
pub use shape::instance::{Instance, ShapeGroup};
pub use shape::{Mesh, Quadric, QuadricKind};
pub use texture::Texture;

use std::path::{Path, PathBuf};

/// A loaded scene, every shape in world space.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The file it was read from (relative paths inside it resolve against its folder).
    pub path: PathBuf,
    pub camera: Camera,
    /// Reconstruction filter, crop window and output formats (the size is the camera's).
    pub film: Film,
    /// Samples per pixel the scene asks for (Mitsuba `sample_count`, Nori `sampleCount`),
    /// before the sampler rounds it ([`Sampler::sample_count`]).
    pub spp: u32,
    /// The sampler the scene names.
    pub sampler: Sampler,
    /// The integrator the scene names, with its parameters still unread.
    pub integrator: IntegratorSpec,
    pub meshes: Vec<Mesh>,
    /// Spheres, disks, cylinders and sdfgrids.
    pub quadrics: Vec<Quadric>,
    /// The grids of the `sdfgrid` quadrics, in the order of their words in the grid
    /// buffer (`QuadricKind::SdfGrid` holds each one's offset).
    pub sdfgrids: Vec<shape::sdfgrid::SdfGrid>,
    /// Shape groups (Mitsuba `shapegroup`): the meshes and quadrics above that are
    /// seen only through `instances`, in the group's space.
    pub groups: Vec<ShapeGroup>,
    /// Placements of the groups (Mitsuba `instance`).
    pub instances: Vec<Instance>,
    /// Every BSDF, indexed by `Mesh::bsdf` / `Quadric::bsdf`.
    pub bsdfs: Vec<Bsdf>,
    /// Every emitter; area emitters are referenced by the shape that carries them.
    pub emitters: Vec<Emitter>,
    /// Per emitter, how often emitter sampling chooses it relative to the others
    /// (Mitsuba's `sampling_weight`, 1 unless the scene says otherwise).
    pub emitter_weights: Vec<f32>,
    /// Every participating medium, referenced by shapes (`interior`, `exterior`) and
    /// by the camera.
    pub media: Vec<Medium>,
    /// The medium the camera sits in.
    pub camera_medium: Option<u32>,
    /// Every texture, indexed by BSDF texture maps and textured emitters.
    pub textures: Vec<Texture>,
    /// Every sensor of the scene in document order (Mitsuba's `scene.sensors()`, which
    /// `mi.render(scene, sensor=i)` indexes: those at the top level and those nested
    /// in shapes alike). `camera`, `film`, `spp`, `sampler` and `camera_medium` above
    /// are those of the one rendered: the first, or the one [`Scene::select_sensor`]
    /// picked.
    pub sensors: Vec<sensor::SceneSensor>,
}

impl Scene {
    /// Renders sensor `index` of [`Scene::sensors`] (`wavetrace render --sensor`); an
    /// index out of range is an error saying how many there are.
    pub fn select_sensor(&mut self, index: usize) -> Result<(), String> {
        let n = self.sensors.len();
        let s = self.sensors.get(index).ok_or_else(|| {
            format!(
                "sensor {index} does not exist: the scene has {n} sensor{} (0{})",
                if n == 1 { "" } else { "s" },
                if n > 1 {
                    format!(" to {}", n - 1)
                } else {
                    String::new()
                }
            )
        })?;
        self.camera = s.camera.clone();
        self.film = s.film.clone();
        self.spp = s.spp;
        self.sampler = s.sampler;
        self.camera_medium = s.medium;
        Ok(())
    }

    /// Total number of triangles over all meshes (those of shape groups once).
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.indices.len()).sum()
    }

    /// Per shape (meshes, then quadrics: the renderer's shape numbering), whether it
    /// belongs to a shape group, and so is seen only through instances.
    pub fn grouped_shapes(&self) -> Vec<bool> {
        let mut grouped = vec![false; self.meshes.len() + self.quadrics.len()];
        for g in &self.groups {
            for &m in &g.meshes {
                grouped[m as usize] = true;
            }
            for &q in &g.quadrics {
                grouped[self.meshes.len() + q as usize] = true;
            }
        }
        grouped
    }

    /// Triangles a ray may meet: those outside groups, plus each instance's group's.
    pub fn instanced_triangle_count(&self) -> u64 {
        let group_triangles: Vec<u64> = self
            .groups
            .iter()
            .map(|g| {
                g.meshes
                    .iter()
                    .map(|&m| self.meshes[m as usize].indices.len() as u64)
                    .sum()
            })
            .collect();
        let grouped: u64 = group_triangles.iter().sum();
        let placed: u64 = self
            .instances
            .iter()
            .map(|i| group_triangles[i.group as usize])
            .sum();
        self.triangle_count() as u64 - grouped + placed
    }

    /// Whether some shape has a `null` BSDF (a boundary rays pass through).
    pub fn has_null_surfaces(&self) -> bool {
        self.meshes.iter().any(|m| m.null_bsdf) || self.quadrics.iter().any(|s| s.null_bsdf)
    }

    /// Whether a ray may cross one of its null surfaces or thin dielectrics and then
    /// meet it again: a sphere, cylinder or sdfgrid, past which the second-nearest hit of a
    /// traversal is not what the ray meets next (bvh.glsl's `bvh_hit_once`), so every
    /// crossing traces again.
    pub fn has_curved_crossings(&self) -> bool {
        let curves = self
            .meshes
            .iter()
            .any(|m| m.is_curves() && (m.null_bsdf || self.is_thin_dielectric(m.bsdf)));
        curves
            || self.quadrics.iter().any(|q| {
                (q.null_bsdf || self.is_thin_dielectric(q.bsdf) || self.is_mask(q.bsdf))
                    && matches!(
                        q.kind,
                        QuadricKind::Sphere | QuadricKind::Cylinder | QuadricKind::SdfGrid(_)
                    )
            })
    }

    /// Whether some shape has a `thindielectric` BSDF.
    pub fn has_thin_dielectrics(&self) -> bool {
        self.meshes.iter().any(|m| self.is_thin_dielectric(m.bsdf))
            || self
                .quadrics
                .iter()
                .any(|s| self.is_thin_dielectric(s.bsdf))
    }

    /// Whether some shape's BSDF is a `mask` (or holds one): the volumetric path
    /// tracers cross it as a null surface with probability 1 - opacity.
    pub fn has_masks(&self) -> bool {
        self.meshes.iter().any(|m| self.is_mask(m.bsdf))
            || self.quadrics.iter().any(|s| self.is_mask(s.bsdf))
    }

    /// Whether BSDF `b` is a `mask` or a composite with one inside (a blend's or bump
    /// map's child; crossed likewise, shaders/bsdf/mask_crossing.glsl).
    fn is_mask(&self, b: u32) -> bool {
        fn has_mask(b: &Bsdf) -> bool {
            match b {
                Bsdf::Mask { .. } => true,
                Bsdf::Blend { .. } | Bsdf::BumpMap { .. } => {
                    bsdf::composite::children(b).into_iter().any(has_mask)
                }
                _ => false,
            }
        }
        self.bsdfs.get(b as usize).is_some_and(has_mask)
    }

    /// Whether BSDF `b` is a `thindielectric`.
    fn is_thin_dielectric(&self, b: u32) -> bool {
        self.bsdfs
            .get(b as usize)
            .is_some_and(|b| b.is_thin_dielectric())
    }

    /// Whether the kernels need their medium code: media or null surfaces.
    pub fn needs_medium_code(&self) -> bool {
        !self.media.is_empty() || self.has_null_surfaces()
    }

    /// What the scene uses, by name: the features that decide which kernel code and
    /// stages a render needs.
    pub fn features(&self) -> Vec<&'static str> {
        let mut f = Vec::new();
        let mut add = |on: bool, name| {
            if on {
                f.push(name)
            }
        };
        add(self.meshes.iter().any(|m| !m.is_curves()), "triangles");
        add(
            self.meshes
                .iter()
                .any(|m| m.is_curves() && !m.is_bspline() && !m.is_ellipsoids()),
            "linear curves",
        );
        add(self.meshes.iter().any(Mesh::is_bspline), "bspline curves");
        add(self.meshes.iter().any(Mesh::is_ellipsoids), "ellipsoids");
        let has = |k: QuadricKind| self.quadrics.iter().any(|q| q.kind == k);
        add(has(QuadricKind::Sphere), "spheres");
        add(has(QuadricKind::Disk), "disks");
        add(has(QuadricKind::Cylinder), "cylinders");
        add(!self.sdfgrids.is_empty(), "sdfgrids");
        add(
            self.meshes.iter().any(|m| !m.normals.is_empty()),
            "vertex normals",
        );
        add(self.meshes.iter().any(|m| !m.uvs.is_empty()), "uvs");
        let has = |p: fn(&Emitter) -> bool| self.emitters.iter().any(p);
        add(has(|e| matches!(e, Emitter::Point { .. })), "point lights");
        add(has(|e| matches!(e, Emitter::Area { .. })), "area lights");
        add(
            has(|e| matches!(e, Emitter::Directional { .. })),
            "directional lights",
        );
        add(
            has(|e| matches!(e, Emitter::Projector { .. })),
            "projectors",
        );
        add(
            has(|e| matches!(e, Emitter::Constant { .. })),
            "constant environment",
        );
        add(!self.media.is_empty(), "media");
        add(
            self.media
                .iter()
                .any(|m| matches!(m.kind, medium::MediumKind::Grid { .. })),
            "grid media",
        );
        add(self.has_null_surfaces(), "null surfaces");
        add(
            has(|e| matches!(e, Emitter::TexturedArea { .. })),
            "textured area lights",
        );
        add(
            has(|e| matches!(e, Emitter::EnvMap { .. })),
            "environment map",
        );
        add(!self.textures.is_empty(), "textures");
        add(
            self.bsdfs.iter().any(|b| {
                matches!(b, Bsdf::NormalMap { .. })
                    || matches!(b, Bsdf::TwoSided(i) if matches!(**i, Bsdf::NormalMap { .. }))
            }),
            "normal maps",
        );
        f
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
    pub fn load(
        files: &[(&str, &str)],
        defines: &[(&str, &str)],
    ) -> Result<super::Scene, super::Error> {
        let dir = write("load", files);
        let defines: Vec<(String, String)> = defines
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect();
        let scene = super::load(&dir.join(files[0].0), &defines);
        // The scene holds everything it read: the folder is not needed any more (the
        // suite would leave thousands of them in the temp dir).
        let _ = std::fs::remove_dir_all(&dir);
        scene
    }

    /// The error's text, checking that it names `file` (a suffix) and `line`.
    pub fn error_at(r: Result<super::Scene, super::Error>, file: &str, line: u32) -> String {
        match r {
            Ok(_) => panic!("expected an error at {file}:{line}"),
            Err(e) => {
                let text = e.to_string();
                match &e {
                    super::Error::At {
                        file: f, line: l, ..
                    } => {
                        assert!(
                            f.ends_with(Path::new(file)),
                            "{text}: wrong file, want {file}"
                        );
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
        format!("<scene version=\"3.0.0\">\n<sensor type=\"perspective\"/>\n{body}\n</scene>\n")
    }

    pub const TRI_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nf 1/1/1 2/2/2 3/3/3\n";
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::bsdf::{Dielectric, Diffuse, NoriMicrofacet};
    use std::path::Path;

    /// The shared scene suites, relative to the crate root (as in CI).
    fn shared(path: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../shared/scenes")
            .join(path)
    }

    #[test]
    fn nori_bunny_loads() {
        let s = load(&shared("nori/bunny/bunny.xml"), &[]).unwrap();
        assert_eq!(s.integrator.name, "normals");
        assert_eq!((s.camera.width, s.camera.height, s.spp), (768, 768, 1));
        assert_eq!(s.meshes.len(), 1);
        let n = s.triangle_count();
        println!("bunny: {n} triangles");
        assert_eq!(n, 2000);
        assert_eq!(s.meshes[0].normals.len(), s.meshes[0].positions.len());
    }

    #[test]
    fn mitsuba_cbox_loads_spectral_and_rgb() {
        for name in ["cbox.xml", "cbox-rgb.xml"] {
            let s = load(&shared(&format!("mitsuba/cbox/{name}")), &[]).unwrap();
            assert_eq!(s.meshes.len(), 8, "{name}");
            assert_eq!((s.camera.width, s.camera.height), (256, 256));
            assert_eq!(s.integrator.name, "path");
            assert_eq!(s.emitters.len(), 1);
            let light = s.meshes[0].emitter.expect("luminaire emits");
            let Emitter::Area { radiance } = s.emitters[light as usize] else {
                panic!()
            };
            assert!(
                radiance.x > radiance.z && radiance.x > 5.0,
                "{name}: {radiance}"
            );
            // The red wall is red, the green wall green.
            let refl = |mesh: usize| match &s.bsdfs[s.meshes[mesh].bsdf as usize] {
                Bsdf::Diffuse(Diffuse { reflectance }) => *reflectance,
                Bsdf::TwoSided(inner) => match **inner {
                    Bsdf::Diffuse(Diffuse { reflectance }) => reflectance,
                    ref other => panic!("{other:?}"),
                },
                other => panic!("{other:?}"),
            };
            assert!(refl(5).x > 3.0 * refl(5).y, "{name}: red {}", refl(5));
            assert!(refl(4).y > 2.0 * refl(4).x, "{name}: green {}", refl(4));
        }
        let s = load(
            &shared("mitsuba/cbox/cbox.xml"),
            &[("spp".into(), "7".into())],
        )
        .unwrap();
        assert_eq!(s.spp, 7);
    }

    #[test]
    fn nori_table_bsdfs_and_missing_mesh() {
        // Nori's table scene: microfacet, dielectrics with intIOR/extIOR, diffuse.
        let s = load(&shared("nori/table/table_path_mis.xml"), &[]).unwrap();
        assert!(s.bsdfs.iter().any(
            |b| matches!(b, Bsdf::NoriMicrofacet(NoriMicrofacet { alpha, .. }) if *alpha == 0.1)
        ));
        let dielectrics = s
            .bsdfs
            .iter()
            .filter(|b| matches!(b, Bsdf::Dielectric(Dielectric { .. })))
            .count();
        assert_eq!(dielectrics, 3);
        let e = load(&shared("nori/sphere/sphere_ao_ems.xml"), &[]).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("pa1/plane.obj' not found") && text.contains("sphere_ao_ems.xml:"),
            "{text}"
        );
    }

    /// Truncations and byte mutations of a valid scene and mesh: errors are fine,
    /// panics are not.
    #[test]
    fn mutated_inputs_never_panic() {
        let xml = r#"<scene version="3.0.0">
  <default name="r" value="8"/>
  <sensor type="perspective"><float name="fov" value="40"/>
    <transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="$r"/><integer name="height" value="$r"/></film>
  </sensor>
  <bsdf type="diffuse" id="w"><spectrum name="reflectance" value="400:0.5, 700:0.7"/></bsdf>
  <shape type="obj"><string name="filename" value="m.obj"/><ref id="w"/>
    <emitter type="area"><rgb name="radiance" value="1,2,3"/></emitter></shape>
  <shape type="sphere"><float name="radius" value="0.5"/></shape>
</scene>"#;
        let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\nf -1 -2 -3\n";
        let dir = testutil::temp_dir("fuzz");
        let scene = dir.join("s.xml");
        let mesh = dir.join("m.obj");
        std::fs::write(&scene, xml).unwrap();
        std::fs::write(&mesh, obj).unwrap();
        assert!(load(&scene, &[]).is_ok());

        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut rand = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let interesting = b"<>/\"=$:,.-0123456789e \n\x00\xff";
        for (target, original) in [(&scene, xml.as_bytes()), (&mesh, obj.as_bytes())] {
            let mut variants: Vec<Vec<u8>> = (0..original.len())
                .step_by(3)
                .map(|n| original[..n].to_vec())
                .collect();
            for _ in 0..400 {
                let mut v = original.to_vec();
                for _ in 0..1 + rand() % 3 {
                    let i = (rand() as usize) % v.len();
                    match rand() % 3 {
                        0 => v[i] = interesting[(rand() as usize) % interesting.len()],
                        1 => {
                            v.remove(i);
                        }
                        _ => v.insert(i, interesting[(rand() as usize) % interesting.len()]),
                    }
                }
                variants.push(v);
            }
            for v in variants {
                std::fs::write(target, &v).unwrap();
                let _ = load(&scene, &[]);
            }
            std::fs::write(target, original).unwrap();
        }
    }

    /// A mask inside a blend or bump map makes the scene's shapes null crossings for
    /// the volumetric integrators as a mask at the root does; a plain BSDF does not.
    #[test]
    fn nested_masks_count_as_masks() {
        use super::testutil::{load, mitsuba};
        let shape = |bsdf: &str| mitsuba(&format!("<shape type=\"sphere\">{bsdf}</shape>"));
        let mask =
            r#"<bsdf type="mask"><float name="opacity" value="0.4"/><bsdf type="diffuse"/></bsdf>"#;
        for (bsdf, want) in [
            (mask.to_string(), true),
            (format!(r#"<bsdf type="blendbsdf"><float name="weight" value="0.3"/>{mask}<bsdf type="diffuse"/></bsdf>"#), true),
            (r#"<bsdf type="blendbsdf"><float name="weight" value="0.3"/><bsdf type="diffuse"/><bsdf type="diffuse"/></bsdf>"#.to_string(), false),
            (r#"<bsdf type="diffuse"/>"#.to_string(), false),
        ] {
            let s = load(&[("s.xml", &shape(&bsdf))], &[]).unwrap();
            assert_eq!(s.has_masks(), want, "{bsdf}");
        }
    }
}
