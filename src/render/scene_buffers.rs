//! The scene in GPU buffers: descriptor set 0 of every kernel that reads the scene
//! (`shaders/scene/scene_bindings.glsl`).

use glam::Vec3;

use crate::accel::Bvh;
use crate::gpu::layout::{
    shape_media, AliasEntry, BsdfRecord, EmitterRecord, MediumRecord, ShapeRecord, TextureRecord,
    TriangleRecord, Vertex, EMITTER_AREA, EMITTER_CONSTANT, EMITTER_DIRECTIONAL, EMITTER_ENVMAP,
    EMITTER_POINT, EMITTER_PROJECTOR, EMITTER_SPOT, MEDIUM_ALBEDO_RGB, MEDIUM_DENSITY_PACKED,
    MEDIUM_FEATURE_ALBEDO_GRID, MEDIUM_FEATURE_DENSITY_WORDS, MEDIUM_FEATURE_HOMOGENEOUS,
    MEDIUM_FEATURE_PACKED1, MEDIUM_FEATURE_PACKED3, MEDIUM_FEATURE_WORDS1, MEDIUM_FEATURE_WORDS3,
    MEDIUM_HOMOGENEOUS, NONE, PRIM_TRIANGLE, SHAPE_FLIP_NORMALS, SHAPE_HAS_NORMALS, SHAPE_HAS_UVS,
    SHAPE_MEDIUM_TRANSITION, SHAPE_MIRRORED, SHAPE_NORMALS_AGREE, SHAPE_NULL_BSDF,
    SHAPE_THIN_DIELECTRIC, SURFACE_FEATURE_NORMALS, SURFACE_FEATURE_UVS,
};
use crate::gpu::layout::{
    surface_feature_of_prim, EMITTER_KIND_BIT_QUADRIC_AREA, EMITTER_KIND_BIT_SPHERE_AREA,
    EMITTER_KIND_BIT_TEXTURE_SAMPLED, EMITTER_KIND_BIT_TEXTURE_SPHERE,
};
use crate::gpu::{BindingLayout, Buffer, DescriptorSet, Device, SceneAccess};
use crate::scene::textured_emitter;
use crate::scene::{Emitter, QuadricKind, Scene};

use super::error::{Error, Result};
use super::scene_parts::{
    array_sizes, extra_bindings, scene_arrays, texel_bytes, SceneArrays, ScenePlan, SCENE_ARRAYS,
};

pub use super::scene_parts::{scene_binding_kinds, SCENE_BINDINGS};

/// Host-side records of a scene, before upload. Built without a GPU so it can be
/// tested and inspected.
#[derive(Debug, Default, Clone)]
pub struct SceneRecords {
    pub shapes: Vec<ShapeRecord>,
    /// Per global triangle number, its vertices in `vertices`; empty when no mesh has
    /// vertex normals or uvs (the kernels then never read it).
    pub triangles: Vec<TriangleRecord>,
    pub vertices: Vec<Vertex>,
    pub bsdfs: Vec<BsdfRecord>,
    /// Point lights first, then the rest; see `point_light_count`.
    pub emitters: Vec<EmitterRecord>,
    pub point_light_count: u32,
    /// The emitter table of emitter sampling (uniform), each mesh emitter's triangle
    /// table, then the emitter table of photon emission (by power) at `photon_alias`.
    pub alias: Vec<AliasEntry>,
    /// Where the photon emission table starts in `alias` (Frame::photon_alias).
    pub photon_alias: u32,
    /// The environment emitter (constant or envmap), or `NONE`.
    pub env_emitter: u32,
    pub textures: Vec<TextureRecord>,
    /// Every bitmap's texels, RGB, three floats each.
    pub texels: Vec<f32>,
    /// Sampling distributions: environment maps' (`scene::envmap::Distribution::cdf`)
    /// and textured area emitters' (`scene::textured_emitter::TextureSampling::buffer`).
    pub distributions: Vec<f32>,
    /// Per emitter, the mean of its radiance texture (white for untextured ones), for
    /// the emitter's power; for an envmap its mean luminance over the sphere.
    emitter_mean: Vec<f64>,
    /// Media, indexed by `Scene::media`; their density grids and majorant grids.
    pub media: Vec<MediumRecord>,
    pub grid_data: Vec<f32>,
    pub majorants: Vec<f32>,
    /// Density grids packed one texel per voxel (`scene::medium::record::pack_density`).
    pub packed_density: Vec<[f32; 4]>,
    /// Per mesh, the global number of its vertex 0 in `triangles` (mesh attributes).
    mesh_vertex_base: Vec<u32>,
    /// The quadric kinds of the scene, as `SURFACE_FEATURE_*` bits.
    quadric_kinds: u32,
    /// `1 << EMITTER_KIND_BIT_SPHERE_AREA` and `1 << EMITTER_KIND_BIT_QUADRIC_AREA`
    /// for the area emitters on quadrics.
    quadric_emitter_kinds: u32,
    /// The shape an irradiancemeter samples (`scene::Projection::IrradianceMeter`),
    /// as an area emitter's record without radiance: uploaded after the emitters, at
    /// index `Frame::emitter_count` (shaders/sensor/camera.glsl); its triangle table
    /// follows the photon table in `alias`.
    pub sensor_shape: Option<EmitterRecord>,
}

/// `SHAPE_*` medium flags and packed media of a shape.
fn medium_flags(interior: Option<u32>, exterior: Option<u32>, null_bsdf: bool) -> (u32, u32) {
    let mut flags = 0;
    if null_bsdf {
        flags |= SHAPE_NULL_BSDF;
    }
    if interior.is_some() || exterior.is_some() {
        flags |= SHAPE_MEDIUM_TRANSITION;
    }
    (flags, shape_media(interior, exterior))
}

/// [`SHAPE_THIN_DIELECTRIC`] for a shape whose BSDF is a thin dielectric.
fn thin_flag(scene: &Scene, bsdf: u32) -> u32 {
    match scene.bsdfs.get(bsdf as usize) {
        Some(b) if b.is_thin_dielectric() => SHAPE_THIN_DIELECTRIC,
        _ => 0,
    }
}

/// Makes textured area emitter `e` (scene index; `rec` its record, on a shape whose
/// uv map the caller has checked) sample its points by its texture, its distribution
/// appended to `distributions`. False, and `rec` unchanged, if its texture cannot be
/// sampled that way (`scene::textured_emitter`): it then keeps area sampling.
fn sample_by_texture(
    scene: &Scene,
    e: u32,
    rec: &mut EmitterRecord,
    distributions: &mut Vec<f32>,
) -> bool {
    let Emitter::TexturedArea { texture, .. } = scene.emitters[e as usize] else {
        return false;
    };
    let Some(sampling) = textured_emitter::TextureSampling::new(&scene.textures[texture as usize])
    else {
        return false;
    };
    rec.dist_offset = distributions.len() as u32;
    rec.dist_width = sampling.dist.width;
    rec.dist_height = sampling.dist.height;
    distributions.extend_from_slice(&sampling.buffer());
    true
}

/// Luminance of linear sRGB (Rec. 709 weights).
fn luminance(c: Vec3) -> f64 {
    (0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z) as f64
}

impl SceneRecords {
    /// Records of `scene`, whose primitives `bvh` holds (light triangles are found
    /// through it).
    pub fn new(scene: &Scene, bvh: &Bvh) -> SceneRecords {
        let mut r = SceneRecords {
            env_emitter: NONE,
            ..Default::default()
        };
        for t in &scene.textures {
            let rec = t.record(&mut r.texels);
            r.textures.push(rec);
        }
        let remap = r.push_emitters(scene);
        r.push_meshes(scene, &remap);
        r.push_quadrics(scene, bvh, &remap);
        crate::scene::texture::mesh_attribute::records(
            scene,
            &r.mesh_vertex_base,
            &mut r.textures,
            &mut r.texels,
        );
        // The sdfgrids' words lead the grid buffer, where their quadrics' primitives
        // say (QuadricKind::SdfGrid); the media's grids follow.
        crate::scene::shape::sdfgrid::pack_scene(scene, &mut r.grid_data);
        if !scene.sdfgrids.is_empty() {
            r.quadric_kinds |= crate::gpu::layout::SURFACE_FEATURE_SDFGRIDS;
        }
        crate::scene::shape::bsplinecurve::pack(&scene.meshes, &mut r.grid_data);
        crate::scene::shape::ellipsoids::pack(&scene.meshes, &mut r.grid_data);
        for m in &scene.media {
            let rec = crate::scene::medium::record::record(
                m,
                &mut r.grid_data,
                &mut r.packed_density,
                &mut r.majorants,
            );
            r.media.push(rec);
        }
        r.build_alias_tables(scene, bvh, &remap);
        r.push_sensor_shape(scene, bvh);
        // A composite's nodes and nested models follow the scene's BSDFs.
        r.bsdfs = crate::scene::bsdf::composite::records(&scene.bsdfs);
        crate::scene::bsdf::measured::place_tables(&scene.bsdfs, &mut r.bsdfs, &mut r.texels);
        r
    }
}

impl SceneRecords {
    /// Pushes the emitters' records of `scene`, point lights first so the shading code
    /// can pick among them by index; returns `remap`, where `remap[i]` is the new index
    /// of scene emitter i.
    fn push_emitters(&mut self, scene: &Scene) -> Vec<u32> {
        let mut order: Vec<usize> = (0..scene.emitters.len()).collect();
        order.sort_by_key(|&i| !matches!(scene.emitters[i], Emitter::Point { .. }));
        let mut remap = vec![NONE; scene.emitters.len()];
        for (new, &old) in order.iter().enumerate() {
            remap[old] = new as u32;
            match scene.emitters[old] {
                Emitter::Point { .. } => self.point_light_count += 1,
                Emitter::Constant { .. } | Emitter::EnvMap { .. } => self.env_emitter = new as u32,
                _ => {}
            }
            let (rec, mean) = scene.emitters[old].record(&scene.textures, &mut self.distributions);
            self.emitters.push(rec);
            self.emitter_mean.push(mean);
        }
        remap
    }

    /// Pushes the shape, vertex and triangle records of `scene`'s meshes (`remap`: the
    /// emitters' new indices, [`Self::push_emitters`]).
    fn push_meshes(&mut self, scene: &Scene, remap: &[u32]) {
        let emitter_of = |e: Option<u32>| e.map(|i| remap[i as usize]).unwrap_or(NONE);
        // Triangle records lead from a hit to its vertices' normals and uvs; without
        // any (a scanned or generated mesh often has none) they would be 16 bytes a
        // triangle that nothing reads.
        let with_vertices = scene
            .meshes
            .iter()
            .any(|m| !m.normals.is_empty() || !m.uvs.is_empty())
            || crate::scene::texture::mesh_attribute::reads_vertices(scene);
        for (shape_index, mesh) in scene.meshes.iter().enumerate() {
            let base = self.vertices.len() as u32;
            self.mesh_vertex_base.push(base);
            let has_n = !mesh.normals.is_empty();
            let has_uv = !mesh.uvs.is_empty();
            let mut flags = 0;
            if has_n {
                flags |= SHAPE_HAS_NORMALS;
                // Only null boundaries and lights are read without their shading frame
                // (surface_at_as): a large mesh of another kind skips the check.
                if (mesh.null_bsdf || mesh.emitter.is_some()) && mesh.normals_agree() {
                    flags |= SHAPE_NORMALS_AGREE;
                }
            }
            if has_uv {
                flags |= SHAPE_HAS_UVS;
            }
            if mesh.flip_normals {
                flags |= SHAPE_FLIP_NORMALS;
            }
            if has_n || has_uv {
                for i in 0..mesh.positions.len() {
                    let n = mesh.normals.get(i).copied().unwrap_or_default();
                    let uv = mesh.uvs.get(i).copied().unwrap_or_default();
                    self.vertices.push(Vertex {
                        nx: n.x,
                        ny: n.y,
                        nz: n.z,
                        u: uv.x,
                        v: uv.y,
                        ..Vertex::default()
                    });
                }
            }
            if with_vertices {
                self.triangles
                    .extend(mesh.indices.iter().map(|t| TriangleRecord {
                        v0: base + t[0],
                        v1: base + t[1],
                        v2: base + t[2],
                        pad0: 0,
                    }));
            }
            if let Some(e) = mesh.emitter {
                let rec = &mut self.emitters[remap[e as usize] as usize];
                rec.shape = shape_index as u32;
                if let Some(map) = textured_emitter::AffineUvMap::of_mesh(mesh) {
                    let at = |v: glam::Vec3, w: f32| [v.x, v.y, v.z, w];
                    if sample_by_texture(scene, e, rec, &mut self.distributions) {
                        rec.to_world_x = at(map.origin, map.normal.x);
                        rec.to_world_y = at(map.du, map.normal.y);
                        rec.to_world_z = at(map.dv, map.normal.z);
                    }
                }
            }
            let (mflags, media) = medium_flags(mesh.interior, mesh.exterior, mesh.null_bsdf);
            self.shapes.push(ShapeRecord {
                bsdf: mesh.bsdf,
                emitter: emitter_of(mesh.emitter),
                flags: flags | mflags | thin_flag(scene, mesh.bsdf),
                media,
            });
        }
    }

    /// Pushes the shape records of `scene`'s quadrics, whose primitives `bvh` holds.
    fn push_quadrics(&mut self, scene: &Scene, bvh: &Bvh, remap: &[u32]) {
        let emitter_of = |e: Option<u32>| e.map(|i| remap[i as usize]).unwrap_or(NONE);
        // BVH slot of every quadric.
        let mut quadric_slot = vec![NONE; scene.quadrics.len()];
        for (i, p) in bvh.shape_prims().iter().enumerate() {
            // (Instances, accel::instance, are no quadrics.)
            if p.kind != PRIM_TRIANGLE && p.kind < crate::gpu::layout::PRIM_INSTANCE {
                quadric_slot[p.index as usize] = i as u32;
                self.quadric_kinds |= surface_feature_of_prim(p.kind);
            }
            if p.kind == crate::gpu::layout::PRIM_LINEAR_CURVE
                || p.kind == crate::gpu::layout::PRIM_BSPLINE_CURVE
                || p.kind == crate::gpu::layout::PRIM_ELLIPSOID
            {
                self.quadric_kinds |= surface_feature_of_prim(p.kind);
            }
        }
        for (k, q) in scene.quadrics.iter().enumerate() {
            let shape_index = self.shapes.len() as u32;
            if let Some(e) = q.emitter {
                let rec = &mut self.emitters[remap[e as usize] as usize];
                rec.shape = shape_index;
                rec.prim = quadric_slot[k];
                rec.prim_kind = crate::accel::quadric_prim(q, 0, 0).kind;
                rec.position = q.origin().into();
                rec.radius = q.radius();
                rec.area = q.area();
                // Disks and cylinders keep area sampling (textured_emitter says why).
                let by_texture = q.kind == QuadricKind::Sphere
                    && sample_by_texture(scene, e, rec, &mut self.distributions);
                self.quadric_emitter_kinds |= match q.kind {
                    _ if by_texture => {
                        1 << EMITTER_KIND_BIT_TEXTURE_SAMPLED | 1 << EMITTER_KIND_BIT_TEXTURE_SPHERE
                    }
                    QuadricKind::Sphere => 1 << EMITTER_KIND_BIT_SPHERE_AREA,
                    _ => 1 << EMITTER_KIND_BIT_QUADRIC_AREA,
                };
            }
            let (mflags, media) = medium_flags(q.interior, q.exterior, q.null_bsdf);
            let mut flags = mflags | thin_flag(scene, q.bsdf);
            if q.normals_flipped() {
                flags |= SHAPE_FLIP_NORMALS;
            }
            if q.mirrored() {
                flags |= SHAPE_MIRRORED;
            }
            self.shapes.push(ShapeRecord {
                bsdf: q.bsdf,
                emitter: emitter_of(q.emitter),
                flags,
                media,
            });
        }
    }
}

impl SceneRecords {
    /// The surface features the scene's shapes use (`SURFACE_FEATURE_*` bits): the
    /// kernels compile the code of the others away.
    pub fn surface_features(&self) -> u32 {
        let mut f = 0;
        for s in &self.shapes {
            if s.flags & SHAPE_HAS_NORMALS != 0 {
                f |= SURFACE_FEATURE_NORMALS;
            }
            if s.flags & SHAPE_HAS_UVS != 0 {
                f |= SURFACE_FEATURE_UVS;
            }
        }
        f
    }

    /// The slots in `bvh`'s prim array of every area emitter's primitives, in slot
    /// order, where there are at most `MAX_EMITTER_PRIMS` ([`Frame::emitter_prims`]);
    /// None where there are more, or none.
    ///
    /// [`Frame::emitter_prims`]: crate::gpu::layout::Frame::emitter_prims
    pub fn emitter_prims(&self, bvh: &Bvh) -> Option<Vec<u32>> {
        let mut slots = Vec::new();
        for (i, p) in bvh.shape_prims().iter().enumerate() {
            if p.kind != crate::gpu::layout::PRIM_INSTANCE
                && self.shapes[p.shape as usize].emitter != NONE
            {
                if slots.len() == crate::gpu::layout::MAX_EMITTER_PRIMS {
                    return None;
                }
                slots.push(i as u32);
            }
        }
        (!slots.is_empty()).then_some(slots)
    }

    /// The quadric kinds the scene has (`SURFACE_FEATURE_SPHERES`, `_DISKS`,
    /// `_CYLINDERS`): the BVH traversal and hit geometry compile the others away.
    pub fn prim_kinds(&self) -> u32 {
        self.quadric_kinds
    }

    /// The medium features the scene's media use (`MEDIUM_FEATURE_*` bits): the
    /// kernels compile the code of the others away.
    pub fn medium_features(&self) -> u32 {
        let mut f = 0;
        for m in &self.media {
            if m.kind == MEDIUM_HOMOGENEOUS {
                f |= MEDIUM_FEATURE_HOMOGENEOUS;
            } else if m.flags & MEDIUM_DENSITY_PACKED != 0 {
                f |= if m.channels == 1 {
                    MEDIUM_FEATURE_PACKED1
                } else {
                    MEDIUM_FEATURE_PACKED3
                };
            } else {
                f |= MEDIUM_FEATURE_DENSITY_WORDS
                    | if m.channels == 1 {
                        MEDIUM_FEATURE_WORDS1
                    } else {
                        MEDIUM_FEATURE_WORDS3
                    };
            }
            if m.albedo_data != NONE {
                f |= MEDIUM_FEATURE_ALBEDO_GRID
                    | if m.flags & MEDIUM_ALBEDO_RGB != 0 {
                        MEDIUM_FEATURE_WORDS3
                    } else {
                        MEDIUM_FEATURE_WORDS1
                    };
            }
        }
        f
    }

    /// The emitter kinds the scene has, a bit per `EMITTER_*` kind (area: on meshes)
    /// plus `EMITTER_KIND_BIT_SPHERE_AREA`, `EMITTER_KIND_BIT_QUADRIC_AREA` (disks
    /// and cylinders) and `EMITTER_KIND_BIT_TEXTURE_SAMPLED` (area emitters sampled
    /// by their texture, instead of their shape's bit; with
    /// `EMITTER_KIND_BIT_TEXTURE_SPHERE` where one is a sphere): `shade` compiles the
    /// others out.
    pub fn emitter_kinds(&self) -> u32 {
        self.emitters.iter().fold(
            self.quadric_emitter_kinds | self.sensor_shape_kinds(),
            |m, e| {
                if e.kind == EMITTER_AREA && e.dist_width != 0 {
                    m | 1 << EMITTER_KIND_BIT_TEXTURE_SAMPLED
                } else if e.kind == EMITTER_AREA && e.tri_count == 0 {
                    m // a quadric's: in quadric_emitter_kinds
                } else if e.kind == crate::gpu::layout::EMITTER_DIRECTIONAL_AREA {
                    // Its points are drawn as an area emitter's (a quadric's bit is in
                    // quadric_emitter_kinds).
                    let mesh = if e.tri_count > 0 {
                        1 << EMITTER_AREA
                    } else {
                        0
                    };
                    m | 1 << e.kind | mesh
                } else {
                    m | 1 << e.kind
                }
            },
        )
    }

    /// The texture mask of `shade` and `shadow` (specialization constant
    /// `SCENE_TEXTURES`): a bit per texture kind present, and `TEXTURE_FEATURE_*` for
    /// what reads textures.
    pub fn texture_mask(&self) -> u32 {
        use crate::gpu::layout::{
            TEXTURE_FEATURE_AREA, TEXTURE_FEATURE_BSDF, TEXTURE_FEATURE_ENVMAP,
            TEXTURE_FEATURE_LOOKUP_LOOP, TEXTURE_FEATURE_NORMALMAP, TEXTURE_FEATURE_PARAM_SHIFT,
        };
        let mut m = self.textures.iter().fold(0u32, |m, t| m | 1 << t.kind);
        let b = &self.bsdfs;
        // The lookups of a record's textured parameters (SURFACE_TEX_* bits of
        // bsdf_textured.glsl; a second roughness naming the first one's texture takes
        // its value).
        let lookups = |b: &BsdfRecord| {
            // A composite's node looks up its weight or height field itself.
            if b.kind == crate::scene::bsdf::kinds::COMPOSITE {
                return 0;
            }
            let alpha_v = if b.tex_alpha_v != b.tex_alpha_u {
                b.tex_alpha_v
            } else {
                0
            };
            [
                b.tex_reflectance,
                b.tex_specular,
                b.tex_transmittance,
                b.tex_alpha_u,
                alpha_v,
                0, // SURFACE_TEX_EMISSION: TEXTURE_FEATURE_AREA
                b.tex_cond_eta,
                b.tex_cond_k,
                b.tex_eta,
            ]
            .iter()
            .enumerate()
            .fold(0u32, |m, (k, &id)| if id != 0 { m | 1 << k } else { m })
        };
        let params = b.iter().fold(0u32, |m, b| m | lookups(b));
        if params != 0 {
            m |= TEXTURE_FEATURE_BSDF | params << TEXTURE_FEATURE_PARAM_SHIFT;
        }
        let area = self
            .emitters
            .iter()
            .any(|e| e.kind == EMITTER_AREA && e.texture != 0);
        // One lookup loop where a point needs fewer lookups than the scene has
        // textured parameters and emitters (bsdf_textured_point says why); a point
        // is taken to need a textured light's lookup or its BSDF's, not both.
        let per_point = b
            .iter()
            .map(|b| lookups(b).count_ones())
            .chain(std::iter::once(area as u32))
            .max()
            .unwrap_or(0);
        if params.count_ones() + area as u32 > per_point {
            m |= TEXTURE_FEATURE_LOOKUP_LOOP;
        }
        m |= crate::scene::bsdf::principled::texture_feature(b);
        if b.iter().any(|b| b.normal_map != 0) {
            m |= TEXTURE_FEATURE_NORMALMAP;
        }
        if self.emitters.iter().any(|e| e.kind == EMITTER_ENVMAP) {
            m |= TEXTURE_FEATURE_ENVMAP;
        }
        if self
            .emitters
            .iter()
            .any(|e| e.kind == EMITTER_AREA && e.texture != 0)
        {
            m |= TEXTURE_FEATURE_AREA;
        }
        if self
            .emitters
            .iter()
            .any(|e| matches!(e.kind, EMITTER_SPOT | EMITTER_PROJECTOR) && e.texture != 0)
        {
            m |= crate::gpu::layout::TEXTURE_FEATURE_EMITTER_PROFILE;
        }

        m
    }

    /// The emitter tables, and per mesh emitter a table of its triangles by area (so a
    /// point is uniform over the mesh's whole surface).
    ///
    /// Emitter sampling chooses an emitter in proportion to its sampling weight,
    /// Mitsuba 3's `sampling_weight`, 1 by default: uniformly, as Mitsuba 3 and Nori
    /// do, unless the scene says otherwise; the same estimator on the same scene
    /// file. Choosing by power instead, as before, is no better in general (a
    /// powerful light far away or behind walls takes the samples a near one needs):
    /// on scenes/textures/textures.xml it left relMSE at 1.34x Mitsuba's at equal
    /// samples.
    /// SPPM's photons still leave each emitter in proportion to its power (their flux
    /// stays even), from the table at `photon_alias`.
    fn build_alias_tables(&mut self, scene: &Scene, bvh: &Bvh, remap: &[u32]) {
        // BVH slot of every global triangle number.
        let mut slot = vec![NONE; scene.triangle_count()];
        for (i, p) in bvh.shape_prims().iter().enumerate() {
            if p.kind == PRIM_TRIANGLE {
                slot[p.index as usize] = i as u32;
            }
        }
        let n = self.emitters.len();
        let mut tables: Vec<AliasEntry> = Vec::new();
        let mut first_triangle = 0usize;
        for mesh in &scene.meshes {
            if let Some(e) = mesh.emitter {
                let areas: Vec<f64> = mesh.triangle_areas().map(f64::from).collect();
                let prims: Vec<u32> = (0..mesh.indices.len())
                    .map(|k| slot[first_triangle + k])
                    .collect();
                let rec = &mut self.emitters[remap[e as usize] as usize];
                rec.area = areas.iter().sum::<f64>() as f32;
                rec.tri_first = (n + tables.len()) as u32;
                rec.tri_count = areas.len() as u32;
                tables.extend(super::alias::build(&areas, &prims));
            }
            first_triangle += mesh.indices.len();
        }
        // Power of each emitter; a constant environment's flux through a sphere
        // bounding the scene.
        let radius = bvh
            .bounds()
            .map_or(1.0, |(lo, hi)| 0.5 * (hi - lo).length()) as f64;
        let pi = std::f64::consts::PI;
        let power: Vec<f64> = self
            .emitters
            .iter()
            .zip(&self.emitter_mean)
            .map(|(e, mean)| {
                let l = luminance(Vec3::from(e.radiance)) * mean;
                match e.kind {
                    EMITTER_POINT => 4.0 * pi * l,
                    EMITTER_SPOT => 2.0 * pi * (1.0 - (0.5 * e.cutoff).cos() as f64) * l,
                    EMITTER_AREA => pi * e.area as f64 * l,
                    // All along the normal: radiance times area (Mitsuba's sample_ray).
                    crate::gpu::layout::EMITTER_DIRECTIONAL_AREA => e.area as f64 * l,
                    // Through a disk of the bounding sphere's radius facing the light.
                    EMITTER_DIRECTIONAL => pi * radius * radius * l,
                    // π scale irradiance (in `radiance`) over the image rectangle at z = 1.
                    EMITTER_PROJECTOR => e.area as f64 * l,
                    EMITTER_ENVMAP => pi * 4.0 * pi * radius * radius * l,
                    _ => pi * 4.0 * pi * radius * radius * l,
                }
            })
            .collect();
        let power = share_with_environment(&power, |i| {
            matches!(self.emitters[i].kind, EMITTER_CONSTANT | EMITTER_ENVMAP)
        });
        // The scene's sampling weights (Mitsuba's `sampling_weight`, 1 by default), in
        // the records' order.
        let mut weights = vec![1.0f64; n];
        for (e, &w) in scene.emitter_weights.iter().enumerate() {
            match remap.get(e) {
                Some(&i) if (i as usize) < n => weights[i as usize] = f64::from(w),
                _ => {}
            }
        }
        self.alias = super::alias::build(&weights, &[]);
        super::alias::set_cdf(&mut self.alias);
        self.alias.extend(tables);
        self.photon_alias = self.alias.len() as u32;
        self.alias.extend(super::alias::build(&power, &[]));
    }
}

impl SceneRecords {
    /// The record of the shape an irradiancemeter samples (`sensor_shape`), packed as
    /// an area emitter on it is (emitter.glsl's `emitter_area_point` draws its points).
    fn push_sensor_shape(&mut self, scene: &Scene, bvh: &Bvh) {
        use crate::scene::camera::SensorShape;
        let crate::scene::Projection::IrradianceMeter { shape } = scene.camera.projection else {
            return;
        };
        let mut rec = EmitterRecord {
            kind: EMITTER_AREA,
            prim: NONE,
            ..EmitterRecord::default()
        };
        match shape {
            SensorShape::Mesh(m) => {
                let first: usize = scene.meshes[..m as usize]
                    .iter()
                    .map(|mesh| mesh.indices.len())
                    .sum();
                let mesh = &scene.meshes[m as usize];
                let mut slot = vec![NONE; mesh.indices.len()];
                for (i, p) in bvh.prims.iter().enumerate() {
                    let k = (p.index as usize).wrapping_sub(first);
                    if p.kind == PRIM_TRIANGLE && k < slot.len() {
                        slot[k] = i as u32;
                    }
                }
                let areas: Vec<f64> = mesh.triangle_areas().map(f64::from).collect();
                rec.shape = m;
                rec.area = areas.iter().sum::<f64>() as f32;
                rec.tri_first = self.alias.len() as u32;
                rec.tri_count = areas.len() as u32;
                self.alias.extend(super::alias::build(&areas, &slot));
            }
            SensorShape::Quadric(k) => {
                let q = &scene.quadrics[k as usize];
                rec.shape = (scene.meshes.len() + k as usize) as u32;
                rec.prim = bvh
                    .prims
                    .iter()
                    .position(|p| {
                        p.kind != PRIM_TRIANGLE
                            && p.kind < crate::gpu::layout::PRIM_INSTANCE
                            && p.index == k
                    })
                    .map_or(NONE, |i| i as u32);
                rec.prim_kind = crate::accel::quadric_prim(q, 0, 0).kind;
                rec.position = q.origin().into();
                rec.radius = q.radius();
                rec.area = q.area();
            }
        }
        self.sensor_shape = Some(rec);
    }

    /// The emitter records as uploaded: the emitters, then the sensor's shape.
    pub fn emitter_array(&self) -> Vec<EmitterRecord> {
        self.emitters
            .iter()
            .chain(&self.sensor_shape)
            .copied()
            .collect()
    }

    /// The emitter-kind bit of the sensor's shape (emitter.glsl compiles the sampling
    /// of the shapes no emitter and no sensor has away).
    fn sensor_shape_kinds(&self) -> u32 {
        use crate::gpu::layout::PRIM_SPHERE;
        match self.sensor_shape {
            None => 0,
            Some(r) if r.tri_count > 0 => 1 << EMITTER_AREA,
            Some(r) if r.prim_kind == PRIM_SPHERE => 1 << EMITTER_KIND_BIT_SPHERE_AREA,
            Some(_) => 1 << EMITTER_KIND_BIT_QUADRIC_AREA,
        }
    }
}

/// Photon emission's weights from emitter powers, giving the environment emitters the
/// share pbrt-v4's light samplers give infinite lights (Pharr, Jakob, Humphreys, PBR
/// 4th ed., sec. 12.6.3): each is chosen with probability 1 / (n_env + 1) when finite
/// emitters exist, the finite ones sharing the rest by power. An environment's "power"
/// through the scene's bounding sphere grows with that sphere (a large fog volume or
/// floor makes it dwarf every light) and would starve the emitters that light what
/// the camera sees: measured when emitter sampling still chose by power, on
/// scenes/media/smoke.xml relMSE at 64 spp 1.0e-2 by power alone against 2.6e-3 for
/// Mitsuba's uniform choice.
fn share_with_environment(power: &[f64], is_env: impl Fn(usize) -> bool) -> Vec<f64> {
    let n_env = (0..power.len()).filter(|&i| is_env(i)).count();
    let finite: f64 = (0..power.len())
        .filter(|&i| !is_env(i))
        .map(|i| power[i])
        .sum();
    if n_env == 0 || finite.is_nan() || finite <= 0.0 {
        return power.to_vec();
    }
    let each = 1.0 / (n_env as f64 + 1.0);
    (0..power.len())
        .map(|i| {
            if is_env(i) {
                each
            } else {
                each * power[i] / finite
            }
        })
        .collect()
}

/// The scene's buffers on the device and the descriptor set binding them.
pub struct SceneBuffers {
    _buffers: Vec<Buffer>,
    pub set: DescriptorSet,
    /// How the arrays were split over the bindings, and their sizes.
    pub plan: ScenePlan,
}

impl SceneBuffers {
    /// Uploads the scene in parts as large as the device allows. If that splits an
    /// array, `layout` must carry the plan's specialization constants: use
    /// [`SceneBuffers::upload_planned`] with a layout made from [`ScenePlan::spec`].
    pub fn upload(
        device: &Device,
        layout: &BindingLayout,
        bvh: &Bvh,
        records: &SceneRecords,
    ) -> Result<SceneBuffers> {
        let arrays = scene_arrays(bvh, records);
        let plan = ScenePlan::for_device(device.info(), array_sizes(&arrays), None)?;
        SceneBuffers::upload_planned(device, layout, arrays, plan)
    }

    /// Uploads `arrays` ([`scene_arrays`], [`super::scene_parts::take_scene_arrays`])
    /// split as `plan` says, on a layout whose kernels are specialized to the plan
    /// ([`BindingLayout::with_spec`] with [`ScenePlan::spec`]); each array is dropped
    /// (freed, if owned) once it is on the device.
    pub fn upload_planned(
        device: &Device,
        layout: &BindingLayout,
        arrays: SceneArrays<'_>,
        plan: ScenePlan,
    ) -> Result<SceneBuffers> {
        if plan.is_split()
            && !(layout.scene_access() == SceneAccess::Split
                && plan.spec().iter().all(|c| layout.spec().contains(c)))
        {
            return Err(Error::Options(
                "the scene is split over several bindings but the binding layout is not made \
                 for it (BindingLayout::with_spec with ScenePlan::spec and SceneAccess::Split)"
                    .into(),
            ));
        }
        let mut buffers = Vec::new();
        // Per binding, the buffer bound there.
        let mut bound = vec![0usize; SCENE_BINDINGS as usize];
        for (a, (array, data)) in SCENE_ARRAYS.iter().zip(arrays).enumerate() {
            let first = buffers.len();
            for p in 0..plan.parts[a] {
                let label = if plan.parts[a] == 1 {
                    array.label.to_string()
                } else {
                    format!("{} (part {} of {})", array.label, p + 1, plan.parts[a])
                };
                let bytes = &data.bytes()[plan.part_range(a, p)];
                buffers.push(Buffer::texels(
                    device,
                    &label,
                    bytes,
                    texel_bytes(array.kind),
                )?);
            }
            bound[a] = first;
            // Parts the array does not have bind its first part: every binding of
            // the layout needs a buffer, and the kernels never read them.
            for (p, b) in extra_bindings(a).enumerate() {
                let part = p + 1;
                bound[b as usize] = if part < plan.parts[a] as usize {
                    first + part
                } else {
                    first
                };
            }
        }
        let refs: Vec<&Buffer> = bound.iter().map(|&i| &buffers[i]).collect();
        let set = DescriptorSet::new(layout, 0, &refs)?;
        Ok(SceneBuffers {
            _buffers: buffers,
            set,
            plan,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::share_with_environment;

    #[test]
    fn environment_gets_a_fixed_share_and_lights_split_the_rest_by_power() {
        let w = share_with_environment(&[1e6, 3.0, 1.0], |i| i == 0);
        assert_eq!(w, vec![0.5, 0.375, 0.125]);
        // Only an environment, or no environment: powers unchanged.
        assert_eq!(share_with_environment(&[7.0], |_| true), vec![7.0]);
        assert_eq!(
            share_with_environment(&[2.0, 1.0], |_| false),
            vec![2.0, 1.0]
        );
    }
}
