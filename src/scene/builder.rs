//! What both dialect loaders share: the growing lists of a [`Scene`], mesh files
//! resolved against the scene file, and the names of object types we know but do not
//! support yet (so those get "not supported yet" and a typo gets "unknown").

use std::path::PathBuf;

use glam::{Mat4, Vec3};

use super::mesh;
use super::properties::Properties;
use super::xml::Element;
use super::{Bsdf, Emitter, Error, Medium, Mesh, Sphere, Texture};

/// BSDF types of Mitsuba 3 or Nori that wavetrace does not implement yet.
pub const UNSUPPORTED_BSDFS: &[&str] = &[
    "principled",
    "principledthin",
    "blendbsdf",
    "mask",
    "bumpmap",
    "polarizer",
    "retarder",
    "circular",
    "measured",
    "measured_polarized",
    "pplastic",
    "hair",
];

/// Emitter types we know but do not implement yet.
pub const UNSUPPORTED_EMITTERS: &[&str] = &[
    "directional",
    "sunsky",
    "projector",
    "directionalarea",
    "environment",
];

/// "bsdf type 'X' is not supported yet" or "unknown bsdf type 'X'".
pub fn unsupported(el: &Element, kind: &str, known: &[&str]) -> Error {
    let t = el.attr("type").unwrap_or("");
    if known.contains(&t) {
        el.err(format!("{kind} type '{t}' is not supported yet"))
    } else {
        el.err(format!("unknown {kind} type '{t}'"))
    }
}

/// The lists a loader fills in.
#[derive(Default)]
pub struct Builder {
    pub meshes: Vec<Mesh>,
    pub spheres: Vec<Sphere>,
    pub bsdfs: Vec<Bsdf>,
    pub emitters: Vec<Emitter>,
    pub media: Vec<Medium>,
    pub textures: Vec<Texture>,
    default_bsdf: Option<u32>,
}

impl Builder {
    /// The shared diffuse 0.5 BSDF of shapes that name none (added on first use).
    pub fn default_bsdf(&mut self) -> u32 {
        if let Some(i) = self.default_bsdf {
            return i;
        }
        let i = self.add_bsdf(Bsdf::default());
        self.default_bsdf = Some(i);
        i
    }

    pub fn add_bsdf(&mut self, bsdf: Bsdf) -> u32 {
        self.bsdfs.push(bsdf);
        (self.bsdfs.len() - 1) as u32
    }

    pub fn add_texture(&mut self, texture: Texture) -> u32 {
        self.textures.push(texture);
        (self.textures.len() - 1) as u32
    }

    pub fn add_emitter(&mut self, emitter: Emitter) -> u32 {
        self.emitters.push(emitter);
        (self.emitters.len() - 1) as u32
    }

    /// Brings a mesh to world space and adds it: optional removal of vertex normals
    /// (`face_normals`), `to_world`, `flip_normals`, then degenerate triangles are
    /// dropped. A mesh left with no triangles is an error at the shape's line.
    #[allow(clippy::too_many_arguments)]
    pub fn add_mesh(
        &mut self,
        el: &Element,
        mut m: Mesh,
        to_world: Mat4,
        face_normals: bool,
        flip_normals: bool,
        bsdf: u32,
        emitter: Option<u32>,
    ) -> Result<(), Error> {
        if face_normals {
            m.normals.clear();
        }
        mesh::transform(&mut m, to_world);
        if flip_normals {
            mesh::flip(&mut m);
        }
        mesh::drop_degenerate(&mut m);
        if m.indices.is_empty() {
            return Err(el.err(format!(
                "mesh '{}' has no triangles (degenerate ones are dropped)",
                m.name
            )));
        }
        m.bsdf = bsdf;
        m.emitter = emitter;
        self.meshes.push(m);
        Ok(())
    }

    /// A sphere: `center` and `radius` in object space, then `to_world`, which may only
    /// rotate, translate and scale uniformly.
    #[allow(clippy::too_many_arguments)]
    pub fn add_sphere(
        &mut self,
        props: &Properties,
        center: Vec3,
        radius: f32,
        to_world: Mat4,
        flip_normals: bool,
        bsdf: u32,
        emitter: Option<u32>,
    ) -> Result<(), Error> {
        let cols = [to_world.x_axis, to_world.y_axis, to_world.z_axis].map(|c| c.truncate());
        let s = cols.map(|c| c.length());
        let scale = s[0];
        let tol = 1e-4 * scale.max(1e-30);
        let uniform = (s[1] - scale).abs() <= tol
            && (s[2] - scale).abs() <= tol
            && cols[0].dot(cols[1]).abs() <= tol * scale
            && cols[1].dot(cols[2]).abs() <= tol * scale
            && cols[0].dot(cols[2]).abs() <= tol * scale
            && to_world.row(3) == glam::Vec4::W;
        if !uniform {
            return Err(props.error(
                "to_world",
                "a sphere's to_world may only rotate, translate and scale uniformly (non-uniform scale or shear found)",
            ));
        }
        let radius = radius * scale;
        if !(radius > 0.0 && radius.is_finite()) {
            return Err(props.error(
                "radius",
                format!("sphere radius must be positive, found {radius}"),
            ));
        }
        self.spheres.push(Sphere {
            center: to_world.transform_point3(center),
            radius,
            bsdf,
            emitter,
            flip_normals,
            interior: None,
            exterior: None,
            null_bsdf: false,
        });
        Ok(())
    }
}

/// Resolves the mesh file named by string parameter `key` (see [`Element::resolve`]); a missing file is an error at the parameter's line naming the
/// path tried.
pub fn mesh_path(el: &Element, props: &Properties, key: &str) -> Result<PathBuf, Error> {
    let name = props
        .string_opt(key)?
        .ok_or_else(|| props.object_error(format!("{} needs a '{key}'", props.object())))?;
    el.resolve(&name)
        .map_err(|tried| props.error(key, format!("mesh file {tried} not found")))
}
