//! Every record the host shares with the kernels, declared once.
//!
//! Each `gpu_record!` struct below is `#[repr(C)]` with explicit padding to GLSL's
//! std430 rules and names, beside every field's Rust type, its GLSL type. From this
//! one declaration come the Rust struct (bytemuck `Pod`) and, through build.rs (which
//! compiles this file too, `build/records.rs`), the GLSL side in
//! `$OUT_DIR/glsl/generated/records.glsl`: the struct, and for each record whose size is
//! whole 16-byte texels the macros that load and store it a texel at a time
//! (`T_LOAD`, `T_STORE`, `T_WORDk`, `T_TEXELS`; `RECORDS(X)` lists those records).
//! The constants that go with the records are in `layout.rs`.
//!
//! This file depends on nothing but `core` and bytemuck, so build.rs can include it.

#[cfg(doc)]
use super::layout::*;
use bytemuck::{Pod, Zeroable};
use core::mem::{offset_of, size_of};

/// A record's layout, as build.rs and the layout tests read it.
#[derive(Clone, Copy, Debug)]
pub struct Record {
    pub name: &'static str,
    /// Its doc comment, a line per `///` line.
    pub doc: &'static str,
    /// `size_of` the Rust struct, in bytes.
    pub size: usize,
    pub fields: &'static [Field],
}

/// One field of a [`Record`].
#[derive(Clone, Copy, Debug)]
pub struct Field {
    pub name: &'static str,
    /// Its GLSL type: `float`, `uint`, `int`, `vec2`..`vec4`, `uvec3`.., `mat4`.
    pub glsl: &'static str,
    /// Elements of a GLSL array (`vec4 table[8]`: 8); 0 for a field that is none.
    pub len: usize,
    /// `offset_of` the Rust field, in bytes.
    pub offset: usize,
    /// `size_of` the Rust field, in bytes.
    pub size: usize,
    pub doc: &'static str,
}

/// Declares GPU records: each `pub struct` (doc comment, then one `#[derive]`)
/// becomes a `#[repr(C)]` struct with an associated `RECORD` describing it, and
/// `RECORDS` lists them all. A field is written `pub name: RustType => glsl_type`,
/// or `=> glsl_type[N]` for a GLSL array.
macro_rules! gpu_record {
    ($(
        $(#[doc = $doc:literal])*
        #[derive($($derive:ident),*)]
        pub struct $name:ident {
            $(
                $(#[doc = $fdoc:literal])*
                pub $field:ident: $ty:ty => $glsl:ident $([$len:literal])?
            ),* $(,)?
        }
    )*) => {
        $(
            $(#[doc = $doc])*
            #[repr(C)]
            #[derive($($derive),*)]
            pub struct $name {
                $(
                    $(#[doc = $fdoc])*
                    pub $field: $ty,
                )*
            }

            impl $name {
                /// This record's layout (`gpu_record!`).
                pub const RECORD: Record = Record {
                    name: stringify!($name),
                    doc: concat!($($doc, "\n",)*),
                    size: size_of::<$name>(),
                    fields: &[$(Field {
                        name: stringify!($field),
                        glsl: stringify!($glsl),
                        len: gpu_record!(@len $($len)?),
                        offset: offset_of!($name, $field),
                        size: size_of::<$ty>(),
                        doc: concat!($($fdoc, "\n",)*),
                    }),*],
                };
            }
        )*

        /// Every record, in declaration order.
        pub const RECORDS: &[Record] = &[$($name::RECORD),*];
    };
    (@len) => { 0 };
    (@len $len:literal) => { $len };
}

/// Words of [`BsdfRecord::table`] (each two 16-bit entries).
pub const BSDF_TABLE_SIZE: usize = 32;

gpu_record! {
    /// A BVH2 node holding the bounds of both its children (Aila and Laine 2009,
    /// "Understanding the Efficiency of Ray Traversal on GPUs"): one fetch tests both.
    ///
    /// For each child: `count == 0` means `index` is an inner node in the node array;
    /// `count > 0` means a leaf holding primitives `index .. index + count` of the
    /// primitive array. An absent child has an empty box (min = +inf, max = -inf).
    /// The root is node 0.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct BvhNode {
        pub left_min: [f32; 3] => vec3,
        pub left_index: u32 => uint,
        pub left_max: [f32; 3] => vec3,
        pub left_count: u32 => uint,
        pub right_min: [f32; 3] => vec3,
        pub right_index: u32 => uint,
        pub right_max: [f32; 3] => vec3,
        pub right_count: u32 => uint,
    }

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
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct Prim {
        pub p0: [f32; 3] => vec3,
        pub shape: u32 => uint,
        pub p1: [f32; 3] => vec3,
        pub index: u32 => uint,
        pub p2: [f32; 3] => vec3,
        pub kind: u32 => uint,
    }

    /// Per-shape data: what a hit on primitive `Prim::shape` shades with. Shapes are the
    /// scene's meshes in order, then its spheres.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct ShapeRecord {
        /// Index into the BSDF records.
        pub bsdf: u32 => uint,
        /// Index into the emitter records, or `NONE`.
        pub emitter: u32 => uint,
        /// `SHAPE_*` flags.
        pub flags: u32 => uint,
        /// The media on both sides ([`shape_media`]): interior medium in the low 16 bits,
        /// exterior in the high 16, [`MEDIUM_NONE16`] for none. Used where
        /// [`SHAPE_MEDIUM_TRANSITION`] is set.
        pub media: u32 => uint,
    }

    /// A participating medium. Homogeneous: `sigma_t` is the extinction per unit length
    /// (scale applied), `albedo` the single-scattering albedo. Grid: the extinction at a
    /// point is `sigma_t` (the scale, per channel) times the trilinearly interpolated
    /// density grid of `res` voxels and `channels` channels at `data` in the grid buffer
    /// (in the packed-density buffer with [`MEDIUM_DENSITY_PACKED`]);
    /// `world_to_grid` maps world space to the grid's unit cube. A coarse grid of
    /// `maj_res` cells at `maj_data` in the majorant buffer bounds the extinction (max
    /// over channels) within each cell; `majorant` bounds it everywhere. `g`: the
    /// Henyey-Greenstein asymmetry (0: isotropic).
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct MediumRecord {
        pub sigma_t: [f32; 3] => vec3,
        pub kind: u32 => uint,
        pub albedo: [f32; 3] => vec3,
        pub g: f32 => float,
        pub world_to_grid: [[f32; 4]; 4] => mat4,
        pub res: [u32; 3] => uvec3,
        pub data: u32 => uint,
        pub maj_res: [u32; 3] => uvec3,
        pub maj_data: u32 => uint,
        pub majorant: f32 => float,
        pub channels: u32 => uint,
        pub flags: u32 => uint,
        /// `NONE`, or the offset in the grid buffer of an albedo grid, its header
        /// (`scene::medium::record::albedo_grid_header`: its own placement and
        /// resolution) then its values ([`MEDIUM_ALBEDO_RGB`]: 3 channels, else 1).
        pub albedo_data: u32 => uint,
    }

    /// A triangle's vertex indices into the [`Vertex`] array (global numbering), padded
    /// to one 16-byte texel.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct TriangleRecord {
        pub v0: u32 => uint,
        pub v1: u32 => uint,
        pub v2: u32 => uint,
        pub pad0: u32 => uint,
    }

    /// Shading attributes of a mesh vertex (positions live in [`Prim`]s), two texels. The
    /// tangent ∂p/∂u is made per triangle at a hit (surface.glsl), as Mitsuba does.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct Vertex {
        pub nx: f32 => float,
        pub ny: f32 => float,
        pub nz: f32 => float,
        pub u: f32 => float,
        pub v: f32 => float,
        pub pad0: u32 => uint,
        pub pad1: u32 => uint,
        pub pad2: u32 => uint,
    }

    /// A BSDF's parameters; made from a `scene::Bsdf` by `BsdfRecord::from`. Fields by kind:
    ///
    /// | kind | fields read |
    /// |------|-------------|
    /// | diffuse | `reflectance` |
    /// | conductor | `specular`, `cond_eta`, `cond_k` |
    /// | roughconductor | + `distribution`, `alpha_u`, `alpha_v` |
    /// | dielectric | `specular`, `transmittance`, `eta` |
    /// | roughdielectric | + `distribution`, `alpha_u`, `alpha_v` |
    /// | plastic | `reflectance`, `specular`, `eta`, `specular_weight`, `internal` (F_dr inside) |
    /// | roughplastic | + `distribution`, `alpha_u` (= `alpha_v`), `table` (coating transmittance at cos θ = i/63, 64 unorm16 entries, two a word), `internal` (R_int) |
    /// | Nori microfacet | `reflectance` (kd), `specular_weight` (ks), `eta`, `alpha_u` |
    /// | pplastic | `reflectance`, `specular`, `eta`, `specular_weight`, `distribution`, `alpha_u`, `alpha_v` |
    /// | principled, principledthin | `reflectance` (base_color), `eta`, `table` (scalar parameters, their textures: `scene::bsdf::principled`) |
    /// | measured | `table[0]`: where its tables start in the texel words, its file's hash (`scene::bsdf::measured`) |
    ///
    /// `flags`: [`BSDF_TWOSIDED`], [`BSDF_NONLINEAR`], [`BSDF_NORMALMAP_FLIP`],
    /// [`BSDF_NORMALMAP_SHADOWING`], [`BSDF_TABLE_TEXTURES`].
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct BsdfRecord {
        pub reflectance: [f32; 3] => vec3,
        pub kind: u32 => uint,
        pub specular: [f32; 3] => vec3,
        pub flags: u32 => uint,
        pub transmittance: [f32; 3] => vec3,
        pub eta: f32 => float,
        pub cond_eta: [f32; 3] => vec3,
        pub alpha_u: f32 => float,
        pub cond_k: [f32; 3] => vec3,
        pub alpha_v: f32 => float,
        pub distribution: u32 => uint,
        pub specular_weight: f32 => float,
        pub internal: f32 => float,
        /// Texture of `eta` (index + 1, 0: `eta` applies), read as Mitsuba's `eval_1`
        /// (pplastic's textured `eta`).
        pub tex_eta: u32 => uint,
        pub table: [[u32; 4]; BSDF_TABLE_SIZE / 4] => uvec4[8],
        /// Textures replacing the constants above at a hit, as texture index + 1 (0: the
        /// constant applies): `reflectance`, `specular`, `transmittance` (colors),
        /// `alpha_u`, `alpha_v` (luminance of the texture).
        pub tex_reflectance: u32 => uint,
        pub tex_specular: u32 => uint,
        pub tex_transmittance: u32 => uint,
        pub tex_alpha_u: u32 => uint,
        pub tex_alpha_v: u32 => uint,
        /// Mitsuba `normalmap` around the model: its texture index + 1, or 0.
        pub normal_map: u32 => uint,
        /// Textures of a conductor's `eta` and `k` (index + 1, 0: `cond_eta` and
        /// `cond_k` apply).
        pub tex_cond_eta: u32 => uint,
        pub tex_cond_k: u32 => uint,
    }

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
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct EmitterRecord {
        pub position: [f32; 3] => vec3,
        pub kind: u32 => uint,
        pub radiance: [f32; 3] => vec3,
        pub shape: u32 => uint,
        pub axis: [f32; 3] => vec3,
        pub cos_cutoff: f32 => float,
        pub cutoff: f32 => float,
        pub inv_transition: f32 => float,
        pub area: f32 => float,
        pub radius: f32 => float,
        pub tri_first: u32 => uint,
        pub tri_count: u32 => uint,
        pub prim: u32 => uint,
        pub prim_kind: u32 => uint,
        pub texture: u32 => uint,
        pub dist_offset: u32 => uint,
        pub dist_width: u32 => uint,
        pub dist_height: u32 => uint,
        pub to_world_x: [f32; 4] => vec4,
        pub to_world_y: [f32; 4] => vec4,
        pub to_world_z: [f32; 4] => vec4,
    }

    /// A texture (`scene::Texture`). Every texture's lookups first map the surface uv by
    /// the affine `to_uv` (rows `to_uv_u`, `to_uv_v`: u' = x u + y v + z).
    ///
    /// Bitmap: `width` x `height` RGB texels (linear) at `offset` in the texel buffer, row
    /// 0 at v = 0, `flags` for filter and wrap. Checkerboard: `color0`, `color1`. Noise
    /// and marble: `color0`, `color1`, `frequency`, `octaves`, `seed`, and for marble
    /// `variation` (see texture.glsl).
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct TextureRecord {
        pub kind: u32 => uint,
        pub offset: u32 => uint,
        pub width: u32 => uint,
        pub height: u32 => uint,
        pub flags: u32 => uint,
        pub octaves: u32 => uint,
        pub seed: u32 => uint,
        pub pad0: u32 => uint,
        pub color0: [f32; 3] => vec3,
        pub frequency: f32 => float,
        pub color1: [f32; 3] => vec3,
        pub variation: f32 => float,
        pub to_uv_u: [f32; 4] => vec4,
        pub to_uv_v: [f32; 4] => vec4,
    }

    /// One entry of an alias table (Walker 1977; Vose 1991): pick `i` uniformly, keep it
    /// with probability `prob`, else take `alias`. `pmf` is the probability of choosing
    /// entry `i` in the end; `prim` is the BVH primitive of a light triangle (tables of
    /// mesh emitters), and in the emitter table the cumulative pmf of the entries before
    /// (f32 bits, `render::alias::set_cdf`), for sampling by inversion.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct AliasEntry {
        pub prob: f32 => float,
        pub alias: u32 => uint,
        pub pmf: f32 => float,
        pub prim: u32 => uint,
    }

    /// Everything constant over one render: camera, film, integrator parameters.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct Frame {
        /// Camera-to-world, column-major.
        pub camera_to_world: [[f32; 4]; 4] => mat4,
        /// tan(fov/2) along x and y: the image plane at z = 1 spans ±these.
        pub tan_half_fov: [f32; 2] => vec2,
        pub near_clip: f32 => float,
        pub far_clip: f32 => float,
        pub width: u32 => uint,
        pub height: u32 => uint,
        pub seed: u32 => uint,
        /// Number of point emitters (they come first in the emitter records).
        pub point_light_count: u32 => uint,
        /// Ambient occlusion: occluders farther than this are ignored.
        pub ao_max_t: f32 => float,
        /// Ambient occlusion: 0 = cosine-weighted, 1 = uniform hemisphere sampling.
        pub ao_uniform: u32 => uint,
        /// Longest path in segments (Mitsuba's `max_depth`), u32::MAX for unbounded.
        pub max_depth: u32 => uint,
        pub emitter_count: u32 => uint,
        /// Russian roulette starts at this path depth (segments).
        pub rr_depth: u32 => uint,
        /// The constant environment emitter, or `NONE`.
        pub env_emitter: u32 => uint,
        /// 1: camera rays do not see emitters.
        pub hide_emitters: u32 => uint,
        /// The medium camera rays start in (Mitsuba's sensor `<medium>`), or `NONE`.
        pub camera_medium: u32 => uint,
        /// `SAMPLER_*`: which sampler draws the random numbers (shaders/sampler/).
        pub sampler_kind: u32 => uint,
        /// Samples of one pass of the sampler (its pattern's size; later sample indices
        /// start new passes).
        pub sample_count: u32 => uint,
        /// The sampler's strata: see [`crate::scene::sampler::SampleCount`].
        pub sampler_res_x: u32 => uint,
        pub sampler_res_y: u32 => uint,
        /// `SAMPLER_JITTER`, strength << `SAMPLER_STRENGTH_SHIFT`, `SAMPLER_SCRAMBLE_*` <<
        /// `SAMPLER_SCRAMBLE_SHIFT`.
        pub sampler_flags: u32 => uint,
        /// The grid the sampler's pixel keys index (the film with its sampled border,
        /// `film_pixel_key`): zsobol reads a key as (key % width, key / width).
        pub sampler_width: u32 => uint,
        pub sampler_height: u32 => uint,
        /// Strata of the first coordinate of a 2-D sample in one pass of the sampler, over
        /// which the emitter choice hands out whole strata (shaders/emitter/emitter.glsl,
        /// [`crate::render::sampler::emitter_strata`]); 0: the choice inverts the cdf of
        /// the emitters' sampling weights.
        pub emitter_strata: u32 => uint,
        /// The prims (slots of the BVH's prim array) of every area emitter, where they are
        /// at most [`MAX_EMITTER_PRIMS`]: bounces that only end paths then intersect them
        /// alone (shaders/integrator/path_emitted.glsl). Four to a word.
        pub emitter_prims: [[u32; 4]; 4] => uvec4[4],
        /// Where photon emission's emitter table (by power) starts among the alias
        /// entries (the one of emitter sampling, uniform, starts at 0).
        pub photon_alias: u32 => uint,
        /// `CAMERA_*` (`scene::Projection`): how shaders/sensor/camera.glsl makes rays.
        pub camera_kind: u32 => uint,
        /// A thin lens's aperture radius and focus distance (Mitsuba `thinlens`).
        pub aperture_radius: f32 => float,
        pub focus_distance: f32 => float,
        /// A `batch` sensor's children (scene::Camera::batch), used where
        /// SCENE_SENSOR_BATCH > 1: child i's camera-to-world (columns 4i..4i+3), its
        /// (tan_half_fov.x, tan_half_fov.y, near_clip, far_clip), and its (CAMERA_*,
        /// aperture radius bits, focus distance bits, 0).
        pub batch_to_world: [[f32; 4]; 32] => vec4[32],
        pub batch_view: [[f32; 4]; 8] => vec4[8],
        pub batch_lens: [[u32; 4]; 8] => uvec4[8],
    }

    /// The state of one path of the wavefront, indexed by path slot. In the paths buffer
    /// its three texels lie in three arrays, texel k of path i at k x capacity + i
    /// (`path_load` in shaders/queue/wavefront.glsl says why).
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct PathState {
        pub throughput: [f32; 3] => vec3,
        /// The pixel key the path's random numbers are drawn with (the full film's pixel,
        /// `render::film::FilmGeometry::key`).
        pub pixel: u32 => uint,
        pub radiance: [f32; 3] => vec3,
        pub sample_index: u32 => uint,
        /// Solid-angle pdf with which the BSDF chose the current ray (for MIS when it hits
        /// an emitter).
        pub bsdf_pdf: f32 => float,
        /// `PATH_*` flags.
        pub flags: u32 => uint,
        /// Product of η_t²/η_i² over the refractions so far: the factor by which they
        /// scaled the throughput's radiance (1/η² each) undone, so that Russian roulette
        /// does not kill paths inside glass for carrying less radiance (PBR 4th ed.,
        /// sec. 13.1, `etaScale`; Mitsuba's path integrator likewise).
        pub eta_scale: f32 => float,
        /// The medium the current ray travels in, or `NONE`.
        pub medium: u32 => uint,
    }

    /// A ray waiting for the `intersect` stage.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct RayItem {
        pub origin: [f32; 3] => vec3,
        pub path: u32 => uint,
        pub dir: [f32; 3] => vec3,
        pub tmax: f32 => float,
    }

    /// The closest hit of the ray at the same queue position (`prim == NONE`: a miss).
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct HitItem {
        pub t: f32 => float,
        pub u: f32 => float,
        pub v: f32 => float,
        pub prim: u32 => uint,
    }

    /// A shadow ray: if nothing blocks it, `contribution` is added to its path's
    /// radiance.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct ShadowItem {
        pub origin: [f32; 3] => vec3,
        pub path: u32 => uint,
        pub dir: [f32; 3] => vec3,
        pub tmax: f32 => float,
        pub contribution: [f32; 3] => vec3,
        /// The medium the shadow ray starts in, or `NONE`.
        pub medium: u32 => uint,
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
    #[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
    pub struct Counters {
        pub ray_count: [u32; 2] => uint[2],
        /// Rays traced in this batch (extension and shadow rays).
        pub rays_traced: u32 => uint,
        /// Samples dropped at accumulation because they were NaN or infinite.
        pub discarded: u32 => uint,
        /// Items the fast kernels of a bounce left to their full twins (deferral.glsl):
        /// `DEFERRED_RAYS` (shade's rays) and `DEFERRED_SHADOWS` (shadow rays).
        pub deferred: [u32; 2] => uint[2],
        /// Deferred items of the batch's bounces before the current lists (queue_args
        /// adds each bounce's as it empties them).
        pub deferred_total: u32 => uint,
        pub head_pad: [u32; 25] => uint[25],
        /// Each segment's append counters, 32 words (128 bytes) apart: `TAIL_*` in
        /// layout.glsl.
        pub tails: [u32; 64] => uint[64],
    }

    /// Indirect dispatch arguments for each queue, written on the GPU from [`Counters`].
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct DispatchArgs {
        pub rays: [u32; 3] => uint[3],
        pub shadows: [u32; 3] => uint[3],
        /// The partitioned bounce's hits and misses (`shade_args`).
        pub hits: [u32; 3] => uint[3],
        pub misses: [u32; 3] => uint[3],
        /// The items a bounce's fast shade and shadow deferred (deferral.glsl).
        pub deferred_rays: [u32; 3] => uint[3],
        pub deferred_shadows: [u32; 3] => uint[3],
    }

    /// Push constants of the wavefront kernels.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct Push {
        /// Paths in this batch.
        pub path_count: u32 => uint,
        /// Path `p` of the batch is global sample number `pixel_base + p`, i.e. pixel
        /// `(pixel_base + p) % pixels` of sample `sample_base + (pixel_base + p) / pixels`.
        pub pixel_base: u32 => uint,
        pub sample_base: u32 => uint,
        /// Current bounce (0 = camera rays).
        pub depth: u32 => uint,
        /// Ray queue read this bounce (0 or 1); the other one is written.
        pub queue_in: u32 => uint,
        /// Path slots allocated: ray queue `q` starts at item `q * capacity`.
        pub capacity: u32 => uint,
        /// The film's sample slot of path 0 of this batch (`render::film`).
        pub sample_slot: u32 => uint,
        /// `film_gather`: the first crop row it gathers, and how many.
        pub film_row: u32 => uint,
        pub film_rows: u32 => uint,
        /// Always 0: the index of the frame's parameters in their uniform block
        /// (shaders/queue/wavefront.glsl says why it is not a constant).
        pub frame_index: u32 => uint,
        pub pad1: u32 => uint,
        pub pad2: u32 => uint,
    }

    /// Push constants of `tonemap` (the viewer's display of the film): the crop window's
    /// size, the linear scale 2^exposure, and whether to show luminance (grey) rather
    /// than RGB, as the render's PNG of a luminance film is grey.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct TonemapPush {
        pub width: u32 => uint,
        pub height: u32 => uint,
        pub scale: f32 => float,
        pub luminance: u32 => uint,
    }

    /// Push constants of `letterbox` (the viewer's window, src/gpu/letterbox.rs): the
    /// window's size; where the picture lies in it (x, y, width, height: the letterbox);
    /// the picture's size; picture pixels per window pixel in x and y; the pixel of the
    /// bars around it, as the window stores it; and whether the window's bytes are
    /// B, G, R, A (else R, G, B, A).
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct LetterboxPush {
        pub window_width: u32 => uint,
        pub window_height: u32 => uint,
        pub x: u32 => uint,
        pub y: u32 => uint,
        pub width: u32 => uint,
        pub height: u32 => uint,
        pub picture_width: u32 => uint,
        pub picture_height: u32 => uint,
        pub step_x: f32 => float,
        pub step_y: f32 => float,
        pub bar: u32 => uint,
        pub bgra: u32 => uint,
    }

    /// The film's parameters (`render::film::FilmGeometry`): the sampled region (the
    /// crop window and the pixels around it whose samples its filter reaches, within the
    /// film or, with `sample_border`, the film and its border), the crop window kept, the
    /// pixel keys of the random numbers (the full sampled film's row-major index, so a
    /// crop draws the same numbers as the full render), the filter's reach in pixels,
    /// the sample slots of the ring, whether every camera path counts as covered, and the
    /// filter's parameters (`shaders/film/filter.glsl`): tent (1 / radius); Gaussian
    /// (-1 / 2σ², exp(-r² / 2σ²)); Mitchell (B, C, 2 / radius); Lanczos (lobes).
    /// Pixel coordinates are the full film's, the top-left pixel (0, 0).
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct FilmParams {
        pub region_x: i32 => int,
        pub region_y: i32 => int,
        pub region_width: u32 => uint,
        pub region_height: u32 => uint,
        pub crop_x: u32 => uint,
        pub crop_y: u32 => uint,
        pub crop_width: u32 => uint,
        pub crop_height: u32 => uint,
        pub key_x: i32 => int,
        pub key_y: i32 => int,
        pub key_width: u32 => uint,
        pub reach: u32 => uint,
        pub slots: u32 => uint,
        pub coverage: u32 => uint,
        pub pad0: u32 => uint,
        pub pad1: u32 => uint,
        pub filter_params: [f32; 4] => vec4,
    }

    /// Photon mapping (`src/render/photon`, `shaders/photon/`): one photon stored where a
    /// photon path met a non-delta surface. `power` is the flux it carries (W, RGB) and
    /// `wi` the unit direction it arrived from (towards its previous vertex), octahedral
    /// in two 16-bit snorms (`photon_dir_encode`, Cigolle et al. 2014, "A Survey of
    /// Efficient Representations for Independent Unit Vectors"). `path`: the index of
    /// its photon path in the emission sequence, which leaves out the photons of paths
    /// past the budget's cut ([`PhotonParams::path_limit`]).
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct Photon {
        pub position: [f32; 3] => vec3,
        pub path: u32 => uint,
        pub power: [f32; 3] => vec3,
        pub wi: u32 => uint,
    }

    /// The state of one photon path, by path slot of the wavefront (in the path-state
    /// buffer, which photon passes share with camera paths). `power`: the flux it carries
    /// now; `index`: its index in the emission sequence; `start_power`: the largest
    /// channel of its power at emission, against which Russian roulette weighs it;
    /// `stored`: photons it has stored (or, counting, would have stored).
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct PhotonPath {
        pub power: [f32; 3] => vec3,
        pub index: u32 => uint,
        pub start_power: f32 => float,
        pub stored: u32 => uint,
        pub pad0: u32 => uint,
        pub pad1: u32 => uint,
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
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct PhotonParams {
        pub scene_center: [f32; 3] => vec3,
        pub scene_radius: f32 => float,
        pub cell_size: f32 => float,
        pub inv_cell_size: f32 => float,
        pub table_mask: u32 => uint,
        pub capacity: u32 => uint,
        pub radius: f32 => float,
        pub gather_scale: f32 => float,
        pub emission_scale: f32 => float,
        pub path_limit: u32 => uint,
        pub store_first: u32 => uint,
        pub max_bounces: u32 => uint,
        pub iteration: u32 => uint,
        pub first_pixel: u32 => uint,
    }

    /// Counters of photon passes (descriptor set 2). `stored`: photons appended to the
    /// photon buffer (may exceed its capacity: the excess was dropped); `max_radius`:
    /// sppm's largest radius after an update, as the bits of a positive float (they order
    /// as the floats do, so `atomicMax` on them takes the largest).
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct PhotonCounters {
        pub stored: u32 => uint,
        pub max_radius: u32 => uint,
        pub pad0: u32 => uint,
        pub pad1: u32 => uint,
    }

    /// Where a camera path ends in a photon mapper: the first surface whose BSDF is not a
    /// delta, as the density estimate needs it. `bsdf` is its BSDF record ([`NONE`]: no
    /// visible point), `uv` where its textures are read; `wo` the unit direction towards
    /// the camera, `n` the shading normal (after a normal map) and `beta` the camera
    /// path's throughput, all world space. With [`VISIBLE_POINT_NORMAL_MAP`] in `flags`,
    /// `n0` is the unmapped shading normal and `alpha2` the normal map's shadowing
    /// roughness (`normal_map.glsl`).
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct VisiblePoint {
        pub p: [f32; 3] => vec3,
        pub bsdf: u32 => uint,
        pub wo: [f32; 3] => vec3,
        pub u: f32 => float,
        pub n: [f32; 3] => vec3,
        pub v: f32 => float,
        pub beta: [f32; 3] => vec3,
        pub alpha2: f32 => float,
        pub n0: [f32; 3] => vec3,
        pub flags: u32 => uint,
    }

    /// The state of one pixel of stochastic progressive photon mapping (pbrt-v4's
    /// `SPPMPixel`): `radius` of its visible points' gathers, `n` the photon count N of
    /// Hachisuka and Jensen 2009, `tau` the flux gathered so far (rescaled as the radius
    /// shrinks), `ld` the sum of the light its camera paths found directly (emission and
    /// emitter sampling), and `phi`, `m` what this iteration's photons added (Φ_i, M).
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct SppmPixel {
        pub tau: [f32; 3] => vec3,
        pub radius: f32 => float,
        pub ld: [f32; 3] => vec3,
        pub n: f32 => float,
        pub phi: [f32; 3] => vec3,
        pub m: u32 => uint,
    }
}

impl Default for Counters {
    fn default() -> Self {
        Self::zeroed()
    }
}
