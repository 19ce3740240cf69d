//! Every struct the host shares with the kernels, declared once.
//!
//! Each is `#[repr(C)]` with explicit padding to GLSL's std430 rules and mirrored field
//! for field, with the same names, in `shaders/scene/layout.glsl`. The test at the
//! bottom parses that file, computes std430 offsets and checks them against these.

use bytemuck::{Pod, Zeroable};

/// A BVH2 node holding the bounds of both its children (Aila and Laine 2009,
/// "Understanding the Efficiency of Ray Traversal on GPUs"): one fetch tests both.
///
/// For each child: `count == 0` means `index` is an inner node in the node array;
/// `count > 0` means a leaf holding primitives `index .. index + count` of the
/// primitive array. An absent child has an empty box (min = +inf, max = -inf).
/// The root is node 0.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    pub left_min: [f32; 3],
    pub left_index: u32,
    pub left_max: [f32; 3],
    pub left_count: u32,
    pub right_min: [f32; 3],
    pub right_index: u32,
    pub right_max: [f32; 3],
    pub right_count: u32,
}

/// Primitive kinds in [`Prim::kind`].
pub const PRIM_TRIANGLE: u32 = 0;
pub const PRIM_SPHERE: u32 = 1;
pub const PRIM_DISK: u32 = 2;
pub const PRIM_CYLINDER: u32 = 3;

/// One primitive, in BVH leaf order.
///
/// Triangle: `p0`, `p1`, `p2` are its world-space vertices and `index` its global
/// triangle number (into [`TriangleRecord`]s). Quadrics (`scene::Quadric`, `index`
/// its number) hold columns of their object-to-world map M: `p0` = M·0 (a sphere's or
/// disk's centre, the start of a cylinder's axis), `p1` = M·x̂ (its length is the
/// radius of a sphere or cylinder), `p2` = M·ŷ (sphere, disk) or M·ẑ (a cylinder's
/// axis, its length the cylinder's). A sphere's and cylinder's third axis follows as
/// the cross product, negated where [`SHAPE_MIRRORED`]. `shape` indexes
/// [`ShapeRecord`]s.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Prim {
    pub p0: [f32; 3],
    pub shape: u32,
    pub p1: [f32; 3],
    pub index: u32,
    pub p2: [f32; 3],
    pub kind: u32,
}

/// Per-shape data: what a hit on primitive `Prim::shape` shades with. Shapes are the
/// scene's meshes in order, then its spheres.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ShapeRecord {
    /// Index into the BSDF records.
    pub bsdf: u32,
    /// Index into the emitter records, or `NONE`.
    pub emitter: u32,
    /// `SHAPE_*` flags.
    pub flags: u32,
    /// The media on both sides ([`shape_media`]): interior medium in the low 16 bits,
    /// exterior in the high 16, [`MEDIUM_NONE16`] for none. Used where
    /// [`SHAPE_MEDIUM_TRANSITION`] is set.
    pub media: u32,
}

/// Marks an absent index (no emitter, no hit).
pub const NONE: u32 = u32::MAX;
/// The mesh has per-vertex normals.
pub const SHAPE_HAS_NORMALS: u32 = 1;
/// The mesh has per-vertex texture coordinates.
pub const SHAPE_HAS_UVS: u32 = 2;
/// Normals point inwards (Mitsuba `flip_normals`).
pub const SHAPE_FLIP_NORMALS: u32 = 4;
/// A `null` BSDF: an index-matched boundary that rays pass straight through.
pub const SHAPE_NULL_BSDF: u32 = 8;
/// The shape bounds media (Mitsuba `interior`/`exterior`): a ray leaving it towards
/// its normal enters the exterior medium, against it the interior one.
pub const SHAPE_MEDIUM_TRANSITION: u32 = 16;
/// A `thindielectric` BSDF: the volumetric path tracers cross the surface as a null
/// one with probability 1 - R' (Mitsuba's null transmission lobe), and shadow rays
/// pass it attenuated by 1 - R'.
pub const SHAPE_THIN_DIELECTRIC: u32 = 32;
/// A quadric whose `to_world` mirrors: its object frame is left-handed, which the
/// uvs and tangents of spheres and cylinders need (see [`Prim`]).
pub const SHAPE_MIRRORED: u32 = 64;
/// No medium in one half of [`ShapeRecord::media`].
pub const MEDIUM_NONE16: u32 = 0xffff;

/// [`ShapeRecord::media`] of a shape with these media (indices below 0xffff).
pub fn shape_media(interior: Option<u32>, exterior: Option<u32>) -> u32 {
    interior.unwrap_or(MEDIUM_NONE16) | exterior.unwrap_or(MEDIUM_NONE16) << 16
}

/// Medium kinds in [`MediumRecord::kind`].
pub const MEDIUM_HOMOGENEOUS: u32 = 0;
pub const MEDIUM_GRID: u32 = 1;
/// [`MediumRecord::flags`]: Mitsuba `sample_emitters` (next-event estimation at
/// scattering points in the medium).
pub const MEDIUM_SAMPLE_EMITTERS: u32 = 1;
/// [`MediumRecord::flags`]: the albedo grid has three channels.
pub const MEDIUM_ALBEDO_RGB: u32 = 2;
/// [`MediumRecord::flags`]: the density grid is in the packed-density buffer at
/// `data`, one 16-byte texel per voxel (`render::media::pack_density`), instead of
/// the grid buffer.
pub const MEDIUM_DENSITY_PACKED: u32 = 4;

/// Surface features a scene uses (`SceneRecords::surface_features`): a specialization
/// constant of the kernels that compute hit geometry (surface.glsl), so the code of
/// absent ones compiles away. Spheres:
pub const SURFACE_FEATURE_SPHERES: u32 = 1;
/// Meshes with vertex normals ([`SHAPE_HAS_NORMALS`]).
pub const SURFACE_FEATURE_NORMALS: u32 = 2;
/// Meshes with vertex uvs ([`SHAPE_HAS_UVS`]).
pub const SURFACE_FEATURE_UVS: u32 = 4;
/// Disks.
pub const SURFACE_FEATURE_DISKS: u32 = 8;
/// Cylinders.
pub const SURFACE_FEATURE_CYLINDERS: u32 = 16;
/// The `SURFACE_FEATURE_*` bit of each quadric `PRIM_*` kind; the BVH traversal's
/// primitive mask (specialization constant of intersect, shade and shadow) is made of
/// these bits too.
pub const fn surface_feature_of_prim(kind: u32) -> u32 {
    match kind {
        PRIM_SPHERE => SURFACE_FEATURE_SPHERES,
        PRIM_DISK => SURFACE_FEATURE_DISKS,
        PRIM_CYLINDER => SURFACE_FEATURE_CYLINDERS,
        _ => 0,
    }
}

/// Medium features a scene uses (`SceneRecords::medium_features`): a specialization
/// constant of the kernels with medium code, so the code of the others compiles away.
/// That matters on llvmpipe, which runs the code of a branch whatever its lanes decide.
/// Homogeneous media:
pub const MEDIUM_FEATURE_HOMOGENEOUS: u32 = 1;
/// A packed one-channel density grid ([`MEDIUM_DENSITY_PACKED`]).
pub const MEDIUM_FEATURE_PACKED1: u32 = 2;
/// A packed three-channel density grid.
pub const MEDIUM_FEATURE_PACKED3: u32 = 4;
/// A density grid left in the grid buffer (too large to pack).
pub const MEDIUM_FEATURE_DENSITY_WORDS: u32 = 8;
/// A one-channel grid (density or albedo) in the grid buffer.
pub const MEDIUM_FEATURE_WORDS1: u32 = 16;
/// A three-channel grid (density or albedo) in the grid buffer.
pub const MEDIUM_FEATURE_WORDS3: u32 = 32;
/// An albedo grid.
pub const MEDIUM_FEATURE_ALBEDO_GRID: u32 = 64;
/// Every grid feature: the scene has grid media.
pub const MEDIUM_FEATURE_GRIDS: u32 =
    MEDIUM_FEATURE_PACKED1 | MEDIUM_FEATURE_PACKED3 | MEDIUM_FEATURE_DENSITY_WORDS;

/// A participating medium. Homogeneous: `sigma_t` is the extinction per unit length
/// (scale applied), `albedo` the single-scattering albedo. Grid: the extinction at a
/// point is `sigma_t` (the scale, per channel) times the trilinearly interpolated
/// density grid of `res` voxels and `channels` channels at `data` in the grid buffer
/// (in the packed-density buffer with [`MEDIUM_DENSITY_PACKED`]);
/// `world_to_grid` maps world space to the grid's unit cube. A coarse grid of
/// `maj_res` cells at `maj_data` in the majorant buffer bounds the extinction (max
/// over channels) within each cell; `majorant` bounds it everywhere. `g`: the
/// Henyey-Greenstein asymmetry (0: isotropic).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct MediumRecord {
    pub sigma_t: [f32; 3],
    pub kind: u32,
    pub albedo: [f32; 3],
    pub g: f32,
    pub world_to_grid: [[f32; 4]; 4],
    pub res: [u32; 3],
    pub data: u32,
    pub maj_res: [u32; 3],
    pub maj_data: u32,
    pub majorant: f32,
    pub channels: u32,
    pub flags: u32,
    /// `NONE`, or the offset in the grid buffer of an albedo grid on the density
    /// grid's voxels ([`MEDIUM_ALBEDO_RGB`]: 3 channels, else 1).
    pub albedo_data: u32,
}

/// A triangle's vertex indices into the [`Vertex`] array (global numbering), padded
/// to one 16-byte texel.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct TriangleRecord {
    pub v0: u32,
    pub v1: u32,
    pub v2: u32,
    pub pad0: u32,
}

/// Shading attributes of a mesh vertex (positions live in [`Prim`]s), two texels. The
/// tangent ∂p/∂u is made per triangle at a hit (surface.glsl), as Mitsuba does.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    pub nx: f32,
    pub ny: f32,
    pub nz: f32,
    pub u: f32,
    pub v: f32,
    pub pad0: u32,
    pub pad1: u32,
    pub pad2: u32,
}

/// [`BsdfRecord::flags`]: Mitsuba `twosided` around the model.
pub const BSDF_TWOSIDED: u32 = 1;
/// [`BsdfRecord::flags`]: plastics with `nonlinear` = true.
pub const BSDF_NONLINEAR: u32 = 2;
/// [`BsdfRecord::flags`]: `normalmap` with `flip_invalid_normals` = true (Mitsuba's default).
pub const BSDF_NORMALMAP_FLIP: u32 = 4;
/// [`BsdfRecord::flags`]: `normalmap` with `use_shadowing_function` = true (Mitsuba's default).
pub const BSDF_NORMALMAP_SHADOWING: u32 = 8;
/// [`BsdfRecord::distribution`] values.
pub const BSDF_BECKMANN: u32 = 0;
pub const BSDF_GGX: u32 = 1;
/// Entries of [`BsdfRecord::table`].
pub const BSDF_TABLE_SIZE: usize = 32;

/// A BSDF's parameters; made from a `scene::Bsdf` by `BsdfRecord::from`. `kind` is the
/// model's id in `scene::bsdf::kinds::KINDS`. Fields by kind:
///
/// | kind | fields read |
/// |------|-------------|
/// | diffuse | `reflectance` |
/// | conductor | `specular`, `cond_eta`, `cond_k` |
/// | roughconductor | + `distribution`, `alpha_u`, `alpha_v` |
/// | dielectric | `specular`, `transmittance`, `eta` |
/// | roughdielectric | + `distribution`, `alpha_u`, `alpha_v` |
/// | plastic | `reflectance`, `specular`, `eta`, `specular_weight`, `internal` (F_dr inside) |
/// | roughplastic | + `distribution`, `alpha_u` (= `alpha_v`), `table` (coating transmittance at cos θ = i/31), `internal` (R_int) |
/// | Nori microfacet | `reflectance` (kd), `specular_weight` (ks), `eta`, `alpha_u` |
///
/// `flags`: [`BSDF_TWOSIDED`], [`BSDF_NONLINEAR`], [`BSDF_NORMALMAP_FLIP`],
/// [`BSDF_NORMALMAP_SHADOWING`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BsdfRecord {
    pub reflectance: [f32; 3],
    pub kind: u32,
    pub specular: [f32; 3],
    pub flags: u32,
    pub transmittance: [f32; 3],
    pub eta: f32,
    pub cond_eta: [f32; 3],
    pub alpha_u: f32,
    pub cond_k: [f32; 3],
    pub alpha_v: f32,
    pub distribution: u32,
    pub specular_weight: f32,
    pub internal: f32,
    pub pad0: u32,
    pub table: [[f32; 4]; BSDF_TABLE_SIZE / 4],
    /// Textures replacing the constants above at a hit, as texture index + 1 (0: the
    /// constant applies): `reflectance`, `specular`, `transmittance` (colors),
    /// `alpha_u`, `alpha_v` (luminance of the texture).
    pub tex_reflectance: u32,
    pub tex_specular: u32,
    pub tex_transmittance: u32,
    pub tex_alpha_u: u32,
    pub tex_alpha_v: u32,
    /// Mitsuba `normalmap` around the model: its texture index + 1, or 0.
    pub normal_map: u32,
    pub pad1: u32,
    pub pad2: u32,
}

/// Emitter kinds in [`EmitterRecord::kind`].
pub const EMITTER_POINT: u32 = 0;
pub const EMITTER_AREA: u32 = 1;
pub const EMITTER_CONSTANT: u32 = 2;
pub const EMITTER_SPOT: u32 = 3;
/// Mitsuba `envmap`: a lat-long image around the scene.
pub const EMITTER_ENVMAP: u32 = 4;
/// Bit of the emitter-kinds mask (specialization constant 9 of `shade`, a bit per
/// kind above) that stands for area emitters on spheres; `EMITTER_AREA`'s bit then
/// means area emitters on meshes.
pub const EMITTER_KIND_BIT_SPHERE_AREA: u32 = 5;
/// Bit of the emitter-kinds mask for area emitters on disks and cylinders.
pub const EMITTER_KIND_BIT_QUADRIC_AREA: u32 = 6;
/// Bit of the emitter-kinds mask for area emitters sampled by their texture
/// (`EmitterRecord::dist_width` > 0, on meshes or spheres), which then set neither
/// `EMITTER_AREA`'s bit nor `EMITTER_KIND_BIT_SPHERE_AREA`: where every light is one,
/// the code of uniform area sampling compiles out.
pub const EMITTER_KIND_BIT_TEXTURE_SAMPLED: u32 = 7;
/// Bit of the emitter-kinds mask set beside [`EMITTER_KIND_BIT_TEXTURE_SAMPLED`] where
/// a texture-sampled emitter lies on a sphere: without it that code compiles out.
pub const EMITTER_KIND_BIT_TEXTURE_SPHERE: u32 = 8;

/// An emitter. `radiance` is the intensity (W/sr) of point and spot lights and the
/// radiance of area and constant emitters.
///
/// Point and spot: `position`; spot also `axis`, `cos_cutoff`, `cutoff` (radians) and
/// `inv_transition` = 1 / (cutoff - beam width). Area: `shape` it sits on, its total
/// `area`; a mesh's triangles are chosen by area through the alias table entries
/// `tri_first .. tri_first + tri_count`; a quadric has `tri_count` = 0, `prim` (its
/// primitive in the BVH's order) and `prim_kind` (its `PRIM_*` kind), and a sphere
/// also `position` = centre and `radius`.
///
/// `texture` (index + 1, 0 for none): an area emitter's radiance is `radiance` times
/// the texture at the hit's uv; an environment map's image (then `radiance` is its
/// `scale`). Environment map: `to_world_*` are the columns of its rotation;
/// `dist_offset` is where its sampling distribution starts in the distribution
/// buffer, over `dist_width` x `dist_height` cells (see `scene::envmap`).
///
/// A textured area emitter sampled by its texture (`scene::textured_emitter`) has
/// `dist_width` x `dist_height` = the bitmap's texels and its distribution (CDFs,
/// then the texels' densities) at `dist_offset`; `dist_width` = 0 on every other
/// area emitter (sampled uniformly by area). On a mesh, `to_world_*` then hold its
/// affine uv map, x(u, v) = `to_world_x.xyz` + u `to_world_y.xyz` + v
/// `to_world_z.xyz`, and in their `w` the geometric normal there (x, y, z); a sphere
/// needs neither.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct EmitterRecord {
    pub position: [f32; 3],
    pub kind: u32,
    pub radiance: [f32; 3],
    pub shape: u32,
    pub axis: [f32; 3],
    pub cos_cutoff: f32,
    pub cutoff: f32,
    pub inv_transition: f32,
    pub area: f32,
    pub radius: f32,
    pub tri_first: u32,
    pub tri_count: u32,
    pub prim: u32,
    pub prim_kind: u32,
    pub texture: u32,
    pub dist_offset: u32,
    pub dist_width: u32,
    pub dist_height: u32,
    pub to_world_x: [f32; 4],
    pub to_world_y: [f32; 4],
    pub to_world_z: [f32; 4],
}

/// Texture kinds in [`TextureRecord::kind`] (`shaders/texture/texture.glsl`).
pub const TEXTURE_BITMAP: u32 = 0;
pub const TEXTURE_CHECKERBOARD: u32 = 1;
pub const TEXTURE_NOISE: u32 = 2;
pub const TEXTURE_MARBLE: u32 = 3;
/// [`TextureRecord::flags`]: nearest-neighbour lookups (else bilinear).
pub const TEXTURE_NEAREST: u32 = 1;
/// [`TextureRecord::flags`] bits 1-2: the wrap mode.
pub const TEXTURE_WRAP_SHIFT: u32 = 1;
pub const TEXTURE_WRAP_REPEAT: u32 = 0;
pub const TEXTURE_WRAP_MIRROR: u32 = 1;
pub const TEXTURE_WRAP_CLAMP: u32 = 2;
/// Bits of the shade kernel's texture mask (specialization constant 2) beside the
/// kinds (`1 << TEXTURE_*`): code for features a scene lacks compiles out.
pub const TEXTURE_FEATURE_BSDF: u32 = 256;
pub const TEXTURE_FEATURE_NORMALMAP: u32 = 512;
pub const TEXTURE_FEATURE_ENVMAP: u32 = 1024;
pub const TEXTURE_FEATURE_AREA: u32 = 2048;
/// Surface points need fewer texture lookups than the scene has textured BSDF
/// parameters and emitters: `bsdf_textured_point` (bsdf_textured.glsl) loops over them.
pub const TEXTURE_FEATURE_LOOKUP_LOOP: u32 = 4096;
/// Bit `TEXTURE_FEATURE_PARAM_SHIFT + k`: some BSDF textures its parameter k (0
/// reflectance, 1 specular, 2 transmittance, 3 alpha_u, 4 alpha_v), as
/// `SURFACE_TEX_*` in bsdf_textured.glsl.
pub const TEXTURE_FEATURE_PARAM_SHIFT: u32 = 16;

/// A texture (`scene::Texture`). Every texture's lookups first map the surface uv by
/// the affine `to_uv` (rows `to_uv_u`, `to_uv_v`: u' = x u + y v + z).
///
/// Bitmap: `width` x `height` RGB texels (linear) at `offset` in the texel buffer, row
/// 0 at v = 0, `flags` for filter and wrap. Checkerboard: `color0`, `color1`. Noise
/// and marble: `color0`, `color1`, `frequency`, `octaves`, `seed`, and for marble
/// `variation` (see texture.glsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct TextureRecord {
    pub kind: u32,
    pub offset: u32,
    pub width: u32,
    pub height: u32,
    pub flags: u32,
    pub octaves: u32,
    pub seed: u32,
    pub pad0: u32,
    pub color0: [f32; 3],
    pub frequency: f32,
    pub color1: [f32; 3],
    pub variation: f32,
    pub to_uv_u: [f32; 4],
    pub to_uv_v: [f32; 4],
}

/// One entry of an alias table (Walker 1977; Vose 1991): pick `i` uniformly, keep it
/// with probability `prob`, else take `alias`. `pmf` is the probability of choosing
/// entry `i` in the end; `prim` is the BVH primitive of a light triangle (tables of
/// mesh emitters), and in the emitter table the cumulative pmf of the entries before
/// (f32 bits, `render::alias::set_cdf`), for sampling by inversion.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct AliasEntry {
    pub prob: f32,
    pub alias: u32,
    pub pmf: f32,
    pub prim: u32,
}

/// Everything constant over one render: camera, film, integrator parameters.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Frame {
    /// Camera-to-world, column-major.
    pub camera_to_world: [[f32; 4]; 4],
    /// tan(fov/2) along x and y: the image plane at z = 1 spans ±these.
    pub tan_half_fov: [f32; 2],
    pub near_clip: f32,
    pub far_clip: f32,
    pub width: u32,
    pub height: u32,
    pub seed: u32,
    /// Number of point emitters (they come first in the emitter records).
    pub point_light_count: u32,
    /// Ambient occlusion: occluders farther than this are ignored.
    pub ao_max_t: f32,
    /// Ambient occlusion: 0 = cosine-weighted, 1 = uniform hemisphere sampling.
    pub ao_uniform: u32,
    /// Longest path in segments (Mitsuba's `max_depth`), u32::MAX for unbounded.
    pub max_depth: u32,
    pub emitter_count: u32,
    /// Russian roulette starts at this path depth (segments).
    pub rr_depth: u32,
    /// The constant environment emitter, or `NONE`.
    pub env_emitter: u32,
    /// 1: camera rays do not see emitters.
    pub hide_emitters: u32,
    /// The medium camera rays start in (Mitsuba's sensor `<medium>`), or `NONE`.
    pub camera_medium: u32,
    /// `SAMPLER_*`: which sampler draws the random numbers (shaders/sampler/).
    pub sampler_kind: u32,
    /// Samples of one pass of the sampler (its pattern's size; later sample indices
    /// start new passes).
    pub sample_count: u32,
    /// The sampler's strata: see [`crate::scene::sampler::SampleCount`].
    pub sampler_res_x: u32,
    pub sampler_res_y: u32,
    /// `SAMPLER_JITTER`, strength << `SAMPLER_STRENGTH_SHIFT`, `SAMPLER_SCRAMBLE_*` <<
    /// `SAMPLER_SCRAMBLE_SHIFT`.
    pub sampler_flags: u32,
    /// The grid the sampler's pixel keys index (the film with its sampled border,
    /// `film_pixel_key`): zsobol reads a key as (key % width, key / width).
    pub sampler_width: u32,
    pub sampler_height: u32,
    /// Strata of the first coordinate of a 2-D sample in one pass of the sampler, over
    /// which the emitter choice hands out whole strata (shaders/emitter/emitter.glsl,
    /// [`crate::render::sampler::emitter_strata`]); 0: the choice inverts the cdf of
    /// the emitters' sampling weights.
    pub emitter_strata: u32,
    /// The prims (slots of the BVH's prim array) of every area emitter, where they are
    /// at most [`MAX_EMITTER_PRIMS`]: bounces that only end paths then intersect them
    /// alone (shaders/integrator/path_emitted.glsl). Four to a word.
    pub emitter_prims: [[u32; 4]; 4],
    /// Where photon emission's emitter table (by power) starts among the alias
    /// entries (the one of emitter sampling, uniform, starts at 0).
    pub photon_alias: u32,
    pub pad0: u32,
    pub pad1: u32,
    pub pad2: u32,
}

/// Most emitter prims [`Frame::emitter_prims`] holds.
pub const MAX_EMITTER_PRIMS: usize = 16;

/// Sampler kinds ([`Frame::sampler_kind`]), mirrored in layout.glsl.
pub const SAMPLER_INDEPENDENT: u32 = 0;
pub const SAMPLER_STRATIFIED: u32 = 1;
pub const SAMPLER_MULTIJITTER: u32 = 2;
pub const SAMPLER_ORTHOGONAL: u32 = 3;
pub const SAMPLER_LDSAMPLER: u32 = 4;
pub const SAMPLER_ZSOBOL: u32 = 5;
pub const SAMPLER_SOBOL: u32 = 6;
pub const SAMPLER_PMJ02BN: u32 = 7;
/// `orthogonal` of strength above 2 (Bush's construction; Bose's for strength 2).
pub const SAMPLER_ORTHOGONAL_BUSH: u32 = 8;
/// [`Frame::sampler_flags`]: jitter within strata.
pub const SAMPLER_JITTER: u32 = 1;
pub const SAMPLER_STRENGTH_SHIFT: u32 = 8;
pub const SAMPLER_SCRAMBLE_SHIFT: u32 = 16;
/// Randomizations of base-2 digits (Sobol' samplers).
pub const SAMPLER_SCRAMBLE_NONE: u32 = 0;
pub const SAMPLER_SCRAMBLE_XOR: u32 = 1;
pub const SAMPLER_SCRAMBLE_FAST_OWEN: u32 = 2;
pub const SAMPLER_SCRAMBLE_OWEN: u32 = 3;

/// The state of one path of the wavefront, indexed by path slot.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PathState {
    pub throughput: [f32; 3],
    /// The pixel key the path's random numbers are drawn with (the full film's pixel,
    /// `render::film::FilmGeometry::key`).
    pub pixel: u32,
    pub radiance: [f32; 3],
    pub sample_index: u32,
    /// Solid-angle pdf with which the BSDF chose the current ray (for MIS when it hits
    /// an emitter).
    pub bsdf_pdf: f32,
    /// `PATH_*` flags.
    pub flags: u32,
    /// Product of η_t²/η_i² over the refractions so far: the factor by which they
    /// scaled the throughput's radiance (1/η² each) undone, so that Russian roulette
    /// does not kill paths inside glass for carrying less radiance (PBR 4th ed.,
    /// sec. 13.1, `etaScale`; Mitsuba's path integrator likewise).
    pub eta_scale: f32,
    /// The medium the current ray travels in, or `NONE`.
    pub medium: u32,
}

/// The current ray was sampled from a delta lobe (no MIS on the emitter it hits).
pub const PATH_DELTA: u32 = 1;
/// Set by the medium stage for path_shade within one dispatch, never stored: the
/// stage chose the reflection lobe of the thin dielectric the ray hit.
pub const PATH_THIN_REFLECT: u32 = 2;
/// The camera path counts for the film's alpha (Mitsuba's `valid_ray`): it found a
/// surface or scattered in a medium, or it sees a visible environment. Set by
/// `generate` and by `shade` at depth 0, kept through the path.
pub const PATH_COVERED: u32 = 4;

/// A ray waiting for the `intersect` stage.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct RayItem {
    pub origin: [f32; 3],
    pub path: u32,
    pub dir: [f32; 3],
    pub tmax: f32,
}

/// The closest hit of the ray at the same queue position (`prim == NONE`: a miss).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct HitItem {
    pub t: f32,
    pub u: f32,
    pub v: f32,
    pub prim: u32,
}

/// A shadow ray: if nothing blocks it, `contribution` is added to its path's
/// radiance.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ShadowItem {
    pub origin: [f32; 3],
    pub path: u32,
    pub dir: [f32; 3],
    pub tmax: f32,
    pub contribution: [f32; 3],
    /// The medium the shadow ray starts in, or `NONE`.
    pub medium: u32,
}

/// Queue lengths and statistics, all in one buffer. `ray_count[q]` is the length of
/// ray queue `q` (two queues, ping-ponged per bounce).
///
/// A queue is filled from both ends, each by one half of the producing dispatch's
/// workgroups, which append to their own counter in `tails` (a segment per 128
/// bytes): lavapipe hands each of its threads one contiguous half of a dispatch, so
/// the two never contend for one cache line (shaders/queue/queue.glsl). Between
/// dispatches, `queue_args` and `shade_args` fold the tails into the lengths, which
/// the kernels read from the frame's uniform buffer (see
/// [`crate::render::wavefront::Wavefront::reset_queues`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Counters {
    pub ray_count: [u32; 2],
    /// Rays traced in this batch (extension and shadow rays).
    pub rays_traced: u32,
    /// Samples dropped at accumulation because they were NaN or infinite.
    pub discarded: u32,
    /// Items the fast kernels of a bounce left to their full twins (deferral.glsl):
    /// `DEFERRED_RAYS` (shade's rays) and `DEFERRED_SHADOWS` (shadow rays).
    pub deferred: [u32; 2],
    /// Deferred items of the batch's bounces before the current lists (queue_args
    /// adds each bounce's as it empties them).
    pub deferred_total: u32,
    pub head_pad: [u32; 25],
    /// Each segment's append counters, 32 words (128 bytes) apart: `TAIL_*` in
    /// layout.glsl.
    pub tails: [u32; 64],
}

impl Default for Counters {
    fn default() -> Self {
        Self::zeroed()
    }
}

/// Indirect dispatch arguments for each queue, written on the GPU from [`Counters`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct DispatchArgs {
    pub rays: [u32; 3],
    pub shadows: [u32; 3],
    /// The partitioned bounce's hits and misses (`shade_args`).
    pub hits: [u32; 3],
    pub misses: [u32; 3],
    /// The items a bounce's fast shade and shadow deferred (deferral.glsl).
    pub deferred_rays: [u32; 3],
    pub deferred_shadows: [u32; 3],
}

/// Push constants of the wavefront kernels.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Push {
    /// Paths in this batch.
    pub path_count: u32,
    /// Path `p` of the batch is global sample number `pixel_base + p`, i.e. pixel
    /// `(pixel_base + p) % pixels` of sample `sample_base + (pixel_base + p) / pixels`.
    pub pixel_base: u32,
    pub sample_base: u32,
    /// Current bounce (0 = camera rays).
    pub depth: u32,
    /// Ray queue read this bounce (0 or 1); the other one is written.
    pub queue_in: u32,
    /// Path slots allocated: ray queue `q` starts at item `q * capacity`.
    pub capacity: u32,
    /// The film's sample slot of path 0 of this batch (`render::film`).
    pub sample_slot: u32,
    /// `film_gather`: the first crop row it gathers, and how many.
    pub film_row: u32,
    pub film_rows: u32,
    /// Always 0: the index of the frame's parameters in their uniform block
    /// (shaders/queue/wavefront.glsl says why it is not a constant).
    pub frame_index: u32,
    pub pad1: u32,
    pub pad2: u32,
}

/// Push constants of `tonemap` (the viewer's display of the film): the crop window's
/// size, the linear scale 2^exposure, and whether to show luminance (grey) rather
/// than RGB, as the render's PNG of a luminance film is grey.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct TonemapPush {
    pub width: u32,
    pub height: u32,
    pub scale: f32,
    pub luminance: u32,
}

/// Reconstruction filters: specialization constant 0 of `film_gather`
/// (`scene::film::Filter`).
pub const FILTER_BOX: u32 = 0;
pub const FILTER_TENT: u32 = 1;
pub const FILTER_GAUSSIAN: u32 = 2;
pub const FILTER_MITCHELL: u32 = 3;
pub const FILTER_LANCZOS: u32 = 4;
/// A film sample's flags: the sample is finite (NaN and infinite ones are dropped) ...
pub const FILM_SAMPLE_VALID: u32 = 1;
/// ... and its camera path was covered ([`PATH_COVERED`]).
pub const FILM_SAMPLE_COVERED: u32 = 2;

/// The film's parameters (`render::film::FilmGeometry`): the sampled region (the
/// crop window and the pixels around it whose samples its filter reaches, within the
/// film or, with `sample_border`, the film and its border), the crop window kept, the
/// pixel keys of the random numbers (the full sampled film's row-major index, so a
/// crop draws the same numbers as the full render), the filter's reach in pixels,
/// the sample slots of the ring, whether every camera path counts as covered, and the
/// filter's parameters (`shaders/film/filter.glsl`): tent (1 / radius); Gaussian
/// (-1 / 2σ², exp(-r² / 2σ²)); Mitchell (B, C, 2 / radius); Lanczos (lobes).
/// Pixel coordinates are the full film's, the top-left pixel (0, 0).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct FilmParams {
    pub region_x: i32,
    pub region_y: i32,
    pub region_width: u32,
    pub region_height: u32,
    pub crop_x: u32,
    pub crop_y: u32,
    pub crop_width: u32,
    pub crop_height: u32,
    pub key_x: i32,
    pub key_y: i32,
    pub key_width: u32,
    pub reach: u32,
    pub slots: u32,
    pub coverage: u32,
    pub pad0: u32,
    pub pad1: u32,
    pub filter_params: [f32; 4],
}

/// Photon mapping (`src/render/photon`, `shaders/photon/`): one photon stored where a
/// photon path met a non-delta surface. `power` is the flux it carries (W, RGB) and
/// `wi` the unit direction it arrived from (towards its previous vertex), octahedral
/// in two 16-bit snorms (`photon_dir_encode`, Cigolle et al. 2014, "A Survey of
/// Efficient Representations for Independent Unit Vectors"). `path`: the index of
/// its photon path in the emission sequence, which leaves out the photons of paths
/// past the budget's cut ([`PhotonParams::path_limit`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Photon {
    pub position: [f32; 3],
    pub path: u32,
    pub power: [f32; 3],
    pub wi: u32,
}

/// The state of one photon path, by path slot of the wavefront (in the path-state
/// buffer, which photon passes share with camera paths). `power`: the flux it carries
/// now; `index`: its index in the emission sequence; `start_power`: the largest
/// channel of its power at emission, against which Russian roulette weighs it;
/// `stored`: photons it has stored (or, counting, would have stored).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PhotonPath {
    pub power: [f32; 3],
    pub index: u32,
    pub start_power: f32,
    pub stored: u32,
    pub pad0: u32,
    pub pad1: u32,
}

/// Parameters of a photon pass (uniform block of descriptor set 2), written by the
/// host before each pass.
///
/// The hash grid: a photon at p lies in cell floor(p × `inv_cell_size`), hashed into
/// `table_mask` + 1 buckets. `capacity`: photon slots in the photon buffer (photons
/// appended past it are counted but not written; 0 counts only). `path_limit`: photons
/// of paths with an index at or above it stay out of the grid. `radius`, `gather_scale`,
/// `emission_scale`: the photon mapper's density estimate (see
/// `shaders/kernels/photon_gather.comp`). `scene_center`, `scene_radius`: a sphere
/// bounding the scene, for photons from environment emitters. `store_first`: store
/// photons at the first surface a photon path meets (photonmapper) or from the second
/// on (sppm, whose camera paths sample direct light). `max_bounces`: surfaces a photon
/// path meets at most. `iteration`: the stream of photon random numbers.
/// `first_pixel`: SPPM's visible points and pixel states hold the pixels from this one
/// on (a tile of the image).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PhotonParams {
    pub scene_center: [f32; 3],
    pub scene_radius: f32,
    pub cell_size: f32,
    pub inv_cell_size: f32,
    pub table_mask: u32,
    pub capacity: u32,
    pub radius: f32,
    pub gather_scale: f32,
    pub emission_scale: f32,
    pub path_limit: u32,
    pub store_first: u32,
    pub max_bounces: u32,
    pub iteration: u32,
    pub first_pixel: u32,
}

/// Counters of photon passes (descriptor set 2). `stored`: photons appended to the
/// photon buffer (may exceed its capacity: the excess was dropped); `max_radius`:
/// sppm's largest radius after an update, as the bits of a positive float (they order
/// as the floats do, so `atomicMax` on them takes the largest).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PhotonCounters {
    pub stored: u32,
    pub max_radius: u32,
    pub pad0: u32,
    pub pad1: u32,
}

/// Where a camera path ends in a photon mapper: the first surface whose BSDF is not a
/// delta, as the density estimate needs it. `bsdf` is its BSDF record ([`NONE`]: no
/// visible point), `uv` where its textures are read; `wo` the unit direction towards
/// the camera, `n` the shading normal (after a normal map) and `beta` the camera
/// path's throughput, all world space. With [`VISIBLE_POINT_NORMAL_MAP`] in `flags`,
/// `n0` is the unmapped shading normal and `alpha2` the normal map's shadowing
/// roughness (`normal_map.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct VisiblePoint {
    pub p: [f32; 3],
    pub bsdf: u32,
    pub wo: [f32; 3],
    pub u: f32,
    pub n: [f32; 3],
    pub v: f32,
    pub beta: [f32; 3],
    pub alpha2: f32,
    pub n0: [f32; 3],
    pub flags: u32,
}

/// [`VisiblePoint::flags`]: the BSDF has a normal map.
pub const VISIBLE_POINT_NORMAL_MAP: u32 = 1;

/// The state of one pixel of stochastic progressive photon mapping (pbrt-v4's
/// `SPPMPixel`): `radius` of its visible points' gathers, `n` the photon count N of
/// Hachisuka and Jensen 2009, `tau` the flux gathered so far (rescaled as the radius
/// shrinks), `ld` the sum of the light its camera paths found directly (emission and
/// emitter sampling), and `phi`, `m` what this iteration's photons added (Φ_i, M).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SppmPixel {
    pub tau: [f32; 3],
    pub radius: f32,
    pub ld: [f32; 3],
    pub n: f32,
    pub phi: [f32; 3],
    pub m: u32,
}

/// Threads per workgroup of every wavefront kernel (`WORKGROUP_SIZE` in GLSL).
pub const WORKGROUP_SIZE: u32 = 128;

#[cfg(test)]
mod tests {
    //! The GLSL mirror must agree with these structs: parse `layout.glsl`, lay every
    //! struct out by the std430 rules (GLSL 4.60 spec, section 7.6.2.2) and compare
    //! each field's name, order and offset, and each struct's size.

    use super::*;
    use std::collections::HashMap;
    use std::mem::{offset_of, size_of};

    /// (size, alignment) of a GLSL type under std430.
    fn std430(ty: &str) -> (usize, usize) {
        match ty {
            "float" | "uint" | "int" | "bool" => (4, 4),
            "vec2" | "uvec2" | "ivec2" => (8, 8),
            "vec3" | "uvec3" | "ivec3" => (12, 16),
            "vec4" | "uvec4" | "ivec4" => (16, 16),
            "mat4" => (64, 16),
            _ => panic!("layout test does not know GLSL type {ty}"),
        }
    }

    /// Struct name -> (fields with offsets, size), in file order.
    fn parse_glsl(src: &str) -> HashMap<String, (Vec<(String, usize)>, usize)> {
        let no_comments: String = src
            .lines()
            .map(|l| l.split("//").next().unwrap_or(""))
            .filter(|l| !l.trim_start().starts_with('#'))
            .collect::<Vec<_>>()
            .join("\n");
        let mut out = HashMap::new();
        let mut rest = no_comments.as_str();
        while let Some(pos) = rest.find("struct ") {
            rest = &rest[pos + 7..];
            let open = rest.find('{').expect("struct body");
            let close = rest.find('}').expect("struct end");
            let name = rest[..open].trim().to_string();
            let (mut offset, mut align_max) = (0usize, 4usize);
            let mut fields = Vec::new();
            for decl in rest[open + 1..close].split(';') {
                let decl = decl.trim();
                if decl.is_empty() {
                    continue;
                }
                let mut parts = decl.split_whitespace();
                let ty = parts.next().expect("type");
                let var = parts.next().expect("field name");
                let (field, count) = match var.find('[') {
                    Some(b) => (
                        &var[..b],
                        var[b + 1..var.len() - 1]
                            .parse::<usize>()
                            .expect("array length"),
                    ),
                    None => (var, 1),
                };
                let (size, align) = std430(ty);
                let stride = size.next_multiple_of(align);
                offset = offset.next_multiple_of(align);
                fields.push((field.to_string(), offset));
                offset += if count == 1 { size } else { stride * count };
                align_max = align_max.max(align);
            }
            out.insert(name, (fields, offset.next_multiple_of(align_max)));
            rest = &rest[close..];
        }
        out
    }

    macro_rules! rust_layout {
        ($t:ty, $($f:ident),+) => {
            (
                stringify!($t).to_string(),
                vec![$((stringify!($f).to_string(), offset_of!($t, $f))),+],
                size_of::<$t>(),
            )
        };
    }

    #[test]
    fn glsl_mirror_matches_rust_layout() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders/scene/layout.glsl");
        let src = std::fs::read_to_string(path).expect("read layout.glsl");
        let glsl = parse_glsl(&src);
        let rust = [
            rust_layout!(
                BvhNode,
                left_min,
                left_index,
                left_max,
                left_count,
                right_min,
                right_index,
                right_max,
                right_count
            ),
            rust_layout!(Prim, p0, shape, p1, index, p2, kind),
            rust_layout!(ShapeRecord, bsdf, emitter, flags, media),
            rust_layout!(TriangleRecord, v0, v1, v2, pad0),
            rust_layout!(Vertex, nx, ny, nz, u, v, pad0, pad1, pad2),
            rust_layout!(
                BsdfRecord,
                reflectance,
                kind,
                specular,
                flags,
                transmittance,
                eta,
                cond_eta,
                alpha_u,
                cond_k,
                alpha_v,
                distribution,
                specular_weight,
                internal,
                pad0,
                table,
                tex_reflectance,
                tex_specular,
                tex_transmittance,
                tex_alpha_u,
                tex_alpha_v,
                normal_map,
                pad1,
                pad2
            ),
            rust_layout!(
                EmitterRecord,
                position,
                kind,
                radiance,
                shape,
                axis,
                cos_cutoff,
                cutoff,
                inv_transition,
                area,
                radius,
                tri_first,
                tri_count,
                prim,
                prim_kind,
                texture,
                dist_offset,
                dist_width,
                dist_height,
                to_world_x,
                to_world_y,
                to_world_z
            ),
            rust_layout!(
                TextureRecord,
                kind,
                offset,
                width,
                height,
                flags,
                octaves,
                seed,
                pad0,
                color0,
                frequency,
                color1,
                variation,
                to_uv_u,
                to_uv_v
            ),
            rust_layout!(AliasEntry, prob, alias, pmf, prim),
            rust_layout!(
                Frame,
                camera_to_world,
                tan_half_fov,
                near_clip,
                far_clip,
                width,
                height,
                seed,
                point_light_count,
                ao_max_t,
                ao_uniform,
                max_depth,
                emitter_count,
                rr_depth,
                env_emitter,
                hide_emitters,
                camera_medium,
                sampler_kind,
                sample_count,
                sampler_res_x,
                sampler_res_y,
                sampler_flags,
                sampler_width,
                sampler_height,
                emitter_strata,
                emitter_prims,
                photon_alias,
                pad0,
                pad1,
                pad2
            ),
            rust_layout!(
                PathState,
                throughput,
                pixel,
                radiance,
                sample_index,
                bsdf_pdf,
                flags,
                eta_scale,
                medium
            ),
            rust_layout!(RayItem, origin, path, dir, tmax),
            rust_layout!(HitItem, t, u, v, prim),
            rust_layout!(ShadowItem, origin, path, dir, tmax, contribution, medium),
            rust_layout!(
                MediumRecord,
                sigma_t,
                kind,
                albedo,
                g,
                world_to_grid,
                res,
                data,
                maj_res,
                maj_data,
                majorant,
                channels,
                flags,
                albedo_data
            ),
            rust_layout!(
                Counters,
                ray_count,
                rays_traced,
                discarded,
                deferred,
                deferred_total,
                head_pad,
                tails
            ),
            rust_layout!(
                DispatchArgs,
                rays,
                shadows,
                hits,
                misses,
                deferred_rays,
                deferred_shadows
            ),
            rust_layout!(
                Push,
                path_count,
                pixel_base,
                sample_base,
                depth,
                queue_in,
                capacity,
                sample_slot,
                film_row,
                film_rows,
                frame_index,
                pad1,
                pad2
            ),
            rust_layout!(
                FilmParams,
                region_x,
                region_y,
                region_width,
                region_height,
                crop_x,
                crop_y,
                crop_width,
                crop_height,
                key_x,
                key_y,
                key_width,
                reach,
                slots,
                coverage,
                pad0,
                pad1,
                filter_params
            ),
            rust_layout!(Photon, position, path, power, wi),
            rust_layout!(PhotonPath, power, index, start_power, stored, pad0, pad1),
            rust_layout!(
                PhotonParams,
                scene_center,
                scene_radius,
                cell_size,
                inv_cell_size,
                table_mask,
                capacity,
                radius,
                gather_scale,
                emission_scale,
                path_limit,
                store_first,
                max_bounces,
                iteration,
                first_pixel
            ),
            rust_layout!(PhotonCounters, stored, max_radius, pad0, pad1),
            rust_layout!(VisiblePoint, p, bsdf, wo, u, n, v, beta, alpha2, n0, flags),
            rust_layout!(SppmPixel, tau, radius, ld, n, phi, m),
            rust_layout!(TonemapPush, width, height, scale, luminance),
        ];
        for (name, fields, size) in &rust {
            let (gfields, gsize) = glsl
                .get(name)
                .unwrap_or_else(|| panic!("struct {name} is missing from layout.glsl"));
            assert_eq!(
                gfields, fields,
                "fields or offsets of {name} differ between Rust and GLSL"
            );
            assert_eq!(gsize, size, "size of {name} differs between Rust and GLSL");
        }
        assert_eq!(
            glsl.len(),
            rust.len(),
            "layout.glsl has structs the Rust side does not check"
        );
    }

    #[test]
    fn parser_applies_std430_rules() {
        let g = parse_glsl("struct A { float a; vec3 b; uint c[2]; vec2 d; };");
        let (fields, size) = &g["A"];
        let offsets: Vec<usize> = fields.iter().map(|f| f.1).collect();
        assert_eq!(offsets, vec![0, 16, 28, 40]);
        assert_eq!(*size, 48);
    }

    /// Asserts that layout.glsl defines each `name` as `value` (`#define NAME 4u`).
    fn assert_glsl_defines(defines: &[(&str, u32)]) {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders/scene/layout.glsl");
        let src = std::fs::read_to_string(path).expect("read layout.glsl");
        for (name, value) in defines {
            assert!(
                src.contains(&format!("#define {name} {value}u\n")),
                "{name} = {value} is not in layout.glsl"
            );
        }
    }

    #[test]
    fn emitter_kinds_match_glsl() {
        assert_glsl_defines(&[
            ("EMITTER_POINT", EMITTER_POINT),
            ("EMITTER_AREA", EMITTER_AREA),
            ("EMITTER_CONSTANT", EMITTER_CONSTANT),
            ("EMITTER_SPOT", EMITTER_SPOT),
            ("EMITTER_ENVMAP", EMITTER_ENVMAP),
            ("EMITTER_KIND_BIT_SPHERE_AREA", EMITTER_KIND_BIT_SPHERE_AREA),
            (
                "EMITTER_KIND_BIT_QUADRIC_AREA",
                EMITTER_KIND_BIT_QUADRIC_AREA,
            ),
            (
                "EMITTER_KIND_BIT_TEXTURE_SAMPLED",
                EMITTER_KIND_BIT_TEXTURE_SAMPLED,
            ),
            (
                "EMITTER_KIND_BIT_TEXTURE_SPHERE",
                EMITTER_KIND_BIT_TEXTURE_SPHERE,
            ),
        ]);
    }

    #[test]
    fn texture_kinds_and_features_match_glsl() {
        assert_glsl_defines(&[
            ("TEXTURE_BITMAP", TEXTURE_BITMAP),
            ("TEXTURE_CHECKERBOARD", TEXTURE_CHECKERBOARD),
            ("TEXTURE_NOISE", TEXTURE_NOISE),
            ("TEXTURE_MARBLE", TEXTURE_MARBLE),
            ("TEXTURE_NEAREST", TEXTURE_NEAREST),
            ("TEXTURE_WRAP_SHIFT", TEXTURE_WRAP_SHIFT),
            ("TEXTURE_WRAP_REPEAT", TEXTURE_WRAP_REPEAT),
            ("TEXTURE_WRAP_MIRROR", TEXTURE_WRAP_MIRROR),
            ("TEXTURE_WRAP_CLAMP", TEXTURE_WRAP_CLAMP),
            ("TEXTURE_FEATURE_BSDF", TEXTURE_FEATURE_BSDF),
            ("TEXTURE_FEATURE_NORMALMAP", TEXTURE_FEATURE_NORMALMAP),
            ("TEXTURE_FEATURE_ENVMAP", TEXTURE_FEATURE_ENVMAP),
            ("TEXTURE_FEATURE_AREA", TEXTURE_FEATURE_AREA),
            ("TEXTURE_FEATURE_LOOKUP_LOOP", TEXTURE_FEATURE_LOOKUP_LOOP),
            ("TEXTURE_FEATURE_PARAM_SHIFT", TEXTURE_FEATURE_PARAM_SHIFT),
        ]);
    }

    #[test]
    fn medium_and_surface_flags_match_glsl() {
        assert_glsl_defines(&[
            ("SURFACE_FEATURE_SPHERES", SURFACE_FEATURE_SPHERES),
            ("SURFACE_FEATURE_NORMALS", SURFACE_FEATURE_NORMALS),
            ("SURFACE_FEATURE_UVS", SURFACE_FEATURE_UVS),
            ("SURFACE_FEATURE_DISKS", SURFACE_FEATURE_DISKS),
            ("SURFACE_FEATURE_CYLINDERS", SURFACE_FEATURE_CYLINDERS),
            ("PRIM_TRIANGLE", PRIM_TRIANGLE),
            ("PRIM_SPHERE", PRIM_SPHERE),
            ("PRIM_DISK", PRIM_DISK),
            ("PRIM_CYLINDER", PRIM_CYLINDER),
            ("SHAPE_HAS_NORMALS", SHAPE_HAS_NORMALS),
            ("SHAPE_HAS_UVS", SHAPE_HAS_UVS),
            ("SHAPE_FLIP_NORMALS", SHAPE_FLIP_NORMALS),
            ("SHAPE_NULL_BSDF", SHAPE_NULL_BSDF),
            ("SHAPE_MEDIUM_TRANSITION", SHAPE_MEDIUM_TRANSITION),
            ("SHAPE_THIN_DIELECTRIC", SHAPE_THIN_DIELECTRIC),
            ("SHAPE_MIRRORED", SHAPE_MIRRORED),
            ("MEDIUM_HOMOGENEOUS", MEDIUM_HOMOGENEOUS),
            ("MEDIUM_GRID", MEDIUM_GRID),
            ("MEDIUM_SAMPLE_EMITTERS", MEDIUM_SAMPLE_EMITTERS),
            ("MEDIUM_ALBEDO_RGB", MEDIUM_ALBEDO_RGB),
            ("MEDIUM_DENSITY_PACKED", MEDIUM_DENSITY_PACKED),
            ("MEDIUM_FEATURE_HOMOGENEOUS", MEDIUM_FEATURE_HOMOGENEOUS),
            ("MEDIUM_FEATURE_PACKED1", MEDIUM_FEATURE_PACKED1),
            ("MEDIUM_FEATURE_PACKED3", MEDIUM_FEATURE_PACKED3),
            ("MEDIUM_FEATURE_DENSITY_WORDS", MEDIUM_FEATURE_DENSITY_WORDS),
            ("MEDIUM_FEATURE_WORDS1", MEDIUM_FEATURE_WORDS1),
            ("MEDIUM_FEATURE_WORDS3", MEDIUM_FEATURE_WORDS3),
            ("MEDIUM_FEATURE_ALBEDO_GRID", MEDIUM_FEATURE_ALBEDO_GRID),
            ("MEDIUM_FEATURE_GRIDS", MEDIUM_FEATURE_GRIDS),
        ]);
    }

    #[test]
    fn film_constants_match_glsl() {
        assert_glsl_defines(&[
            ("PATH_DELTA", PATH_DELTA),
            ("PATH_THIN_REFLECT", PATH_THIN_REFLECT),
            ("PATH_COVERED", PATH_COVERED),
            ("FILTER_BOX", FILTER_BOX),
            ("FILTER_TENT", FILTER_TENT),
            ("FILTER_GAUSSIAN", FILTER_GAUSSIAN),
            ("FILTER_MITCHELL", FILTER_MITCHELL),
            ("FILTER_LANCZOS", FILTER_LANCZOS),
            ("FILM_SAMPLE_VALID", FILM_SAMPLE_VALID),
            ("FILM_SAMPLE_COVERED", FILM_SAMPLE_COVERED),
        ]);
    }

    #[test]
    fn sampler_constants_match_glsl() {
        assert_glsl_defines(&[
            ("SAMPLER_INDEPENDENT", SAMPLER_INDEPENDENT),
            ("SAMPLER_STRATIFIED", SAMPLER_STRATIFIED),
            ("SAMPLER_MULTIJITTER", SAMPLER_MULTIJITTER),
            ("SAMPLER_ORTHOGONAL", SAMPLER_ORTHOGONAL),
            ("SAMPLER_LDSAMPLER", SAMPLER_LDSAMPLER),
            ("SAMPLER_ZSOBOL", SAMPLER_ZSOBOL),
            ("SAMPLER_SOBOL", SAMPLER_SOBOL),
            ("SAMPLER_PMJ02BN", SAMPLER_PMJ02BN),
            ("SAMPLER_ORTHOGONAL_BUSH", SAMPLER_ORTHOGONAL_BUSH),
            ("SAMPLER_JITTER", SAMPLER_JITTER),
            ("SAMPLER_STRENGTH_SHIFT", SAMPLER_STRENGTH_SHIFT),
            ("SAMPLER_SCRAMBLE_SHIFT", SAMPLER_SCRAMBLE_SHIFT),
            ("SAMPLER_SCRAMBLE_NONE", SAMPLER_SCRAMBLE_NONE),
            ("SAMPLER_SCRAMBLE_XOR", SAMPLER_SCRAMBLE_XOR),
            ("SAMPLER_SCRAMBLE_FAST_OWEN", SAMPLER_SCRAMBLE_FAST_OWEN),
            ("SAMPLER_SCRAMBLE_OWEN", SAMPLER_SCRAMBLE_OWEN),
        ]);
    }

    #[test]
    fn photon_flags_match_glsl() {
        assert_glsl_defines(&[("VISIBLE_POINT_NORMAL_MAP", VISIBLE_POINT_NORMAL_MAP)]);
    }

    #[test]
    fn bsdf_flags_match_glsl() {
        assert_glsl_defines(&[
            ("BSDF_TWOSIDED", BSDF_TWOSIDED),
            ("BSDF_NONLINEAR", BSDF_NONLINEAR),
            ("BSDF_NORMALMAP_FLIP", BSDF_NORMALMAP_FLIP),
            ("BSDF_NORMALMAP_SHADOWING", BSDF_NORMALMAP_SHADOWING),
        ]);
    }

    #[test]
    fn workgroup_size_matches_glsl() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders/queue/wavefront.glsl");
        let src = std::fs::read_to_string(path).expect("read wavefront.glsl");
        assert!(src.contains(&format!("#define WORKGROUP_SIZE {WORKGROUP_SIZE}\n")));
    }
}
