//! The wavefront renderer: queues, per-bounce dispatch, integrators, film.
//!
//! A batch of paths runs as `generate -> (intersect -> shade -> queue_args -> shadow)
//! per bounce -> accumulate (not with the box filter) -> film_gather`, every stage one
//! dispatch over a queue in GPU memory. Queue lengths stay on the GPU and drive
//! indirect dispatch, so a whole batch is one submission with no read-back between
//! bounces (Laine, Karras and Aila 2013, "Megakernels Considered Harmful").

pub mod alias;
pub mod error;
pub mod film;
pub mod integrator;
pub mod job;
pub mod partial;
pub mod photon;
pub mod progressive;
pub mod sampler;
pub mod scene_buffers;
pub mod scene_parts;
pub mod wavefront;

pub use error::{Error, Result};
pub use film::FilmSums;
pub use integrator::Integrator;

use std::time::Instant;

use crate::accel::{self, Bvh, BvhStats, FlatPrims};
use crate::gpu::layout::{Counters, Frame, Push, MEDIUM_FEATURE_GRIDS, WORKGROUP_SIZE};
use crate::gpu::{
    shaders, BindingLayout, CommandList, DescriptorSet, Device, DeviceKind, Kernel, KernelSpec,
    KernelTimes,
};
use crate::image::Image;
use crate::scene::sampler::{SampleCount, Sampler, SamplerKind};
use crate::scene::Scene;

use film::{film_binding_kinds, Film, FilmGeometry, BYTES_PER_SAMPLE_SLOT};
use photon::{photon_binding_kinds, PhotonStats, Photons};
use scene_buffers::{SceneBuffers, SceneRecords};
use scene_parts::{array_sizes, scene_binding_kinds, take_scene_arrays, ScenePlan};
use wavefront::{wavefront_binding_kinds, Wavefront, BYTES_PER_PATH};

/// How to render, beyond what the scene says.
#[derive(Debug, Clone, Default)]
pub struct RenderOptions {
    /// Integrator name overriding the scene's (`--integrator`).
    pub integrator: Option<String>,
    /// Seed of the random numbers, added to the sampler's `seed`; a render is a
    /// function of scene, seed and sample range.
    pub seed: u32,
    /// Sampler type overriding the scene's (`--sampler`); the scene's sampler
    /// parameters carry over where the type has them.
    pub sampler: Option<String>,
    /// Most paths in flight per batch; `None` picks a size for the device and the
    /// render (see `expected_spp`).
    pub max_batch_paths: Option<u32>,
    /// Samples per pixel the renders will take, which sizes the batches where
    /// `max_batch_paths` does not (a render of few paths needs no large batch, whose
    /// memory the start-up touches); `None`: the scene's sample count.
    pub expected_spp: Option<u32>,
    /// Record GPU timestamps around every kernel.
    pub timestamps: bool,
    /// Most bounces a path may take before it is cut (and counted in
    /// [`RenderStats::cut_paths`]); `None`: [`integrator::MAX_BOUNCES`]. Paths the
    /// integrator's `max_depth` ends sooner are never cut.
    pub max_bounces: Option<u32>,
    /// log2 of the most texels in one part of a scene array (`scene_parts`); `None`:
    /// as large as the device allows. Smaller parts split even small scenes over
    /// several bindings, which is how tests and benchmarks exercise that path.
    pub scene_part_shift: Option<u32>,
    /// Photon mappers: most photons a photon pass holds; `None` picks what the
    /// device's memory and binding limits allow. A photon map with more photons is
    /// split into passes.
    pub max_photons_per_pass: Option<u32>,
    /// SPPM: most pixels whose visible points and states are held at once; `None`:
    /// as many as one storage binding holds (the whole film but for huge ones). A film
    /// with more is rendered in tiles of pixels, each through all its iterations.
    pub max_sppm_pixels: Option<u32>,
    /// Trace the bounces that only end paths through the whole BVH even where the
    /// scene has few emitter primitives (by default those bounces meet the emitters
    /// alone: shaders/integrator/path_emitted.glsl). The same image either way; tests
    /// compare the two.
    pub trace_last_bounce: bool,
    /// Traverse the BVH even where the scene has so few primitives that the kernels
    /// would test each in turn ([`accel::FLAT_PRIMS_MAX`], bvh.glsl's
    /// `bvh_trace_flat`). The same image either way; tests compare the two.
    pub traverse_small_scenes: bool,
    /// Render with the wavefront's kernels alone even where a CPU device would run a
    /// first bounce in one kernel (shaders/kernels/first_bounce.comp). The same image either
    /// way, up to float contraction; tests compare the two.
    pub wavefront: bool,
    /// Whether shade and shadow leave the rays that cross more null surfaces than
    /// their traversal found to full twins of themselves (shaders/queue/deferral.glsl)
    /// instead of tracing in their crossing loops: `None` where it pays (see
    /// `Renderer::new`), `Some(false)` never, `Some(true)` in every scene with null
    /// surfaces. The same image either way but for float rounding; tests compare them.
    pub deferral: Option<bool>,
}

/// Time spent before the first sample, in seconds.
#[derive(Debug, Clone, Default)]
pub struct SetupStats {
    pub bvh: BvhStats,
    /// The primitives the kernels test in turn: every one, instead of traversing the
    /// BVH (`flat.flat_only`), or the few quadrics kept out of the tree (`Bvh::apart`),
    /// before it.
    pub flat: FlatPrims,
    pub upload_seconds: f64,
    /// Creating the pipelines.
    pub pipeline_seconds: f64,
    /// The first dispatch of every kernel with no work, where llvmpipe compiles
    /// (fast on a second run thanks to Mesa's shader disk cache).
    pub first_dispatch_seconds: f64,
}

/// What a render did.
#[derive(Debug, Clone, Default)]
pub struct RenderStats {
    pub seconds: f64,
    pub spp: u32,
    /// Camera rays plus every extension and shadow ray traced.
    pub rays: u64,
    /// Samples dropped because they were NaN or infinite.
    pub discarded: u64,
    pub batches: u32,
    /// Paths still going when the bounce budget ([`integrator::MAX_BOUNCES`]) ran out:
    /// their later vertices are missing from the image.
    pub cut_paths: u64,
    /// Rays and shadow rays that shade and shadow left to their full twins
    /// (shaders/queue/deferral.glsl; scenes with null surfaces).
    pub deferred: u64,
    pub kernel_times: KernelTimes,
    /// Photon mappers: photons emitted and stored, passes, where the time went.
    pub photons: Option<PhotonStats>,
}

/// The sampler a render uses: the scene's, or its type replaced by `name`
/// (`--sampler`).
pub fn choose_sampler(scene: &Scene, name: Option<&str>) -> Result<Sampler> {
    match name {
        None => Ok(scene.sampler),
        Some(n) => SamplerKind::from_name(n)
            .map(|k| scene.sampler.with_kind(k))
            .ok_or_else(|| {
                Error::Options(format!(
                    "unknown sampler '{n}' (expected one of {})",
                    SamplerKind::NAMES.join(", ")
                ))
            }),
    }
}

struct Kernels {
    /// generate, intersect and shadow: None where `first_bounce` runs every bounce of
    /// a batch (read them through the methods of the same names).
    generate: Option<Kernel>,
    intersect: Option<Kernel>,
    /// None for the photon mappers, which shade with kernels of their own.
    shade: Option<Kernel>,
    /// `shade` for the bounces whose vertices end their paths (depth + 2 > max_depth:
    /// only the emission rays find; shaders/integrator/path.glsl's SHADE_LAST), where a
    /// path integrator's depth is bounded.
    shade_last: Option<Kernel>,
    /// Whether `shade_last` meets the emitters itself (shaders/integrator/path_emitted.glsl):
    /// its bounces then run no `intersect` and send their light through `shadow`.
    last_meets_emitters: bool,
    /// Where `intersect` partitions a bounce's rays into hits and misses (see
    /// [`partitions`]): `shade_args` makes the dispatches of each part, and
    /// `shade_miss` shades the misses.
    shade_args: Option<Kernel>,
    shade_miss: Option<Kernel>,
    shadow: Option<Kernel>,
    /// In scenes with null surfaces: the full twins of `shade` and `shadow`, which
    /// then run without the traversals of their crossing loops and leave the rays
    /// that need one to these (shaders/queue/deferral.glsl).
    shade_deferred: Option<Kernel>,
    shadow_deferred: Option<Kernel>,
    queue_args: Kernel,
    /// None where `film_gather` reads the paths ([`Film::reads_paths`]).
    accumulate: Option<Kernel>,
    film_gather: Kernel,
    /// Where a CPU device runs a batch's camera rays and first bounce in one kernel
    /// (shaders/kernels/first_bounce.comp; see [`fuses_first_bounce`]): it, in place of
    /// generate and bounce 0 (and of bounce 1 where that ends the paths).
    first_bounce: Option<Kernel>,
    /// The bounces `first_bounce` runs: 1, or 2 where bounce 1 ends the paths.
    fused_bounces: u32,
}

impl Kernels {
    fn generate(&self) -> Result<&Kernel> {
        made(&self.generate, "generate")
    }
    fn intersect(&self) -> Result<&Kernel> {
        made(&self.intersect, "intersect")
    }
    fn shadow(&self) -> Result<&Kernel> {
        made(&self.shadow, "shadow")
    }
}

/// A kernel that the render may have left out.
fn made<'a>(kernel: &'a Option<Kernel>, name: &str) -> Result<&'a Kernel> {
    kernel.as_ref().ok_or_else(|| {
        Error::Options(format!(
            "internal error: the render made no '{name}' kernel (first_bounce runs its paths)"
        ))
    })
}

/// A scene prepared on a device, ready to render any number of samples.
pub struct Renderer {
    device: Device,
    integrator: Integrator,
    /// Bounces a batch may run: the integrator's, within RenderOptions::max_bounces.
    bounces: u32,
    kernels: Kernels,
    scene_buffers: SceneBuffers,
    wavefront: Wavefront,
    /// The photon mappers' kernels and buffers (descriptor set 2).
    photon: Option<Photons>,
    /// The film (descriptor set 3).
    film: Film,
    /// The full film's size.
    width: u32,
    height: u32,
    /// The sampler's grid of pixel keys ([`FilmGeometry::key_size`]).
    key_size: (u32, u32),
    timestamps: bool,
    /// The frame as uploaded; its sampler fields change with the sample count.
    frame: Frame,
    sampler: Sampler,
    /// The render's seed (before the sampler's is added).
    seed: u32,
    sample_count: SampleCount,
    pub setup: SetupStats,
}

/// Which queue a stage of a bounce runs over (see [`Renderer::run_bounces`]).
#[derive(Clone, Copy)]
enum Over {
    /// The ray queue of the bounce (indirect dispatch).
    Rays,
    /// The rays of the bounce that found a surface, and those that left the scene,
    /// where `intersect` partitions them (indirect dispatches).
    Hits,
    Misses,
    /// The shadow queue (indirect dispatch).
    Shadows,
    /// The rays and the shadow rays the fast shade and shadow deferred (indirect
    /// dispatches; shaders/queue/deferral.glsl).
    DeferredRays,
    DeferredShadows,
    /// One workgroup.
    One,
}

/// Whether a batch's camera rays and first bounce may run in one kernel, `first_bounce`
/// (and the second bounce too where it ends the paths), instead of generate and a
/// dispatch of each stage: on CPU devices, for the integrators of path.glsl (in scenes
/// with media or null surfaces too, with their medium stage). llvmpipe turns each
/// divergent access to the queues into a loop over its SIMD lanes, and at the first
/// bounce every lane has a path to follow, so handing it from kernel to kernel costs
/// and compaction saves nothing. A GPU keeps the wavefront. (`Renderer::new` decides
/// where it pays.)
fn fuses_first_bounce(device: &Device, integrator: &Integrator) -> bool {
    device.info().kind == DeviceKind::Cpu && integrator.shades_paths()
}

/// The fewest paths a render must have for a path tracer's first bounce to run fused
/// (see `Renderer::new`): with savings of 4-16% of some 0.5 us per path, what pays for
/// the extra kernel's creation.
const FUSED_MIN_PATHS: u64 = 1 << 21;

/// The fraction of a 16 x 16 grid of camera rays through pixel centres that meet
/// nothing (traced on the host: `Renderer::new` decides with it whether bounce 0 of a
/// scene with an environment runs fused, where its misses cannot have their kernel).
fn camera_miss_fraction(bvh: &Bvh, cam: &crate::scene::Camera) -> f32 {
    const N: u32 = 16;
    let [tan_x, tan_y] = cam.tan_half_fov();
    let mut misses = 0;
    for j in 0..N {
        for i in 0..N {
            // As camera.glsl's camera_ray.
            let ndc = glam::Vec2::new((i as f32 + 0.5) / N as f32, (j as f32 + 0.5) / N as f32);
            let d = glam::Vec3::new(
                (1.0 - 2.0 * ndc.x) * tan_x,
                (1.0 - 2.0 * ndc.y) * tan_y,
                1.0,
            );
            let near = cam.to_world.transform_point3(d * cam.near_clip);
            let far = cam.to_world.transform_point3(d * cam.far_clip);
            let span = far - near;
            let len = span.length();
            if !(len > 0.0 && len.is_finite()) || bvh.closest(near, span / len, 0.0, len).is_none()
            {
                misses += 1;
            }
        }
    }
    misses as f32 / (N * N) as f32
}

/// Whether `intersect` partitions a bounce's rays into hits and misses for `shade`
/// (its specialization constant 2; shaders/queue/partition.glsl): llvmpipe runs
/// shade's whole code for a lane whose ray left the scene, so path integrators in
/// scenes with an environment shade the rays that found a surface in SIMD groups of
/// their own and the misses in `shade_miss`, a kernel with only the miss code. The
/// partition costs an atomic per ray (intersect +30-50% on llvmpipe): it pays where
/// many rays miss and the environment lights them (the normal-map scene 256^2, 64
/// spp: shade 1235 -> 860 ms + shade_miss 100 ms; the glossy env-map scene 16 spp:
/// shade 415 -> 220 + 60 ms), not in closed scenes (Cornell box: no gain), and
/// without an environment a miss adds nothing anyway. The first-hit integrators, the
/// photon mappers and scenes with media (whose medium stage turns misses into
/// scattering events) shade every ray of the queue in one kernel.
fn partitions(integrator: &Integrator, has_media: bool, has_environment: bool) -> bool {
    has_environment && integrator.shades_paths() && !has_media
}

/// Workgroups for `n` threads on a 2D grid (at most 65535 per dimension); the same
/// rule as `groups_for` in queue_args.comp.
pub(crate) fn groups_for(n: u32) -> [u32; 3] {
    let groups = n.div_ceil(WORKGROUP_SIZE);
    let x = groups.min(65535);
    let y = if x == 0 { 1 } else { groups.div_ceil(x) };
    [x, y, 1]
}

/// What a render of `scene` with `options` uses, before any device: the integrator,
/// the film it renders (SPPM's differs from the scene's, see
/// [`Renderer::film_overridden`]) and its geometry, and the sampler.
fn resolve(
    scene: &Scene,
    options: &RenderOptions,
) -> Result<(Integrator, crate::scene::Film, FilmGeometry, Sampler)> {
    let integrator = Integrator::from_spec(
        &scene.integrator,
        options.integrator.as_deref(),
        &scene.path,
    )?;
    let cam = &scene.camera;
    // SPPM keeps one estimate per pixel (its radius and flux): a box filter over
    // the whole film, whatever the scene's film asks for (see `film_overridden`).
    let film_spec = if matches!(integrator, Integrator::Sppm(_)) {
        crate::scene::Film {
            filter: crate::scene::film::Filter::Box,
            crop: None,
            sample_border: false,
            ..scene.film.clone()
        }
    } else {
        scene.film.clone()
    };
    let geometry = FilmGeometry::new(
        cam.width,
        cam.height,
        film_spec.crop,
        &film_spec.filter,
        film_spec.sample_border,
    )?;
    let sampler = choose_sampler(scene, options.sampler.as_deref())?;
    Ok((integrator, film_spec, geometry, sampler))
}

/// The integrator, sampler and film geometry a render of `scene` with `options` uses,
/// as [`Renderer::new`] would set them up (without a device); the sampler's
/// [`Sampler::sample_count`] over the geometry's [`FilmGeometry::key_size`] is the
/// count [`Renderer::round_sample_count`] gives.
pub fn plan_render(
    scene: &Scene,
    options: &RenderOptions,
) -> Result<(Integrator, Sampler, FilmGeometry)> {
    resolve(scene, options).map(|(i, _, g, s)| (i, s, g))
}

impl Renderer {
    pub fn new(device: &Device, scene: &Scene, options: &RenderOptions) -> Result<Renderer> {
        let (integrator, film_spec, geometry, sampler) = resolve(scene, options)?;
        let cam = &scene.camera;
        let pixels = cam.width * cam.height;
        let key_size = geometry.key_size();
        let sample_count = sampler
            .sample_count(scene.spp, key_size.0, key_size.1)
            .map_err(Error::Options)?;

        if integrator.is_photon_mapper() && scene.needs_medium_code() {
            return Err(Error::Integrator {
                file: scene.path.clone(),
                line: scene.integrator.line,
                message: format!(
                    "integrator '{}' traces light between surfaces only: the scene has \
                     participating media or null (index-matched) surfaces; render it with \
                     vol_path_mis",
                    integrator.name()
                ),
            });
        }
        if integrator.is_photon_mapper() && scene.emitters.is_empty() {
            return Err(Error::Integrator {
                file: scene.path.clone(),
                line: scene.integrator.line,
                message: format!(
                    "integrator '{}' needs an emitter to shoot photons from; the scene has none",
                    integrator.name()
                ),
            });
        }
        let prims = scene.triangle_count() + scene.quadrics.len();
        if prims > accel::BVH_MAX_PRIMS {
            return Err(Error::Options(format!(
                "the scene has {prims} primitives, more than one BVH holds ({}): use fewer \
                 triangles (decimate the largest meshes)",
                accel::BVH_MAX_PRIMS
            )));
        }
        let bvh = Bvh::for_shapes(&scene.meshes, &scene.quadrics);
        let mut records = SceneRecords::new(scene, &bvh);
        let emitter_prims = records.emitter_prims(&bvh);
        // Their kinds, a bit per PRIM_* kind (constant 17 of shade_last).
        let emitter_prim_kinds = emitter_prims
            .iter()
            .flatten()
            .fold(0u32, |m, &i| m | 1 << bvh.prims[i as usize].kind);
        let bvh_stats = bvh.stats;
        // Scenes of a few primitives are traced without the tree.
        let flat = FlatPrims::of(
            &bvh,
            if options.traverse_small_scenes {
                0
            } else {
                accel::FLAT_PRIMS_MAX
            },
        );
        let [flat_count, flat_kinds] = flat.constants();
        let scene_bounds = photon::SceneBounds::of(&bvh);
        // For the choice of a fused first bounce in a scene with an environment (below;
        // traced here, before the upload takes the BVH).
        let camera_misses = (device.info().kind == DeviceKind::Cpu
            && records.env_emitter != crate::gpu::layout::NONE)
            .then(|| camera_miss_fraction(&bvh, cam));

        let t = Instant::now();
        // The BVH and the large records are moved into the upload, which frees each
        // once it is on the device.
        let arrays = take_scene_arrays(bvh, &mut records);
        let plan = ScenePlan::for_device(
            device.info(),
            array_sizes(&arrays),
            options.scene_part_shift,
        )?;
        let layout = BindingLayout::with_spec(
            device,
            &[
                scene_binding_kinds(),
                wavefront_binding_kinds(),
                photon_binding_kinds(),
                film_binding_kinds(),
            ],
            std::mem::size_of::<Push>() as u32,
            &plan.spec(),
            plan.is_split(),
        )?;
        let scene_buffers = SceneBuffers::upload_planned(device, &layout, arrays, plan)?;
        let mut frame = Frame {
            camera_to_world: cam.to_world.to_cols_array_2d(),
            tan_half_fov: cam.tan_half_fov(),
            near_clip: cam.near_clip,
            far_clip: cam.far_clip,
            width: cam.width,
            height: cam.height,
            seed: options.seed,
            point_light_count: records.point_light_count,
            ao_max_t: match integrator {
                Integrator::Ao { max_t, .. } => max_t,
                _ => f32::INFINITY,
            },
            ao_uniform: matches!(integrator, Integrator::Ao { uniform: true, .. }) as u32,
            max_depth: integrator.max_depth(),
            emitter_count: records.emitters.len() as u32,
            rr_depth: integrator.rr_depth(),
            env_emitter: records.env_emitter,
            hide_emitters: integrator.hide_emitters() as u32,
            camera_medium: scene.camera_medium.unwrap_or(crate::gpu::layout::NONE),
            photon_alias: records.photon_alias,
            ..Default::default()
        };
        sampler::set_frame(&mut frame, &sampler, &sample_count, options.seed, key_size);
        for (k, &slot) in emitter_prims.iter().flatten().enumerate() {
            frame.emitter_prims[k / 4][k % 4] = slot;
        }
        let expected_paths = u64::from(geometry.region_pixels())
            * u64::from(options.expected_spp.unwrap_or(scene.spp));
        let capacity = options
            .max_batch_paths
            .unwrap_or_else(|| default_capacity(device, expected_paths))
            .max(1);
        // Keep every queue inside one storage-buffer binding.
        let limit = device.info().max_storage_buffer_range
            / (2 * std::mem::size_of::<crate::gpu::layout::RayItem>() as u64);
        let capacity = capacity
            .min(limit as u32)
            .min(Film::max_batch_paths(device, &geometry))
            .clamp(1, MAX_BATCH_PATHS);
        // Media and null surfaces: the medium code of shade and shadow
        // (constant_id 4 of both; 2-3 belong to textures).
        // Thin dielectrics are null crossings for the volumetric path tracers
        // (constant_id 7 of shade and shadow), which need the medium code for them.
        let thin_null = (scene.has_thin_dielectrics() && integrator.is_volumetric()) as u32;
        let has_media = (scene.needs_medium_code() || thin_null != 0) as u32;
        // Where rays cross null surfaces, intersect keeps each ray's second-nearest hit
        // too (constant_id 5 of intersect; vol_path.glsl).
        let wavefront = Wavefront::new(device, &layout, capacity, &frame, has_media != 0)?;
        // Alpha: the film keeps covered weights and shade marks covered camera paths;
        // a visible environment covers every path of the integrators where Mitsuba
        // counts it (`valid_ray` of path and volpath). The photon mappers' camera
        // kernels mark none: no alpha there (see `film_overridden`).
        let has_alpha = film_spec.pixel_format.has_alpha() && !integrator.is_photon_mapper();
        let covered = integrator.counts_environment_coverage()
            && !integrator.hide_emitters()
            && records.env_emitter != crate::gpu::layout::NONE;
        let film = Film::new(
            device,
            &layout,
            geometry,
            film_spec.filter,
            has_alpha,
            covered,
            capacity,
        )?;
        let features = photon::SceneFeatures {
            surface: records.surface_features() | records.prim_kinds(),
            textures: records.texture_mask(),
            emitters: records.emitter_kinds(),
            bsdfs: records.bsdfs.iter().fold(0u32, |m, b| m | 1 << b.kind),
            sampler: sampler::kind_id(&sampler),
        };
        let upload_seconds = t.elapsed().as_secs_f64();

        let t = Instant::now();
        // Specialization: code for features the scene lacks is compiled out.
        // The quadric kinds (SURFACE_FEATURE_* bits): the traversal and the hit
        // geometry compile the others away.
        let prim_kinds = records.prim_kinds();
        // Medium features (constant_id 6): the kinds and grid layouts the scene's media
        // use; homogeneous-only scenes compile tracking away.
        let medium_features = records.medium_features();
        // Surface features (constant_id 10 of shade and shadow): quadric kinds,
        // vertex normals and uvs; hit geometry compiles the absent ones away.
        let surface_features = records.surface_features() | prim_kinds;
        let bsdf_kinds = records.bsdfs.iter().fold(0u32, |m, b| m | 1 << b.kind);
        // The traversal stack holds at most one entry per level above the deepest
        // leaf (constant_id 1 of intersect, 11 of shade and shadow; bvh.glsl).
        let bvh_depth = bvh_stats.stack_depth();
        let partitioned = partitions(
            &integrator,
            has_media != 0,
            records.env_emitter != crate::gpu::layout::NONE,
        );
        // Bounces that only end paths meet the emitters alone (path_emitted.glsl)
        // where the scene has few emitter prims, no environment and no media, from
        // the second bounce on (a camera ray's hit also decides its pixel's alpha).
        let emitted_only = if has_media == 0
            && !options.trace_last_bounce
            && records.env_emitter == crate::gpu::layout::NONE
            && !integrator.ends_paths_at(0)
        {
            emitter_prims.as_ref().map_or(0, |p| p.len() as u32)
        } else {
            0
        };
        let shade_spec = |last: bool, misses: bool| {
            [
                integrator.id(),
                bsdf_kinds,
                records.texture_mask(),
                0,
                has_media,
                prim_kinds,
                medium_features,
                thin_null,
                integrator.power_heuristic() as u32,
                records.emitter_kinds(),
                surface_features,
                bvh_depth,
                sampler::kind_id(&sampler),
                has_alpha as u32,
                last as u32,
                // SHADE_RAYS_* (path.glsl): all, hits, misses; shade_last meeting the
                // emitters itself runs over all its rays.
                match (partitioned && !(last && emitted_only > 0), misses) {
                    (false, _) => 0,
                    (true, false) => 1,
                    (true, true) => 2,
                },
                if last { emitted_only } else { 0 },
                if last { emitter_prim_kinds } else { 0xf },
                flat_count,
                flat_kinds,
            ]
        };
        let bounces = integrator
            .bounces()
            .min(options.max_bounces.unwrap_or(u32::MAX))
            .max(1);
        // Every kernel of the render, created in parallel (Kernel::new_all), the
        // largest first.
        let mut specs: Vec<KernelSpec> = Vec::new();
        // Every kernel is inlined before lavapipe sees it (render start-up: see
        // gpu::specialize::INLINE_PASSES). Scenes with media too, since their code
        // returns once from every function (medium.glsl): the media cube's pipelines
        // 500-640 -> 120-160 ms, its kernels' instructions +0.1% (callgrind, 256^2
        // 32 spp, with the fused first bounce).
        let mut add = |name, spirv, spec: &[u32]| {
            specs.push(KernelSpec::new(name, spirv, spec).inlined(true));
            specs.len() - 1
        };
        // On CPU devices the batch's first bounce runs in one kernel, first_bounce.comp,
        // in place of generate and bounce 0's intersect, shade and shadow (and bounce
        // 1 where it ends the paths meeting the emitters alone: direct lighting in
        // scenes with few emitter primitives, when the kernel is the whole path and
        // the others are not made). Where the wavefront goes on after it (path
        // tracers) it is made beside shade, which costs 60-110 ms of start-up on
        // lavapipe, so only for renders of FUSED_MIN_PATHS paths or more; and not
        // where over a third of the camera rays leave the scene into an environment,
        // whose misses the wavefront shades apart (`partitions`). callgrind at
        // 64^2 16 spp, fused against not: normal map -16%, textures (23% of camera
        // rays miss) -7%, glass -6%, Cornell box -4%, envmap_glossy (44%) +9%; the
        // media cube at 256^2 32 spp -3.1%.
        let second_ends = bounces == 2 && integrator.ends_paths_at(1) && emitted_only > 0;
        let fused_bounces = 1 + second_ends as u32;
        let fused = fuses_first_bounce(device, &integrator)
            && !options.wavefront
            && (bounces <= fused_bounces
                || (expected_paths >= FUSED_MIN_PATHS
                    && (!partitioned || camera_misses.is_some_and(|m| m <= 1.0 / 3.0))));
        let wavefront_kernels = !fused || bounces > fused_bounces;
        // Deferral (shaders/queue/deferral.glsl): in scenes with null surfaces, shade
        // and shadow run without the traversals of their crossing loops, and their
        // full twins take the rays that need one (first_bounce traces: deferring its
        // shadow rays too cost the media cube 1.3% more, fused at 256^2 32 spp). It pays
        // where few rays defer and a deferred one costs little to run again: not with
        // a null sphere or cylinder, which every ray that crosses it must trace again
        // past, nor with grid media, whose tracking shade_deferred repeats. callgrind,
        // kernels' instructions, deferring against not (the same images):
        // media/cube.xml 256^2 32 spp (fused) -5.7%, 128^2 16 spp (wavefront) -7.5%;
        // at 128^2 16 spp thin_textured.xml -6.5%, two_media.xml (a null sphere
        // around the camera) +3.0%, smoke.xml (a grid) +9.6%, cbox_smoke.xml (a grid)
        // 0.0%.
        let deferring = has_media != 0
            && integrator.shades_paths()
            && options.deferral.unwrap_or_else(|| {
                !scene.has_curved_crossings() && medium_features & MEDIUM_FEATURE_GRIDS == 0
            });
        let deferral = wavefront_kernels && deferring;
        let first_bounce = fused.then(|| {
            // Shade's constants, with 14 and 20 saying whether bounce 0 or bounce 1
            // ends the paths, and 16-17 the emitter primitives bounce 1 meets.
            let mut spec = shade_spec(second_ends, false).to_vec();
            spec[14] = integrator.ends_paths_at(0) as u32;
            spec.push(second_ends as u32);
            add("first_bounce", shaders::FIRST_BOUNCE, &spec)
        });
        let shade_with = |mode: u32| {
            let mut spec = shade_spec(false, false).to_vec();
            spec.push(mode);
            spec
        };
        let shade = (wavefront_kernels && !integrator.is_photon_mapper())
            .then(|| add("shade", shaders::SHADE, &shade_with(deferral as u32)));
        let shade_deferred = (deferral && !integrator.is_photon_mapper())
            .then(|| add("shade_deferred", shaders::SHADE, &shade_with(2)));
        let shade_last = (wavefront_kernels && (0..bounces).any(|d| integrator.ends_paths_at(d)))
            .then(|| add("shade_last", shaders::SHADE, &shade_spec(true, false)));
        let shade_miss = (wavefront_kernels && partitioned)
            .then(|| add("shade_miss", shaders::SHADE, &shade_spec(false, true)));
        let shadow_with = |mode: u32| {
            [
                prim_kinds,
                0,
                records.texture_mask(),
                0,
                has_media,
                0,
                medium_features,
                thin_null,
                0,
                0,
                surface_features,
                bvh_depth,
                flat_count,
                flat_kinds,
                mode,
            ]
        };
        let shadow = wavefront_kernels
            .then(|| add("shadow", shaders::SHADOW, &shadow_with(deferral as u32)));
        let shadow_deferred =
            deferral.then(|| add("shadow_deferred", shaders::SHADOW, &shadow_with(2)));
        let intersect = wavefront_kernels.then(|| {
            add(
                "intersect",
                shaders::INTERSECT,
                &[
                    prim_kinds,
                    bvh_depth,
                    partitioned as u32,
                    flat_count,
                    flat_kinds,
                    has_media,
                ],
            )
        });
        let generate =
            (!fused).then(|| add("generate", shaders::GENERATE, &[sampler::kind_id(&sampler)]));
        let film_gather = add(
            "film_gather",
            shaders::FILM_GATHER,
            &film.gather_constants(),
        );
        let accumulate = (!film.reads_paths()).then(|| {
            add(
                "accumulate",
                shaders::ACCUMULATE,
                &[sampler::kind_id(&sampler)],
            )
        });
        let queue_args = add("queue_args", shaders::QUEUE_ARGS, &[]);
        let shade_args =
            (wavefront_kernels && partitioned).then(|| add("shade_args", shaders::SHADE_ARGS, &[]));
        let mut made: Vec<Option<Kernel>> = Kernel::new_all(device, &layout, &specs)?
            .into_iter()
            .map(Some)
            .collect();
        let mut take = |i: usize| {
            made[i]
                .take()
                .unwrap_or_else(|| unreachable!("kernel {i} taken twice"))
        };
        let kernels = Kernels {
            generate: generate.map(&mut take),
            intersect: intersect.map(&mut take),
            shade: shade.map(&mut take),
            shade_last: shade_last.map(&mut take),
            last_meets_emitters: emitted_only > 0,
            shade_args: shade_args.map(&mut take),
            shade_miss: shade_miss.map(&mut take),
            shadow: shadow.map(&mut take),
            shade_deferred: shade_deferred.map(&mut take),
            shadow_deferred: shadow_deferred.map(&mut take),
            queue_args: take(queue_args),
            accumulate: accumulate.map(&mut take),
            film_gather: take(film_gather),
            first_bounce: first_bounce.map(&mut take),
            fused_bounces,
        };
        // The photon mappers' kernels and buffers (their buffers are small until a
        // photon map needs more).
        let photon = if integrator.is_photon_mapper() {
            Some(Photons::new(
                device,
                &layout,
                &integrator,
                features,
                scene_bounds,
                pixels,
                capacity,
                options.max_photons_per_pass,
                options.max_sppm_pixels,
            )?)
        } else {
            None
        };
        device.save_pipeline_cache();
        let pipeline_seconds = t.elapsed().as_secs_f64();

        let mut renderer = Renderer {
            device: device.clone(),
            bounces,
            integrator,
            kernels,
            scene_buffers,
            wavefront,
            photon,
            film,
            width: cam.width,
            height: cam.height,
            key_size,
            timestamps: options.timestamps,
            frame,
            sampler,
            seed: options.seed,
            sample_count,
            setup: SetupStats {
                bvh: bvh_stats,
                flat,
                upload_seconds,
                pipeline_seconds,
                first_dispatch_seconds: 0.0,
            },
        };
        renderer.setup.first_dispatch_seconds = renderer.warm_up()?;
        Ok(renderer)
    }

    pub fn integrator(&self) -> &Integrator {
        &self.integrator
    }

    /// How the scene's arrays lie on the device: sizes and parts.
    pub fn scene_plan(&self) -> &ScenePlan {
        &self.scene_buffers.plan
    }

    /// Most bounces a path runs before it is cut (see [`RenderStats::cut_paths`]).
    pub fn bounce_budget(&self) -> u32 {
        self.bounces
    }

    /// Makes later renders use `seed` (RenderOptions::seed) without setting the scene
    /// up again.
    pub fn set_seed(&mut self, seed: u32) -> Result<()> {
        // The frame's seed is the render's plus the sampler's (sampler::set_frame).
        self.seed = seed;
        self.set_sample_count(self.sample_count.clone())
    }

    /// Whether later renders record GPU timestamps around every kernel.
    pub fn set_timestamps(&mut self, on: bool) {
        self.timestamps = on;
    }

    pub fn capacity(&self) -> u32 {
        self.wavefront.capacity
    }

    /// Which pixels are sampled and which kept.
    pub fn film_geometry(&self) -> &FilmGeometry {
        &self.film.geometry
    }

    /// What of the scene's film this integrator does not render, in words (`None`:
    /// all of it): SPPM keeps one estimate per pixel (a box filter over the whole
    /// film, no alpha), the photon mappers compute no alpha (it is written as 1).
    pub fn film_overridden(&self, film: &crate::scene::Film) -> Option<String> {
        let mut lost = Vec::new();
        if matches!(self.integrator, Integrator::Sppm(_)) {
            if film.filter != crate::scene::film::Filter::Box {
                lost.push(format!(
                    "its {} filter (sppm keeps one estimate per pixel: a box)",
                    film.filter.name()
                ));
            }
            if film.crop.is_some() {
                lost.push("its crop window (sppm renders the whole film)".to_string());
            }
            if film.sample_border {
                lost.push("sample_border".to_string());
            }
        }
        if self.integrator.is_photon_mapper() && film.pixel_format.has_alpha() {
            lost.push(format!(
                "alpha ('{}' computes none: written as 1)",
                self.integrator.name()
            ));
        }
        (!lost.is_empty()).then(|| lost.join(", "))
    }

    /// The descriptor sets of the path-tracing kernels: scene, wavefront, film.
    fn path_sets(&self) -> [&DescriptorSet; 3] {
        [&self.scene_buffers.set, &self.wavefront.set, &self.film.set]
    }

    /// Dispatches every kernel once with empty queues: llvmpipe compiles a kernel at
    /// its first dispatch, and this keeps that cost out of the render's timing.
    fn warm_up(&mut self) -> Result<f64> {
        let t = Instant::now();
        let mut cmd = CommandList::new(&self.device)?;
        let wf = &self.wavefront;
        // Touch the queues once: a CPU device (lavapipe) maps their pages in at the first
        // write, which would otherwise fall into the first batch's time.
        for b in [&wf.paths, &wf.rays, &wf.hits, &wf.shadows, &wf.shade_rays] {
            cmd.fill(b, 0, b.size(), 0);
        }
        wf.reset_queues(&mut cmd, 0, 0);
        cmd.barrier();
        let push = Push {
            capacity: wf.capacity,
            ..Default::default()
        };
        let push = bytemuck::bytes_of(&push);
        let k = &self.kernels;
        let mut kernels = vec![&k.queue_args, &k.film_gather];
        kernels.extend(&k.generate);
        kernels.extend(&k.intersect);
        kernels.extend(&k.shadow);
        kernels.extend(&k.shade);
        kernels.extend(&k.accumulate);
        kernels.extend(&k.shade_last);
        kernels.extend(&k.shade_args);
        kernels.extend(&k.shade_miss);
        kernels.extend(&k.shade_deferred);
        kernels.extend(&k.shadow_deferred);
        kernels.extend(&k.first_bounce);
        let mut sets = vec![&self.scene_buffers.set, &wf.set, &self.film.set];
        if let Some(p) = &self.photon {
            kernels.extend(p.kernels());
            sets.push(&p.map.set);
        }
        for kernel in kernels {
            cmd.dispatch(kernel, &sets, push, [1, 1, 1]);
            cmd.barrier();
        }
        cmd.submit_and_wait()?;
        Ok(t.elapsed().as_secs_f64())
    }

    /// The sampler the render draws its random numbers from.
    pub fn sampler(&self) -> &Sampler {
        &self.sampler
    }

    /// The sample count of the sampler's pattern (one pass): what [`Renderer::render`]
    /// last rendered, or the scene's count as the sampler rounds it.
    pub fn sample_count(&self) -> &SampleCount {
        &self.sample_count
    }

    /// The count the sampler renders when asked for `spp` samples per pixel (rounded
    /// as it rounds, e.g. to a square for `stratified`), or why it cannot.
    pub fn round_sample_count(&self, spp: u32) -> Result<SampleCount> {
        self.sampler
            .sample_count(spp, self.key_size.0, self.key_size.1)
            .map_err(Error::Options)
    }

    /// Makes the sampler's pattern `count` samples (one pass); sample indices past it
    /// belong to later passes. [`Renderer::render`] does this itself; renders of sample
    /// ranges of a whole (resumed, split) render set the whole's count first.
    pub fn set_sample_count(&mut self, count: SampleCount) -> Result<()> {
        sampler::set_frame(
            &mut self.frame,
            &self.sampler,
            &count,
            self.seed,
            self.key_size,
        );
        self.wavefront
            .frame
            .write(&self.device, 0, bytemuck::bytes_of(&self.frame))?;
        self.sample_count = count;
        Ok(())
    }

    /// Renders `spp` samples per pixel as the sampler rounds them (see
    /// [`Renderer::round_sample_count`]: samples `0..count` of a pattern of `count`)
    /// and returns the image; the stats say how many were rendered. `progress` is
    /// called after each batch with (samples done, samples in all).
    pub fn render(
        &mut self,
        spp: u32,
        progress: &mut dyn FnMut(u64, u64),
    ) -> Result<(Image, RenderStats)> {
        let count = self.round_sample_count(spp)?;
        let n = count.count;
        self.set_sample_count(count)?;
        self.render_range(0, n, progress)
    }

    /// Renders samples `first .. first + count` of every pixel and returns the image.
    /// Sample `s` of a pixel is the same whatever range it is rendered in (for the same
    /// [`Renderer::set_sample_count`]); to combine ranges exactly, merge their
    /// [`FilmSums`] ([`Self::render_film`]).
    pub fn render_range(
        &mut self,
        first: u32,
        count: u32,
        progress: &mut dyn FnMut(u64, u64),
    ) -> Result<(Image, RenderStats)> {
        let (film, stats) = self.render_film(first, count, progress)?;
        Ok((film.develop(), stats))
    }

    /// Renders samples `first .. first + count` of every sampled pixel and returns
    /// the film's sums: renders of disjoint ranges merge into the render of their
    /// union ([`FilmSums::merge`]).
    pub fn render_film(
        &mut self,
        first: u32,
        count: u32,
        progress: &mut dyn FnMut(u64, u64),
    ) -> Result<(FilmSums, RenderStats)> {
        self.render_film_controlled(first, count, None, progress, &mut |_, _| Ok(false))
    }

    /// [`Self::render_film`], continuing from `start` (the sums of other samples of
    /// this film, e.g. a resumed render's: the film adds each sample to a pixel's sum
    /// in sample order, so rendering samples `k..n` onto the sums of `0..k` gives the
    /// render of `0..n` bit for bit), and calling `boundary(self, done)` whenever the
    /// samples `first .. first + done` are complete for every pixel (a clean sample
    /// boundary: after a batch of whole samples, or after the last batch of a sample
    /// that is split over batches). If it returns true, rendering stops there and
    /// [`RenderStats::spp`] says how many samples the returned sums hold (`done`).
    /// [`Self::read_film`] reads the sums at a boundary (the samples done so far: a
    /// checkpoint).
    /// SPPM cannot stop early or start from sums (its radii shrink over
    /// iterations); the photon mapper stops only where its photon map is one pass.
    pub fn render_film_controlled(
        &mut self,
        first: u32,
        count: u32,
        start: Option<&FilmSums>,
        progress: &mut dyn FnMut(u64, u64),
        boundary: BoundaryFn,
    ) -> Result<(FilmSums, RenderStats)> {
        if count == 0 {
            return Err(Error::Options(
                "samples per pixel must be at least 1".into(),
            ));
        }
        match self.integrator {
            Integrator::PhotonMapper(p) => {
                return self.render_photonmapper(p, first, count, start, progress, boundary)
            }
            Integrator::Sppm(p) => {
                if start.is_some() {
                    return Err(Error::Options(
                        "sppm cannot continue from another render's sums: its per-pixel \
                         radii and photon statistics shrink over the iterations"
                            .into(),
                    ));
                }
                return self.render_sppm(p, first, count, progress);
            }
            _ => {}
        }
        let t = Instant::now();
        let mut stats = RenderStats {
            spp: count,
            ..Default::default()
        };
        let mut cmd = self.command_list()?;
        self.start_film(&mut cmd, start)?;
        stats.spp = self.for_each_batch(
            &mut cmd,
            first,
            count,
            &mut stats,
            progress,
            &mut |r, cmd, sample, base, n, slot, stats| {
                r.run_batch(cmd, sample, base, n, slot, stats)
            },
            boundary,
        )?;
        let film = self.film.read(&self.device)?;
        stats.seconds = t.elapsed().as_secs_f64();
        Ok((film, stats))
    }

    /// Records clearing the film, or loads `start`'s sums into it (checked to be of
    /// this film).
    fn start_film(&self, cmd: &mut CommandList, start: Option<&FilmSums>) -> Result<()> {
        match start {
            None => {
                self.film.clear(cmd);
                cmd.barrier();
                Ok(())
            }
            Some(sums) => self.film.load(&self.device, sums),
        }
    }

    /// A command list, with timestamps if the renderer records them.
    fn command_list(&self) -> Result<CommandList> {
        Ok(if self.timestamps {
            CommandList::with_timestamps(&self.device)?
        } else {
            CommandList::new(&self.device)?
        })
    }

    /// Calls `batch(self, cmd, sample_base, pixel_base, path_count, slot, stats)` for
    /// batches covering samples `first .. first + count` of every pixel the film
    /// samples: whole samples of every pixel per batch where they fit, else runs of
    /// pixels of one sample. `slot`: the film's sample slot of the batch's first path.
    /// After each batch that completes samples (a clean sample boundary) calls
    /// `boundary(self, samples done)` and stops if it returns true. Returns the
    /// samples done.
    #[allow(clippy::too_many_arguments)]
    fn for_each_batch(
        &self,
        cmd: &mut CommandList,
        first: u32,
        count: u32,
        stats: &mut RenderStats,
        progress: &mut dyn FnMut(u64, u64),
        batch: BatchFn,
        boundary: BoundaryFn,
    ) -> Result<u32> {
        let pixels = self.film.geometry.region_pixels();
        let cap = self.wavefront.capacity;
        let total = pixels as u64 * count as u64;
        let mut done = 0u64;
        let mut sample = first;
        let mut slot = 0;
        let end = first
            .checked_add(count)
            .ok_or_else(|| Error::Options("sample range overflows".into()))?;
        while sample < end {
            if pixels <= cap {
                let k = (cap / pixels).min(end - sample);
                batch(self, cmd, sample, 0, k * pixels, slot, stats)?;
                slot = self.film.next_slot(slot, k * pixels);
                sample += k;
                done += k as u64 * pixels as u64;
                progress(done, total);
            } else {
                let mut base = 0;
                while base < pixels {
                    let n = cap.min(pixels - base);
                    batch(self, cmd, sample, base, n, slot, stats)?;
                    slot = self.film.next_slot(slot, n);
                    base += n;
                    done += n as u64;
                    progress(done, total);
                }
                sample += 1;
            }
            // Every batch ends with its submission waited for: the film holds the
            // samples first..sample of every pixel now.
            if sample < end && boundary(self, sample - first)? {
                break;
            }
        }
        Ok(sample - first)
    }

    /// Records the start of a batch of camera paths (`push`: its paths): the queues
    /// and the first bounce's dispatch set for `push.path_count` rays, and `generate`.
    /// The batch's bounces run from 0.
    fn start_batch(
        &self,
        cmd: &mut CommandList,
        sets: &[&DescriptorSet],
        push: &Push,
    ) -> Result<()> {
        let wf = &self.wavefront;
        let path_count = push.path_count;
        wf.reset_queues(cmd, path_count, path_count);
        cmd.barrier();
        cmd.dispatch(
            self.kernels.generate()?,
            sets,
            bytemuck::bytes_of(push),
            groups_for(path_count),
        );
        cmd.barrier();
        Ok(())
    }

    /// Records the start of a batch of camera paths (`push`: its paths) where
    /// `first_bounce` runs its first bounce (or two): it, and queue_args, which folds
    /// the rays it queued into bounce 1's queue (or counts them as cut paths where the
    /// budget is one bounce).
    fn start_batch_fused(
        &self,
        cmd: &mut CommandList,
        sets: &[&DescriptorSet],
        push: &Push,
        fused: &Kernel,
    ) {
        let wf = &self.wavefront;
        wf.reset_queues(cmd, 0, 0);
        cmd.barrier();
        let p = bytemuck::bytes_of(push);
        cmd.dispatch(fused, sets, p, groups_for(push.path_count));
        cmd.barrier();
        cmd.dispatch(&self.kernels.queue_args, sets, p, [1, 1, 1]);
        cmd.barrier();
    }

    /// Records bounces `range` of a batch whose first rays are in ray queue
    /// `range.start % 2`, each a dispatch of every stage in order. Bounces are recorded
    /// in chunks, the first of `chunks.0`, each next one twice as long up to `chunks.1`;
    /// between chunks the batch is submitted and stops early once no path is left in the
    /// ray queue, so long bounce budgets cost nothing where paths end sooner (an empty
    /// dispatch still costs some 100 us on lavapipe; a check, a submission and a
    /// read-back).
    /// Bounces that only end paths ([`Integrator::ends_paths_at`]) run `ending`'s
    /// stages where given. Returns the bounces recorded.
    #[allow(clippy::too_many_arguments)]
    fn run_bounces(
        &self,
        cmd: &mut CommandList,
        sets: &[&DescriptorSet],
        push: &mut Push,
        stages: &[(&Kernel, Over)],
        ending: Option<&[(&Kernel, Over)]>,
        range: std::ops::Range<u32>,
        chunks: (u32, u32),
        stats: &mut RenderStats,
    ) -> Result<u32> {
        let wf = &self.wavefront;
        let bounces = range.end;
        let mut depth = range.start;
        let mut chunk = chunks.0;
        while depth < bounces {
            let end = (depth + chunk).min(bounces);
            chunk = (2 * chunk).min(chunks.1);
            for d in depth..end {
                push.depth = d;
                push.queue_in = d % 2;
                let p = bytemuck::bytes_of(push);
                let stages = match ending {
                    Some(ending) if self.integrator.ends_paths_at(d) => ending,
                    _ => stages,
                };
                for (kernel, over) in stages {
                    // The indirect arguments of the queue the stage runs over.
                    let args = match over {
                        Over::Rays => Some(Wavefront::RAY_ARGS),
                        Over::Hits => Some(Wavefront::HIT_ARGS),
                        Over::Misses => Some(Wavefront::MISS_ARGS),
                        Over::Shadows => Some(Wavefront::SHADOW_ARGS),
                        Over::DeferredRays => Some(Wavefront::DEFERRED_RAY_ARGS),
                        Over::DeferredShadows => Some(Wavefront::DEFERRED_SHADOW_ARGS),
                        Over::One => None,
                    };
                    match args {
                        Some(a) => cmd.dispatch_indirect(kernel, sets, p, &wf.dispatch_args, a),
                        None => cmd.dispatch(kernel, sets, p, [1, 1, 1]),
                    }
                    cmd.barrier();
                }
            }
            depth = end;
            if depth < bounces {
                // The rays of bounce `depth` are in queue depth % 2.
                stats.kernel_times.add(&cmd.submit_and_wait_timed()?);
                let c: Vec<Counters> = wf.counters.read(&self.device)?;
                if c[0].ray_count[(depth % 2) as usize] == 0 {
                    break;
                }
            }
        }
        Ok(depth)
    }

    /// Renders one batch: `path_count` paths starting at global sample
    /// `sample_base * pixels + pixel_base` (pixels the film samples), the first in film
    /// sample slot `slot`, `BOUNCE_CHUNK` bounces per submission, or for budgets
    /// beyond that `LONG_BUDGET_CHUNKS` (see [`Self::run_bounces`]).
    fn run_batch(
        &self,
        cmd: &mut CommandList,
        sample_base: u32,
        pixel_base: u32,
        path_count: u32,
        slot: u32,
        stats: &mut RenderStats,
    ) -> Result<()> {
        let wf = &self.wavefront;
        let sets = self.path_sets();
        let mut push = Push {
            path_count,
            pixel_base,
            sample_base,
            depth: 0,
            queue_in: 0,
            capacity: wf.capacity,
            sample_slot: slot,
            ..Default::default()
        };
        let k = &self.kernels;
        let first = match &k.first_bounce {
            Some(fused) => {
                self.start_batch_fused(cmd, &sets, &push, fused);
                k.fused_bounces
            }
            None => {
                self.start_batch(cmd, &sets, &push)?;
                0
            }
        };
        if first >= self.bounces {
            self.record_film(cmd, &sets, &push);
            return self.finish_batch(cmd, stats, self.bounces);
        }
        let shade = k.shade.as_ref().ok_or_else(|| {
            Error::Options(format!(
                "integrator '{}' renders photon passes, not batches of paths",
                self.integrator.name()
            ))
        })?;
        let stages = self.bounce_stages(shade, k.shade_deferred.as_ref())?;
        // Bounces that only end paths run shade_last in shade's place.
        let ending = match &k.shade_last {
            Some(s) if k.last_meets_emitters => Some(
                vec![
                    (s, Over::Rays),
                    (&k.queue_args, Over::One),
                    (k.shadow()?, Over::Shadows),
                ]
                .into_iter()
                .chain(k.shadow_deferred.iter().map(|d| (d, Over::DeferredShadows)))
                .collect(),
            ),
            Some(s) => Some(self.bounce_stages(s, None)?),
            None => None,
        };
        let depth = self.run_bounces(
            cmd,
            &sets,
            &mut push,
            &stages,
            ending.as_ref().map(|s| &s[..]),
            first..self.bounces,
            if self.bounces > BOUNCE_CHUNK {
                LONG_BUDGET_CHUNKS
            } else {
                (BOUNCE_CHUNK, BOUNCE_CHUNK)
            },
            stats,
        )?;
        self.record_film(cmd, &sets, &push);
        self.finish_batch(cmd, stats, depth)
    }

    /// The stages of a path batch's bounce with `shade` as its shading kernel:
    /// intersect, shade, queue_args, shadow; partitioned (see [`partitions`]), shade
    /// takes the hits after `shade_args` and `shade_miss` the misses; deferring
    /// (shaders/queue/deferral.glsl), `deferred` after shade and shadow's full twin
    /// after shadow take the rays they left.
    fn bounce_stages<'a>(
        &'a self,
        shade: &'a Kernel,
        deferred: Option<&'a Kernel>,
    ) -> Result<Vec<(&'a Kernel, Over)>> {
        let k = &self.kernels;
        let partitioned = k.shade_args.is_some();
        let mut s = vec![(k.intersect()?, Over::Rays)];
        s.extend(k.shade_args.iter().map(|a| (a, Over::One)));
        s.push((shade, if partitioned { Over::Hits } else { Over::Rays }));
        s.extend(deferred.map(|d| (d, Over::DeferredRays)));
        s.extend(k.shade_miss.iter().map(|m| (m, Over::Misses)));
        s.push((&k.queue_args, Over::One));
        s.push((k.shadow()?, Over::Shadows));
        s.extend(k.shadow_deferred.iter().map(|d| (d, Over::DeferredShadows)));
        Ok(s)
    }

    /// Records `accumulate` and `film_gather` after the batch `push` describes: its
    /// finished paths go to the film (`sets` must hold the film's).
    fn record_film(&self, cmd: &mut CommandList, sets: &[&DescriptorSet], push: &Push) {
        let k = &self.kernels;
        if let Some(accumulate) = &k.accumulate {
            cmd.dispatch(
                accumulate,
                sets,
                bytemuck::bytes_of(push),
                groups_for(push.path_count),
            );
            cmd.barrier();
        }
        self.film.record_gather(cmd, &k.film_gather, sets, push);
    }

    /// Submits the rest of a batch that ran `depth` bounces and adds its counters.
    fn finish_batch(
        &self,
        cmd: &mut CommandList,
        stats: &mut RenderStats,
        depth: u32,
    ) -> Result<()> {
        let times = cmd.submit_and_wait_timed()?;
        stats.kernel_times.add(&times);
        let c: Vec<Counters> = self.wavefront.counters.read(&self.device)?;
        // Rays queued for a bounce past the budget: paths cut short (none for a
        // max_depth within it, whose last bounce queues nothing).
        if depth == self.bounces {
            stats.cut_paths += c[0].ray_count[(depth % 2) as usize] as u64;
        }
        stats.rays += c[0].rays_traced as u64;
        stats.discarded += c[0].discarded as u64;
        // The last bounce's deferred shadow rays are still in their list.
        stats.deferred += c[0].deferred_total as u64 + c[0].deferred[1] as u64;
        stats.batches += 1;
        Ok(())
    }
}

/// A batch of [`Renderer::for_each_batch`]: (renderer, commands, sample base, pixel
/// base, paths, the film's sample slot of its first path, statistics).
type BatchFn<'a> = &'a mut dyn FnMut(
    &Renderer,
    &mut CommandList,
    u32,
    u32,
    u32,
    u32,
    &mut RenderStats,
) -> Result<()>;

/// Called at each clean sample boundary of a render with the samples done (from the
/// range's first); returns whether to stop there (see
/// [`Renderer::render_film_controlled`]).
pub type BoundaryFn<'a> = &'a mut dyn FnMut(&Renderer, u32) -> Result<bool>;

/// Bounces recorded per submission of a batch (see `Renderer::run_bounces`).
const BOUNCE_CHUNK: u32 = 64;

/// The chunks of bounces of the photon mappers' batches (`Renderer::run_bounces`):
/// photon and SPPM camera batches are small and many (one per iteration), and their
/// paths mostly end within a few bounces, so their first chunk is short.
const SHORT_BOUNCE_CHUNKS: (u32, u32) = (4, BOUNCE_CHUNK);

/// The chunks of bounces of path batches whose budget exceeds one chunk (paths of
/// unbounded length, ended by Russian roulette): most end within a few bounces and the
/// longest within a few dozen, and a batch of 64 bounces then ran some 40 empty ones,
/// four dispatches of about 30 us each (scenes/envmap/envmap_glossy.xml at 256x256,
/// 16 spp: 384 dispatches of each kernel, the last path ending before bounce 24).
/// Submissions after 8, 24 and 56 bounces let such a batch stop at the first of
/// them that finds no path left.
const LONG_BUDGET_CHUNKS: (u32, u32) = (8, BOUNCE_CHUNK);

/// Most paths in one batch: the kernels divide path and pixel indices by a float
/// quotient (shaders/film/divide.glsl), exact for quotients below 2^23; a batch of
/// at most 2^22 paths keeps every quotient below that, whatever the film.
pub const MAX_BATCH_PATHS: u32 = 1 << 22;

/// Paths per batch of a render of `paths` paths (pixels times spp): bounded by memory
/// (path state and film samples: on a CPU device 40 MiB at least and 160 MiB at most,
/// on a GPU 300 MiB) and large enough to fill a GPU.
/// On lavapipe a batch has costs of its own whatever its size (its camera rays, the
/// film gather, a submission and a read-back per chunk of bounces, the last paths'
/// bounces), and larger batches spread them over more paths: from 40 to 160 MiB
/// (209,715 to 838,860 paths), 64 spp at 256 x 256 (3 runs each, rendered in) took
/// 2.35-2.44 -> 2.29-2.32 s on the Cornell box, 1.95-2.08 -> 1.84-1.90 s on
/// media/cube.xml, 1.27-1.35 -> 1.21-1.22 s on textures.xml, 0.79-1.02 -> 0.77-0.79 s
/// on normalmap.xml, and Veach's plates (direct, 128 x 128) 0.221-0.234 -> 0.197-0.203
/// s; 320 MiB gained nothing more. The start-up touches the batch's memory once
/// (`Renderer::warm_up`), about 0.6 ms per MB on lavapipe, so a render of fewer paths
/// gets a batch no larger than it needs, but no smaller than 40 MiB's (tests and
/// callers that render more than the scene's spp keep the batches they had). Images
/// are the same bits whatever the batches (the film sums samples in order).
fn default_capacity(device: &Device, paths: u64) -> u32 {
    let (least, most): (u64, u64) = match device.info().kind {
        DeviceKind::Cpu => (40 << 20, 160 << 20),
        _ => (300 << 20, 300 << 20),
    };
    let per_path = BYTES_PER_PATH + BYTES_PER_SAMPLE_SLOT;
    paths.clamp(least / per_path, most / per_path) as u32
}
