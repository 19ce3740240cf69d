//! Every specialization constant of the kernels, by name, with one id across all of
//! them: the one table both sides read. build.rs generates the GLSL header
//! `generated/spec_constants.glsl` from it (one `SPEC_<NAME>` macro per constant,
//! which a kernel names with `SPEC(NAME);` to declare the constants it uses), and the
//! renderer sets constants by [`Spec`] ([`super::spec::SpecValues`]). A test reads
//! every kernel's SPIR-V and checks its `SpecId`s and names against this table.
//!
//! Plain data only: build.rs includes this file as a module of its own.

/// A specialization constant; its discriminant is its `constant_id` in every kernel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u32)]
pub enum Spec {
    Integrator = 0,
    BsdfKinds = 1,
    Textures = 2,
    HasMedia = 4,
    PrimKinds = 5,
    MediumFeatures = 6,
    ThinNull = 7,
    MisPower = 8,
    EmitterKinds = 9,
    SurfaceFeatures = 10,
    BvhDepth = 11,
    SamplerKind = 12,
    FilmAlpha = 13,
    ShadeLast = 14,
    ShadeRays = 15,
    EmitterPrims = 16,
    EmitterPrimKinds = 17,
    FlatPrims = 18,
    FlatKinds = 19,
    Deferral = 20,
    Partition = 21,
    SecondHits = 22,
    FirstEnds = 23,
    SecondEnds = 24,
    FilmFilter = 25,
    FilmFromPaths = 26,
    UniformEmitterChoice = 27,
    SppmAlpha = 28,
    ScanStage = 29,
    SecondFused = 30,
    Instances = 44,
    InstanceSlots = 45,
    SensorShape = 56,
    SensorBatch = 57,
    PtracerThinLens = 58,
    SubgroupsInOrder = 59,
    /// The AOVs of `aov.comp` (scene::integrator::aov): kinds 1-8, then 9-16.
    FilmAovsLo = 90,
    FilmAovsHi = 91,
    FilmMoment = 92,
    FilmAovSamples = 93,
    /// How the scene's arrays are split over bindings (`render::scene_parts`), set by
    /// the binding layout for every kernel that reads the scene: 64, then 65 + the
    /// array's binding for the arrays that may be split.
    ScenePartShift = 64,
    BvhNodeParts = 65,
    PrimParts = 66,
    TriangleParts = 68,
    VertexParts = 69,
    TexelParts = 74,
    DistParts = 75,
    GridParts = 77,
    GridPackedParts = 79,
}

impl Spec {
    /// Its `constant_id`.
    pub const fn id(self) -> u32 {
        self as u32
    }
}

/// The vertices of the first primitives a traversal tests in turn
/// (`accel::FlatPrims::vertices`), as constants of their own: `FLAT_P<k>_<i>`, word i
/// of p0, p1, p2 (x, y, z each) of primitive k, has id `FLAT_VERTEX_BASE + 9 k + i`,
/// for k below [`FLAT_VERTEX_PRIMS`]. A load every lane makes from one address costs
/// llvmpipe a bounds check per word; a constant costs nothing (docs/performance.md).
pub const FLAT_VERTEX_BASE: u32 = 100;
/// Primitives whose vertices the constants hold (`accel::FLAT_STEPS`, the steps of
/// bvh.glsl's `bvh_trace_flat`).
pub const FLAT_VERTEX_PRIMS: u32 = 40;

/// The constant id and GLSL name of word i of primitive k's vertices.
pub fn flat_vertex(k: u32, i: u32) -> (u32, String) {
    (FLAT_VERTEX_BASE + 9 * k + i, format!("FLAT_P{k}_{i}"))
}

/// The GLSL type of a constant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpecType {
    Uint,
    Int,
    Bool,
    Float,
}

impl SpecType {
    pub const fn glsl(self) -> &'static str {
        match self {
            SpecType::Uint => "uint",
            SpecType::Int => "int",
            SpecType::Bool => "bool",
            SpecType::Float => "float",
        }
    }
}

/// One row of the table.
#[derive(Debug, Clone, Copy)]
pub struct SpecConst {
    pub spec: Spec,
    /// The GLSL name.
    pub name: &'static str,
    pub ty: SpecType,
    /// The default, as a GLSL literal (what a kernel gets where the host sets none).
    pub default: &'static str,
    pub doc: &'static str,
}

const fn c(
    spec: Spec,
    name: &'static str,
    ty: SpecType,
    default: &'static str,
    doc: &'static str,
) -> SpecConst {
    SpecConst {
        spec,
        name,
        ty,
        default,
        doc,
    }
}

use SpecType::{Bool, Float, Int, Uint};

/// Every constant, by id.
#[rustfmt::skip]
pub const SPEC_CONSTANTS: &[SpecConst] = &[
    c(Spec::Integrator, "INTEGRATOR", Uint, "1u",
      "The integrator (INTEGRATOR_* of integrator.glsl)."),
    c(Spec::BsdfKinds, "SCENE_BSDF_KINDS", Uint, "0xffffffffu",
      "The BSDF kinds the scene uses (a bit per BSDF_* kind): the others compile away."),
    c(Spec::Textures, "SCENE_TEXTURES", Uint, "0xffffffffu",
      "Texture kinds and features the scene uses (TEXTURE_* kind bits, TEXTURE_FEATURE_*)."),
    c(Spec::HasMedia, "SCENE_HAS_MEDIA", Bool, "false",
      "Media or null surfaces in the scene; without them the medium code compiles away."),
    c(Spec::PrimKinds, "SCENE_PRIM_KINDS", Uint, "0xffffffffu",
      "The quadric kinds of the scene (SURFACE_FEATURE_* bits): the traversal compiles \
       the tests of the others out (bvh.glsl)."),
    c(Spec::MediumFeatures, "SCENE_MEDIUM_FEATURES", Uint, "0xffffffffu",
      "The medium kinds and grid layouts in the scene (MEDIUM_FEATURE_* bits); the code \
       of the others compiles away."),
    c(Spec::ThinNull, "SCENE_THIN_NULL", Bool, "false",
      "Thin dielectrics and masks are null crossings (volumetric integrators in scenes with them)."),
    c(Spec::MisPower, "SCENE_MIS_POWER", Bool, "false",
      "MIS weights by the power heuristic instead of the balance heuristic."),
    c(Spec::EmitterKinds, "SCENE_EMITTER_KINDS", Uint, "0xffffffffu",
      "The emitter kinds the scene has (a bit per EMITTER_* kind, \
       EMITTER_KIND_BIT_SPHERE_AREA for area lights on spheres): the others compile away."),
    c(Spec::SurfaceFeatures, "SCENE_SURFACE_FEATURES", Uint, "0xffffffffu",
      "The primitive and vertex features of the scene (SURFACE_FEATURE_* bits): hit \
       geometry compiles the others away (surface.glsl)."),
    c(Spec::BvhDepth, "SCENE_BVH_DEPTH", Int, "32",
      "Entries of the traversal stack: the scene BVH's deepest leaf (bvh.glsl)."),
    c(Spec::SamplerKind, "SCENE_SAMPLER_KIND", Uint, "0u",
      "The sampler kind (SAMPLER_*): the other kinds compile away."),
    c(Spec::FilmAlpha, "SCENE_FILM_ALPHA", Bool, "false",
      "The film keeps an alpha channel: camera paths record whether they cover their \
       pixel, and film_gather keeps alpha sums."),
    c(Spec::ShadeLast, "SCENE_SHADE_LAST", Bool, "false",
      "shade for the bounces whose vertices end their paths (depth + 2 > max_depth): \
       only the emission rays find (path.glsl)."),
    c(Spec::ShadeRays, "SCENE_SHADE_RAYS", Uint, "0u",
      "The rays shade shades (SHADE_RAYS_* in path.glsl): the bounce's queue, or one \
       part of intersect's partition of it."),
    c(Spec::EmitterPrims, "SCENE_EMITTER_PRIMS", Uint, "0u",
      "Where a bounce's rays meet the emitters alone (path_emitted.glsl): how many \
       emitter primitives there are (frame.emitter_prims; 0: it traces)."),
    c(Spec::EmitterPrimKinds, "SCENE_EMITTER_PRIM_KINDS", Uint, "0xfu",
      "Their kinds (a bit per PRIM_* kind)."),
    c(Spec::FlatPrims, "SCENE_FLAT_PRIMS", Uint, "0u",
      "A scene of a few primitives: how many; the traversal tests each in turn \
       (bvh.glsl: bvh_trace_flat; 0: traverse the BVH)."),
    c(Spec::FlatKinds, "SCENE_FLAT_KINDS", Uint, "0u",
      "Their kinds."),
    c(Spec::Deferral, "SCENE_DEFERRAL", Uint, "0u",
      "Deferral (deferral.glsl; scenes with null surfaces): 0 none; 1 the fast kernel, \
       which leaves the rays that need a traversal to the full one; 2 the full kernel \
       over those rays alone."),
    c(Spec::Partition, "SCENE_PARTITION", Bool, "false",
      "intersect partitions the rays into hits and misses for shade (partition.glsl)."),
    c(Spec::SecondHits, "SCENE_SECOND_HITS", Bool, "false",
      "Rays may cross null surfaces: intersect keeps the second-nearest hit too \
       (vol_path.glsl)."),
    c(Spec::FirstEnds, "SCENE_FIRST_ENDS", Bool, "false",
      "first_bounce: the first bounce ends the paths (max_depth 1)."),
    c(Spec::SecondEnds, "SCENE_SECOND_ENDS", Bool, "false",
      "first_bounce: the second bounce ends the paths and meets the emitters alone: it \
       runs there too."),
    c(Spec::SecondFused, "SCENE_SECOND_FUSED", Bool, "false",
      "first_bounce: bounce 1 runs there too (traced, shaded, its shadow ray traced), and \
       the rays it continues go to ray queue 0 for the wavefront's bounce 2."),
    c(Spec::FilmFilter, "FILM_FILTER", Uint, "2u",
      "The film's reconstruction filter (FILTER_*)."),
    c(Spec::FilmFromPaths, "FILM_FROM_PATHS", Bool, "false",
      "film_gather reads the pixels' samples from the paths (the box filter; film.rs)."),
    c(Spec::UniformEmitterChoice, "UNIFORM_EMITTER_CHOICE", Bool, "false",
      "photon_emit chooses the emitter uniformly (the photonmapper, as Nori) instead of \
       by power."),
    c(Spec::SppmAlpha, "SPPM_ALPHA", Float, "0.6666667",
      "The alpha of SPPM's radius update (Hachisuka and Jensen)."),
    c(Spec::ScanStage, "SCAN_STAGE", Uint, "0u",
      "The stage of the photon grid's prefix sum."),
    c(Spec::Instances, "SCENE_INSTANCES", Uint, "0u",
      "A scene with instances: hits in instance k are named (k + 1) << (this & 31) | \
       primitive, and this & 32: the instance records are compact (accel::instance, \
       shaders/accel/instance.glsl); 0: no instances, and their code compiles away."),
    c(Spec::InstanceSlots, "SCENE_INSTANCE_SLOTS", Uint, "0u",
      "The first record after the primitives: the instance records (instance.glsl)."),
    c(Spec::SensorShape, "SCENE_SENSOR_SHAPE", Bool, "false",
      "The sensor samples a shape (an irradiancemeter: sensor/irradiancemeter.glsl); \
       without one its code compiles away."),
    c(Spec::SensorBatch, "SCENE_SENSOR_BATCH", Uint, "0u",
      "A batch sensor's number of children (Frame::batch_*, integrator/camera_path.glsl); \
       0: one camera, and the batch's code compiles away."),
    c(Spec::PtracerThinLens, "PTRACER_THIN_LENS", Bool, "false",
      "The particle tracer connects to a thin lens's aperture (integrator/ptracer.glsl); \
       false: the pinhole, and the lens's code compiles away."),
    c(Spec::SubgroupsInOrder, "SUBGROUPS_IN_ORDER", Bool, "false",
      "Subgroup s of a workgroup holds its invocations s * gl_SubgroupSize on, in order \
       (DeviceInfo::subgroups_in_order): thread_index (queue/wavefront.glsl) is read \
       from the subgroup's number and the lane's."),
    c(Spec::ScenePartShift, "SCENE_PART_SHIFT", Uint, "27u",
      "log2 of the texels of one part of a split scene array (scene_bindings.glsl)."),
    c(Spec::BvhNodeParts, "BVH_NODE_PARTS", Uint, "1u", "Parts of the BVH nodes."),
    c(Spec::PrimParts, "PRIM_PARTS", Uint, "1u", "Parts of the primitives."),
    c(Spec::TriangleParts, "TRIANGLE_PARTS", Uint, "1u", "Parts of the triangles."),
    c(Spec::VertexParts, "VERTEX_PARTS", Uint, "1u", "Parts of the vertices."),
    c(Spec::TexelParts, "TEXEL_PARTS", Uint, "1u", "Parts of the texels."),
    c(Spec::DistParts, "DIST_PARTS", Uint, "1u", "Parts of the sampling distributions."),
    c(Spec::GridParts, "GRID_PARTS", Uint, "1u", "Parts of the density grids."),
    c(Spec::GridPackedParts, "GRID_PACKED_PARTS", Uint, "1u",
      "Parts of the packed density grids."),
    c(Spec::FilmAovsLo, "FILM_AOVS_LO", Uint, "0u",
      "The AOVs aov.comp writes, 4 bits a kind (AOV_* of aov.glsl), 0 ending the list: \
       the first eight."),
    c(Spec::FilmAovsHi, "FILM_AOVS_HI", Uint, "0u",
      "The AOVs aov.comp writes: the ninth to sixteenth."),
    c(Spec::FilmMoment, "FILM_MOMENT", Bool, "false",
      "aov.comp keeps the samples' second moments (Mitsuba's moment)."),
    c(Spec::FilmAovSamples, "FILM_AOV_SAMPLES", Bool, "false",
      "aov.comp writes each path's AOVs into the film's AOV ring (filters wider than \
       the box) instead of gathering."),
];

/// The GLSL header build.rs writes: `SPEC(NAME)` declares constant `NAME` with its id,
/// type and default from [`SPEC_CONSTANTS`].
pub fn glsl_header() -> String {
    let mut s = String::from(
        "// Generated by build.rs from src/gpu/spec_ids.rs: every specialization constant\n\
         // of the kernels with its one id. A kernel declares a constant it uses with\n\
         // `SPEC(NAME);`.\n\
         #ifndef GENERATED_SPEC_CONSTANTS_GLSL\n\
         #define GENERATED_SPEC_CONSTANTS_GLSL\n\
         #define SPEC(name) SPEC_##name\n",
    );
    for k in SPEC_CONSTANTS {
        s.push_str(&format!(
            "// {}\n#define SPEC_{} layout(constant_id = {}) const {} {} = {}\n",
            k.doc,
            k.name,
            k.spec.id(),
            k.ty.glsl(),
            k.name,
            k.default
        ));
    }
    s.push_str(
        "// The vertices of the first primitives tested in turn (spec_ids::flat_vertex).\n\
         #define SPEC_FLAT_VERTICES",
    );
    for k in 0..FLAT_VERTEX_PRIMS {
        for i in 0..9 {
            let (id, name) = flat_vertex(k, i);
            s.push_str(&format!(
                " \\\n    layout(constant_id = {id}) const float {name} = 0.0;"
            ));
        }
    }
    s.push_str("\n#endif\n");
    s
}
