//! What both dialect loaders share: the growing lists of a [`Scene`] and mesh files
//! resolved against the scene file. (The types each family knows but does not
//! support yet are in its registry; `super::plugin::unsupported` words the errors.)

use std::path::PathBuf;

use glam::Mat4;

use super::mesh;
use super::properties::Properties;
use super::shape::{Quadric, QuadricKind};
use super::xml::Element;
use super::{Bsdf, Emitter, Error, Medium, Mesh, Texture};

/// The lists a loader fills in.
#[derive(Default)]
pub struct Builder {
    pub meshes: Vec<Mesh>,
    pub quadrics: Vec<Quadric>,
    /// The grids of the `sdfgrid` quadrics ([`super::Scene::sdfgrids`]).
    pub sdfgrids: Vec<super::shape::sdfgrid::SdfGrid>,
    pub bsdfs: Vec<Bsdf>,
    pub emitters: Vec<Emitter>,
    /// Per emitter, its sampling weight ([`super::Scene::emitter_weights`]).
    pub emitter_weights: Vec<f32>,
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
        self.add_weighted_emitter(emitter, 1.0)
    }

    /// An emitter that emitter sampling chooses `weight` times as often as one of
    /// weight 1 (Mitsuba's `sampling_weight`).
    pub fn add_weighted_emitter(&mut self, emitter: Emitter, weight: f32) -> u32 {
        self.emitters.push(emitter);
        self.emitter_weights.push(weight);
        (self.emitters.len() - 1) as u32
    }

    /// Brings a mesh to world space and adds it: optional removal of vertex normals
    /// (`face_normals`), `to_world`, Mitsuba's vertex normals where the file has none
    /// (`options.compute_normals`), then degenerate triangles are dropped. A mesh left
    /// with no triangles is an error at the shape's line.
    pub fn add_mesh(
        &mut self,
        el: &Element,
        mut m: Mesh,
        options: &MeshOptions,
        bsdf: u32,
        emitter: Option<u32>,
    ) -> Result<(), Error> {
        if options.face_normals {
            m.normals.clear();
        }
        mesh::transform(&mut m, options.to_world);
        // The normals' pass sees every triangle's area: where all are positive, the
        // degenerate triangles' pass would find none (a fifth of a PLY's load).
        let all_valid = options.compute_normals
            && !options.face_normals
            && m.normals.is_empty()
            && mesh::compute_vertex_normals(&mut m);
        m.flip_normals = options.flip_normals;
        if !all_valid {
            mesh::drop_degenerate(&mut m);
        }
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

    /// Adds curves ([`Mesh::radii`]): `to_world` moves their control points and leaves
    /// the radii as they are, as Mitsuba does.
    pub fn add_curves(
        &mut self,
        el: &Element,
        mut m: Mesh,
        to_world: Mat4,
        bsdf: u32,
        null_bsdf: bool,
    ) -> Result<(), Error> {
        for p in &mut m.positions {
            *p = to_world.transform_point3(*p);
            if !p.is_finite() {
                return Err(el.err(format!(
                    "to_world takes a control point of '{}' to infinity",
                    m.name
                )));
            }
        }
        m.bsdf = bsdf;
        m.null_bsdf = null_bsdf;
        self.meshes.push(m);
        Ok(())
    }

    /// Adds a quadric after checking that its `to_world` keeps the shape one the
    /// intersector handles: spheres may only rotate, mirror, translate and scale
    /// uniformly; cylinders may also scale along their axis; disks take any
    /// invertible affine map. The error names `to_world` (`props`' object).
    pub fn add_quadric(&mut self, props: &Properties, q: Quadric) -> Result<(), Error> {
        let m = q.to_world;
        let cols = [m.x_axis, m.y_axis, m.z_axis].map(|c| c.truncate());
        let len = cols.map(|c| c.length());
        let finite = m.is_finite() && m.row(3) == glam::Vec4::W;
        let tol = |scale: f32| 1e-4 * scale.max(1e-30);
        let orthogonal =
            |i: usize, j: usize| cols[i].dot(cols[j]).abs() <= tol(len[i]) * len[j].max(1e-30);
        let (ok, what) = match q.kind {
            QuadricKind::Sphere => (
                (len[1] - len[0]).abs() <= tol(len[0])
                    && (len[2] - len[0]).abs() <= tol(len[0])
                    && orthogonal(0, 1)
                    && orthogonal(1, 2)
                    && orthogonal(0, 2),
                "a sphere's to_world may only rotate, mirror, translate and scale uniformly (non-uniform scale or shear found)",
            ),
            QuadricKind::Cylinder => (
                (len[1] - len[0]).abs() <= tol(len[0])
                    && orthogonal(0, 1)
                    && orthogonal(1, 2)
                    && orthogonal(0, 2),
                "a cylinder's to_world may only rotate, mirror, translate, scale uniformly across its axis and scale along it (non-uniform scale across the axis or shear found)",
            ),
            QuadricKind::Disk => (
                cols[0].cross(cols[1]).length() > 0.0,
                "a disk's to_world collapses the disk to a line or a point",
            ),
            QuadricKind::SdfGrid(_) => (
                m.determinant().abs() > 0.0,
                "an sdfgrid's to_world must be invertible",
            ),
        };
        if !finite || !ok || len.iter().any(|&l| !(l > 0.0 && l.is_finite())) {
            let detail = if finite {
                what
            } else {
                "to_world is not a finite affine map"
            };
            return Err(props.error("to_world", detail));
        }
        let sdf = matches!(q.kind, QuadricKind::SdfGrid(_));
        if !sdf && (q.area() <= 0.0 || !q.area().is_finite()) {
            return Err(props.error("to_world", "the shape has no area"));
        }
        self.quadrics.push(q);
        Ok(())
    }

    /// Adds an `sdfgrid` quadric (its `kind` is set here) and its grid, whose words
    /// follow the previous grids' in the grid buffer.
    pub fn add_sdfgrid(
        &mut self,
        props: &Properties,
        mut grid: super::shape::sdfgrid::SdfGrid,
        mut q: Quadric,
    ) -> Result<(), Error> {
        let offset: usize = self.sdfgrids.iter().map(|g| g.words()).sum();
        grid.offset = u32::try_from(offset)
            .ok()
            .filter(|&o| (o as u64) + (grid.words() as u64) < 1 << 31)
            .ok_or_else(|| {
                props.error("filename", "the scene's sdfgrids together are too large")
            })?;
        q.kind = QuadricKind::SdfGrid(grid.place());
        self.add_quadric(props, q)?;
        self.sdfgrids.push(grid);
        Ok(())
    }
}

/// How [`Builder::add_mesh`] brings a mesh to world space.
#[derive(Debug, Clone, Copy)]
pub struct MeshOptions {
    pub to_world: Mat4,
    /// Mitsuba `face_normals`: drop the vertex normals (flat shading).
    pub face_normals: bool,
    /// Mitsuba `flip_normals`.
    pub flip_normals: bool,
    /// Compute vertex normals where the mesh has none, as Mitsuba's mesh plugins do
    /// (Nori's meshes keep face normals).
    pub compute_normals: bool,
}

impl Default for MeshOptions {
    fn default() -> Self {
        MeshOptions {
            to_world: Mat4::IDENTITY,
            face_normals: false,
            flip_normals: false,
            compute_normals: false,
        }
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
