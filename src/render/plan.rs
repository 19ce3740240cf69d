//! What a render of a scene needs, decided before any device is touched: the
//! integrator, film and sampler, the scene's records and BVH, the batch size and the
//! buffers it sizes, which kernels run and with which specialization constants, and
//! the schedule choices (a fused first bounce, deferral, partitioned shading).
//! [`RenderPlan::new`] reads only the scene, the options and the device's
//! capabilities as plain data ([`DeviceInfo`]), so it is tested here without a GPU;
//! [`super::Renderer::new`] builds a plan and allocates and creates what it says.

use crate::accel::{self, Bvh, BvhStats, FlatPrims};
use crate::gpu::layout::{Frame, RayItem, MEDIUM_FEATURE_GRIDS, NONE};
use crate::gpu::{shaders, DeviceInfo, DeviceKind, Spec, SpecValues};
use crate::scene::sampler::{SampleCount, Sampler};
use crate::scene::Scene;

use super::error::{Error, Result};
use super::film::{self, ExtraChannels, Film, FilmGeometry, BYTES_PER_SAMPLE_SLOT};
use super::integrator::Integrator;
use super::photon::{SceneBounds, SceneFeatures};
use super::scene_buffers::SceneRecords;
use super::scene_parts::{array_sizes, scene_arrays, ScenePlan};
use super::wavefront::{QueueBytes, BYTES_PER_PATH};
use super::{choose_sampler, sampler, RenderOptions};

/// Most paths in one batch: the kernels divide path and pixel indices by a float
/// quotient (shaders/film/divide.glsl), exact for quotients below 2^23; a batch of
/// at most 2^22 paths keeps every quotient below that, whatever the film.
pub const MAX_BATCH_PATHS: u32 = 1 << 22;

/// The fewest paths a render must have for a path tracer's first bounce to run fused
/// (see [`Schedule`]): what pays for the extra kernel's creation
/// (docs/performance.md, "Renderer decisions").
const FUSED_MIN_PATHS: u64 = 1 << 21;
/// The largest fraction of camera rays leaving the scene at which `first_bounce`
/// shades bounce 1 too (`Schedule::second_fused`): lanes whose paths ended idle
/// through it (scenes/textures/textures.xml, 23% misses: +6% instructions).
const SECOND_FUSED_MISSES_MAX: f32 = 1.0 / 16.0;

/// Most samples of one pixel in a batch of a render with AOVs: aov.comp traces them in
/// one thread, whose loops (the BVH traversal's, per sample) llvmpipe stops after
/// 65,535 iterations in all; 256 leaves each sample 256.
const AOV_SAMPLES_PER_PIXEL: u32 = 256;

/// One kernel of the path-tracing wavefront, by the part it plays in a batch (the
/// photon mappers' own kernels are `photon::Photons`').
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// A batch's camera rays and first bounce (or two) in one kernel
    /// (shaders/kernels/first_bounce.comp), in place of generate and bounce 0's stages.
    FirstBounce,
    Shade,
    /// In scenes with null surfaces, the full twins of `shade` and `shadow` that take
    /// the rays the fast ones left (shaders/queue/deferral.glsl).
    ShadeDeferred,
    /// `shade` for the bounces whose vertices end their paths (path.glsl's SHADE_LAST).
    ShadeLast,
    /// `shade` with only the miss code, where `intersect` partitions the rays.
    ShadeMiss,
    Shadow,
    ShadowDeferred,
    Intersect,
    Generate,
    FilmGather,
    /// The AOV and moment channels' gather (shaders/kernels/aov.comp).
    Aov,
    /// aov.comp writing each path's AOVs into the ring (filters wider than the box).
    AovSamples,
    Accumulate,
    QueueArgs,
    /// The dispatches of each part of a partitioned bounce.
    ShadeArgs,
}

impl Stage {
    /// The kernel's name (in timings and errors).
    pub fn name(self) -> &'static str {
        match self {
            Stage::FirstBounce => "first_bounce",
            Stage::Shade => "shade",
            Stage::ShadeDeferred => "shade_deferred",
            Stage::ShadeLast => "shade_last",
            Stage::ShadeMiss => "shade_miss",
            Stage::Shadow => "shadow",
            Stage::ShadowDeferred => "shadow_deferred",
            Stage::Intersect => "intersect",
            Stage::Generate => "generate",
            Stage::FilmGather => "film_gather",
            Stage::Aov => "aov",
            Stage::AovSamples => "aov_samples",
            Stage::Accumulate => "accumulate",
            Stage::QueueArgs => "queue_args",
            Stage::ShadeArgs => "shade_args",
        }
    }

    /// The kernel's SPIR-V.
    pub fn spirv(self) -> &'static [u8] {
        match self {
            Stage::FirstBounce => shaders::FIRST_BOUNCE,
            Stage::Shade | Stage::ShadeDeferred | Stage::ShadeLast | Stage::ShadeMiss => {
                shaders::SHADE
            }
            Stage::Shadow | Stage::ShadowDeferred => shaders::SHADOW,
            Stage::Intersect => shaders::INTERSECT,
            Stage::Generate => shaders::GENERATE,
            Stage::FilmGather => shaders::FILM_GATHER,
            Stage::Aov | Stage::AovSamples => shaders::AOV,
            Stage::Accumulate => shaders::ACCUMULATE,
            Stage::QueueArgs => shaders::QUEUE_ARGS,
            Stage::ShadeArgs => shaders::SHADE_ARGS,
        }
    }
}

/// A kernel the render creates: its stage and the values of its specialization
/// constants.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlannedKernel {
    pub stage: Stage,
    pub spec: SpecValues,
}

/// How a batch's bounces run: the choices [`RenderPlan::new`] makes for the scene and
/// the device.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Schedule {
    /// Bounces a batch may run: the integrator's, within RenderOptions::max_bounces.
    pub bounces: u32,
    /// Whether shade and shadow run the medium code (media, null surfaces, or thin
    /// dielectrics for a volumetric integrator); intersect then keeps each ray's
    /// second-nearest hit too.
    pub media: bool,
    /// Whether thin dielectrics and masks are null crossings (for the volumetric
    /// integrators).
    pub thin_null: bool,
    /// Whether `intersect` partitions a bounce's rays into hits and misses
    /// ([`partitions`]).
    pub partitioned: bool,
    /// Where bounces that only end paths meet the emitters alone
    /// (shaders/integrator/path_emitted.glsl): the emitter primitives they meet; else 0.
    pub emitted_only: u32,
    /// Whether `first_bounce` runs a batch's first bounce (or two), and how many.
    pub fused: bool,
    pub fused_bounces: u32,
    /// Whether `first_bounce` shades bounce 1 too (in full, the wavefront going on from
    /// bounce 2): in closed scenes without media, where every camera path continues.
    pub second_fused: bool,
    /// Whether generate and the per-bounce kernels are made (not where `first_bounce`
    /// is the whole path).
    pub wavefront_kernels: bool,
    /// Whether shade and shadow defer the rays that cross more null surfaces than
    /// their traversal found to their full twins (shaders/queue/deferral.glsl).
    pub deferral: bool,
}

/// Everything a render of a scene needs, before a device: see the module's doc.
pub struct RenderPlan {
    pub integrator: Integrator,
    /// The film it renders (SPPM's differs from the scene's, see
    /// `Renderer::film_overridden`) and its geometry.
    pub film_spec: crate::scene::Film,
    pub geometry: FilmGeometry,
    pub sampler: Sampler,
    pub sample_count: SampleCount,
    /// The scene's BVH and GPU records, moved into the upload by the builder.
    pub bvh: Bvh,
    pub records: SceneRecords,
    pub bvh_stats: BvhStats,
    /// The primitives the kernels test in turn.
    pub flat: FlatPrims,
    pub scene_bounds: SceneBounds,
    /// How the scene's arrays are split over bindings.
    pub scene_plan: ScenePlan,
    /// The frame as uploaded.
    pub frame: Frame,
    /// Paths per batch.
    pub capacity: u32,
    pub schedule: Schedule,
    /// The film keeps alpha sums; every camera path counts as covered from the start.
    pub has_alpha: bool,
    pub covered: bool,
    /// What the photon kernels specialize on.
    pub features: SceneFeatures,
    /// Every path-tracing kernel, the largest first (they are created in parallel).
    pub kernels: Vec<PlannedKernel>,
    /// The film's AOV and moment channels (empty: none, and no `aov` kernel).
    pub extra: ExtraChannels,
    /// Per shape record, the global number of its first triangle (a quadric's: its
    /// own number), for the `prim_index` AOV.
    pub shape_first: Vec<u32>,
}

impl RenderPlan {
    /// The plan of a render of `scene` with `options` on a device with `caps`.
    pub fn new(scene: &Scene, options: &RenderOptions, caps: &DeviceInfo) -> Result<RenderPlan> {
        let (integrator, film_spec, geometry, sampler) = resolve(scene, options)?;
        let key_size = geometry.key_size();
        let sample_count = sampler
            .sample_count(scene.spp, key_size.0, key_size.1)
            .map_err(Error::Options)?;
        check(scene, &integrator)?;
        let bvh = accel::instance::scene_bvh(scene).map_err(Error::Options)?;
        let records = SceneRecords::new(scene, &bvh);
        let facts = SceneFacts::of(scene, options, caps, &bvh, &records);
        let scene_plan = ScenePlan::for_device(
            caps,
            array_sizes(&scene_arrays(&bvh, &records)),
            options.scene_part_shift,
        )?;
        let mut frame = scene_frame(scene, options, &integrator, &records);
        if let crate::scene::Projection::Distant { target } = scene.camera.projection {
            let (lo, hi) = bvh.bounds().unwrap_or((glam::Vec3::ZERO, glam::Vec3::ZERO));
            let d = scene
                .camera
                .to_world
                .transform_vector3(glam::Vec3::Z)
                .normalize();
            let m = crate::scene::Projection::distant_frame(
                d,
                target,
                0.5 * (lo + hi),
                0.5 * (hi - lo).length(),
            );
            frame.camera_to_world = m.to_cols_array_2d();
        }
        sampler::set_frame(&mut frame, &sampler, &sample_count, options.seed, key_size);
        for (k, &slot) in facts.emitter_prims.iter().flatten().enumerate() {
            frame.emitter_prims[k / 4][k % 4] = slot;
        }
        let expected_paths = u64::from(geometry.region_pixels())
            * u64::from(options.expected_spp.unwrap_or(scene.spp));
        let mut capacity = batch_capacity(caps, options, &geometry, expected_paths);
        let schedule = Schedule::new(scene, options, caps, &integrator, &facts, expected_paths);
        // Alpha: the film keeps covered weights and shade marks covered camera paths;
        // a visible environment covers every path of the integrators where Mitsuba
        // counts it (`valid_ray` of path and volpath). The photon mappers' camera
        // kernels mark none: no alpha there (see `film_overridden`).
        if check_aovs(scene, options)? > 0 {
            // aov.comp traces the rays of a pixel's samples of a batch in one thread
            // (the box filter's gather): llvmpipe ends a thread's loops after 65,535
            // iterations in all, which a 1 x 1 film at 65,536 spp met after ~6,000
            // samples (the AOVs of the rest went missing). A batch holds at most
            // AOV_SAMPLES_PER_PIXEL samples of each pixel; images are the same bits
            // whatever the batches.
            let most = geometry
                .region_pixels()
                .saturating_mul(AOV_SAMPLES_PER_PIXEL);
            capacity = capacity.min(most.max(1));
        }
        let extra = ExtraChannels::of(
            &scene.integrator.outputs,
            &options.aovs,
            geometry.crop_pixels() as usize,
        );
        if !extra.is_empty() && integrator.is_photon_mapper() {
            return Err(Error::Options(format!(
                "AOV and moment channels are not supported with the integrator '{}' yet",
                integrator.name()
            )));
        }
        // An `aov`'s nested integrator has an alpha channel (`<name>.A`).
        let has_alpha = (film_spec.pixel_format.has_alpha() || extra.inner_rgba.is_some())
            && !integrator.is_photon_mapper();
        let covered = integrator.counts_environment_coverage()
            && !integrator.hide_emitters()
            && records.env_emitter != NONE;
        let mut constants = Constants::of(&integrator, &records, &sampler, &facts, has_alpha);
        constants.sensor_batch = scene.camera.batch.len() as u32;
        let mut kernels = kernels(
            &integrator,
            &schedule,
            &constants,
            film::gather_constants(&film_spec.filter, has_alpha),
            film::reads_paths(&film_spec.filter),
        );
        if !extra.is_empty() {
            let spec = aov_constants(scene, options, &constants, &schedule, &film_spec.filter);
            if !extra.aov_names.is_empty() && !film::reads_paths(&film_spec.filter) {
                kernels.push(PlannedKernel {
                    stage: Stage::AovSamples,
                    spec: spec.clone().with(Spec::FilmAovSamples, 1),
                });
            }
            kernels.push(PlannedKernel {
                stage: Stage::Aov,
                spec,
            });
        }
        let shape_first = scene
            .meshes
            .iter()
            .scan(0u32, |first, m| {
                let f = *first;
                *first += m.indices.len() as u32;
                Some(f)
            })
            .chain(0..scene.quadrics.len() as u32)
            .collect();
        let features = SceneFeatures {
            surface: constants.surface_features,
            textures: constants.textures,
            emitters: constants.emitter_kinds,
            bsdfs: constants.bsdf_kinds,
            sampler: constants.sampler,
            traversal: constants.traversal,
            film_filter: film::filter_constants(&film_spec.filter).0,
            thin_lens: scene.camera.projection.is_thin_lens() as u32,
            sensor_shape: constants.sensor_shape,
        };
        Ok(RenderPlan {
            integrator,
            film_spec,
            geometry,
            sampler,
            sample_count,
            bvh_stats: bvh.stats,
            flat: facts.flat,
            scene_bounds: SceneBounds::of(&bvh),
            bvh,
            records,
            scene_plan,
            frame,
            capacity,
            schedule,
            has_alpha,
            covered,
            features,
            kernels,
            extra,
            shape_first,
        })
    }

    /// The kernel of `stage`, if the render makes it.
    pub fn kernel(&self, stage: Stage) -> Option<&PlannedKernel> {
        self.kernels.iter().find(|k| k.stage == stage)
    }

    /// Whether the render makes the kernel of `stage`.
    pub fn has(&self, stage: Stage) -> bool {
        self.kernel(stage).is_some()
    }

    /// The sizes of the wavefront's queues for a batch of [`Self::capacity`] paths.
    pub fn queue_bytes(&self) -> QueueBytes {
        QueueBytes::new(self.capacity, self.schedule.media)
    }
}

/// The integrator, sampler and film geometry a render of `scene` with `options` uses,
/// as [`super::Renderer::new`] would set them up (without a device); the sampler's
/// [`Sampler::sample_count`] over the geometry's [`FilmGeometry::key_size`] is the
/// count [`super::Renderer::round_sample_count`] gives.
pub fn plan_render(
    scene: &Scene,
    options: &RenderOptions,
) -> Result<(Integrator, Sampler, FilmGeometry)> {
    resolve(scene, options).map(|(i, _, g, s)| (i, s, g))
}

/// What a render of `scene` with `options` uses, before any device: the integrator,
/// the film it renders (SPPM's differs from the scene's, see
/// `Renderer::film_overridden`) and its geometry, and the sampler.
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

/// Why `integrator` cannot render `scene`, if it cannot.
fn check(scene: &Scene, integrator: &Integrator) -> Result<()> {
    let refuse = |message: String| {
        Err(Error::Integrator {
            file: scene.path.clone(),
            line: scene.integrator.line,
            message,
        })
    };
    if integrator.is_photon_mapper() && scene.needs_medium_code() {
        return refuse(format!(
            "integrator '{}' traces light between surfaces only: the scene has \
             participating media or null (index-matched) surfaces; render it with \
             vol_path_mis",
            integrator.name()
        ));
    }
    // The particle tracer connects light paths to the sensor by its sample_direction
    // (importance and the pixel a point projects to, shaders/integrator/ptracer.glsl):
    // Mitsuba 3.9.1's perspective, thinlens and irradiancemeter have one.
    if matches!(integrator, Integrator::Ptracer(_)) {
        use crate::scene::camera::Projection;
        match scene.camera.projection {
            Projection::Perspective
            | Projection::ThinLens { .. }
            | Projection::IrradianceMeter { .. } => {}
            p => {
                let kind = match p {
                    Projection::Orthographic => "orthographic",
                    Projection::RadianceMeter => "radiancemeter",
                    _ => "distant",
                };
                return refuse(format!(
                    "integrator 'ptracer' connects light paths to the sensor by its \
                     sample_direction, which Mitsuba 3.9.1's '{kind}' sensor does not have \
                     (Mitsuba: \"Endpoint::sample_direction(): not implemented!\"); \
                     render this sensor with path"
                ));
            }
        }
    }
    // The particle tracer's camera connections know one camera.
    if matches!(integrator, Integrator::Ptracer(_)) && !scene.camera.batch.is_empty() {
        return refuse(
            "integrator 'ptracer' connects light paths to one camera, not to a batch \
             sensor's several yet; render this sensor with path"
                .to_string(),
        );
    }
    // SPPM lights its visible points by emitter sampling and keeps the photons for
    // indirect light, so a light that emitter sampling never answers (Mitsuba's
    // directionalarea) would light nothing directly.
    if matches!(integrator, Integrator::Sppm(_))
        && scene
            .emitters
            .iter()
            .any(|e| matches!(e, crate::scene::Emitter::DirectionalArea { .. }))
    {
        return refuse(
            "integrator 'sppm' lights what the camera sees directly by emitter sampling, \
             which a directionalarea emitter never answers (as in Mitsuba); render the \
             scene with ptracer or photonmapper"
                .to_string(),
        );
    }
    if integrator.is_photon_mapper() && scene.emitters.is_empty() {
        return refuse(format!(
            "integrator '{}' needs an emitter to shoot photons from; the scene has none",
            integrator.name()
        ));
    }
    let prims = scene.triangle_count() + scene.quadrics.len();
    if prims > accel::BVH_MAX_PRIMS {
        return Err(Error::Options(format!(
            "the scene has {prims} primitives, more than one BVH holds ({}): use fewer \
             triangles (decimate the largest meshes)",
            accel::BVH_MAX_PRIMS
        )));
    }
    Ok(())
}

/// Most primitives of a scene the kernels test each in turn instead of walking its
/// tree, on the device `caps` describes: [`accel::FLAT_PRIMS_MAX_WIDE`] where a load
/// every lane makes from one address is one scalar load and a SIMD vector holds 16
/// lanes or more (llvmpipe at 512 bits reading the scene from storage buffers: its
/// tree walk gathers lane by lane), else [`accel::FLAT_PRIMS_MAX`]. (A layout that
/// cannot bind the storage buffers after all reads the flat primitives through texel
/// buffers: the same image, somewhat slower.)
pub fn flat_prims_max(caps: &DeviceInfo) -> usize {
    let lanes = crate::gpu::device::llvmpipe_bits(&caps.name).map_or(0, |bits| bits / 32);
    if caps.scene_storage && lanes >= 16 {
        accel::FLAT_PRIMS_MAX_WIDE
    } else {
        accel::FLAT_PRIMS_MAX
    }
}

/// What the plan reads from the scene's BVH and records.
struct SceneFacts {
    /// The emitter primitives (at most `MAX_EMITTER_PRIMS`; `None`: more).
    emitter_prims: Option<Vec<u32>>,
    /// Their kinds, a bit per PRIM_* kind.
    emitter_prim_kinds: u32,
    /// Scenes of a few primitives are traced without the tree.
    flat: FlatPrims,
    /// The vertex words of the first of them, where they are kernel constants
    /// (FlatPrims::vertex_words; empty where not).
    flat_vertices: Vec<u32>,
    /// The traversal stack's depth (bvh.glsl).
    bvh_depth: u32,
    /// SCENE_INSTANCES and SCENE_INSTANCE_SLOTS (accel::instance; 0 without).
    instances: [u32; 2],
    /// On CPU devices: the fraction of camera rays that leave the scene
    /// ([`camera_miss_fraction`]).
    camera_misses: Option<f32>,
    /// Whether the scene has an environment emitter.
    environment: bool,
    /// The kinds and grid layouts of the scene's media (MEDIUM_FEATURE_* bits).
    medium_features: u32,
}

impl SceneFacts {
    fn of(
        scene: &Scene,
        options: &RenderOptions,
        caps: &DeviceInfo,
        bvh: &Bvh,
        records: &SceneRecords,
    ) -> SceneFacts {
        let emitter_prims = records.emitter_prims(bvh);
        let emitter_prim_kinds = emitter_prims
            .iter()
            .flatten()
            .fold(0u32, |m, &i| m | 1 << bvh.prims[i as usize].kind);
        // A two-level tree holds every primitive (accel::instance).
        let flat = if bvh.two_level.is_some() {
            FlatPrims::default()
        } else {
            let max = if options.traverse_small_scenes {
                0
            } else {
                flat_prims_max(caps)
            };
            // Where a load every lane makes from one address is one scalar load (and
            // its bounds check), the vertices of the triangles tested in turn are
            // constants of the kernels instead: the same image bits, the Cornell box
            // 1.38 -> 1.21 s at 512 bits with its first 16, 1.06 -> 0.82 s with all 32
            // (docs/performance.md).
            if max >= accel::FLAT_PRIMS_MAX_WIDE {
                FlatPrims::with_vertex_constants(bvh, max)
            } else {
                FlatPrims::of(bvh, max)
            }
        };
        let flat_vertices = flat.vertex_words(bvh);
        let environment = records.env_emitter != NONE;
        SceneFacts {
            emitter_prims,
            emitter_prim_kinds,
            flat,
            flat_vertices,
            bvh_depth: bvh
                .two_level
                .map_or(bvh.stats.stack_depth(), |t| t.stack_depth),
            instances: accel::instance::TwoLevel::constants(bvh.two_level.as_ref()),
            camera_misses: (caps.kind == DeviceKind::Cpu)
                .then(|| camera_miss_fraction(bvh, &scene.camera)),
            environment,
            medium_features: records.medium_features(),
        }
    }
}

/// The frame of a render, but for its sampler fields and emitter primitives.
fn scene_frame(
    scene: &Scene,
    options: &RenderOptions,
    integrator: &Integrator,
    records: &SceneRecords,
) -> Frame {
    let cam = &scene.camera;
    Frame {
        camera_to_world: cam.to_world.to_cols_array_2d(),
        tan_half_fov: cam.tan_half_fov(),
        near_clip: cam.near_clip,
        far_clip: cam.far_clip,
        width: cam.width,
        height: cam.height,
        seed: options.seed,
        point_light_count: records.point_light_count,
        ao_max_t: match integrator {
            Integrator::Ao { max_t, .. } => *max_t,
            _ => f32::INFINITY,
        },
        ao_uniform: matches!(integrator, Integrator::Ao { uniform: true, .. }) as u32,
        max_depth: integrator.max_depth(),
        emitter_count: records.emitters.len() as u32,
        rr_depth: integrator.rr_depth(),
        env_emitter: records.env_emitter,
        hide_emitters: integrator.hide_emitters() as u32,
        camera_medium: scene.camera_medium.unwrap_or(NONE),
        photon_alias: records.photon_alias,
        camera_kind: cam.projection.frame_fields().0,
        aperture_radius: cam.projection.frame_fields().1,
        focus_distance: cam.projection.frame_fields().2,
        ..batch_frame(&cam.batch)
    }
}

/// The `Frame::batch_*` records of a batch sensor's children (all zero for one camera).
fn batch_frame(children: &[crate::scene::Camera]) -> Frame {
    let mut f = Frame::default();
    for (i, c) in children.iter().enumerate() {
        let cols = c.to_world.to_cols_array_2d();
        f.batch_to_world[4 * i..4 * i + 4].copy_from_slice(&cols);
        let [tx, ty] = c.tan_half_fov();
        f.batch_view[i] = [tx, ty, c.near_clip, c.far_clip];
        let (kind, aperture, focus) = c.projection.frame_fields();
        f.batch_lens[i] = [kind, aperture.to_bits(), focus.to_bits(), 0];
    }
    f
}

/// Paths per batch: `options.max_batch_paths`, or what [`default_capacity`] gives a
/// render of `expected_paths`, within what one storage binding holds of each queue
/// and of the film's sample ring.
fn batch_capacity(
    caps: &DeviceInfo,
    options: &RenderOptions,
    geometry: &FilmGeometry,
    expected_paths: u64,
) -> u32 {
    let capacity = options
        .max_batch_paths
        .unwrap_or_else(|| default_capacity(caps.kind, expected_paths))
        .max(1);
    // Keep every queue inside one storage-buffer binding.
    let limit = caps.max_storage_buffer_range / (2 * std::mem::size_of::<RayItem>() as u64);
    capacity
        .min(limit as u32)
        .min(Film::max_batch_paths(caps, geometry))
        .clamp(1, MAX_BATCH_PATHS)
}

/// Paths per batch of a render of `paths` paths (pixels times spp): bounded by memory
/// (path state and film samples: on a CPU device 40 MiB at least and 160 MiB at most,
/// on a GPU 300 MiB) and large enough to fill a GPU. Larger batches spread a batch's
/// own costs over more paths, but a render of fewer paths gets a batch no larger than
/// it needs, since the start-up touches the batch's memory once (docs/performance.md,
/// "Renderer decisions"). Images are the same bits whatever the batches (the film sums
/// samples in order).
fn default_capacity(kind: DeviceKind, paths: u64) -> u32 {
    let (least, most): (u64, u64) = match kind {
        DeviceKind::Cpu => (40 << 20, 160 << 20),
        _ => (300 << 20, 300 << 20),
    };
    let per_path = BYTES_PER_PATH + BYTES_PER_SAMPLE_SLOT;
    paths.clamp(least / per_path, most / per_path) as u32
}

impl Schedule {
    fn new(
        scene: &Scene,
        options: &RenderOptions,
        caps: &DeviceInfo,
        integrator: &Integrator,
        facts: &SceneFacts,
        expected_paths: u64,
    ) -> Schedule {
        // Thin dielectrics and masks are null crossings for the volumetric path
        // tracers, which need the medium code for them.
        let thin_null =
            (scene.has_thin_dielectrics() || scene.has_masks()) && integrator.is_volumetric();
        let media = scene.needs_medium_code() || thin_null;
        let partitioned = partitions(integrator, media, facts.environment);
        // Bounces that only end paths meet the emitters alone (path_emitted.glsl)
        // where the scene has few emitter prims, no environment and no media, from
        // the second bounce on (a camera ray's hit also decides its pixel's alpha).
        let emitted_only = if !media
            && !options.trace_last_bounce
            && !facts.environment
            && !integrator.ends_paths_at(0)
        {
            facts.emitter_prims.as_ref().map_or(0, |p| p.len() as u32)
        } else {
            0
        };
        let bounces = integrator
            .bounces()
            .min(options.max_bounces.unwrap_or(u32::MAX))
            .max(1);
        // On CPU devices the batch's first bounce runs in one kernel (and bounce 1
        // where it ends the paths meeting the emitters alone: then the kernel is the
        // whole path). Where the wavefront goes on after it, the extra kernel costs
        // start-up, so only for renders of FUSED_MIN_PATHS paths or more, and not
        // where over a third of the camera rays leave the scene into an environment,
        // whose misses the wavefront shades apart (docs/performance.md).
        let second_ends = bounces == 2 && integrator.ends_paths_at(1) && emitted_only > 0;
        // Without an environment or media, where (nearly) every camera ray finds a
        // surface, nearly every lane of a SIMD group still has a path at bounce 1
        // (before Russian roulette): shading it in the same kernel keeps its ray, hit
        // and path state out of the queues; its shadow rays still go through the
        // shadow queue, which traces only the lanes that have one (docs/performance.md:
        // the Cornell box -3.4% instructions, glass -7.2%; textures, where 23% of the
        // camera rays miss, would be +6%).
        let second_fused = !second_ends
            && bounces > 2
            && !media
            && !facts.environment
            && !integrator.ends_paths_at(0)
            && !integrator.ends_paths_at(1)
            && facts
                .camera_misses
                .is_some_and(|m| m <= SECOND_FUSED_MISSES_MAX);
        let fused_bounces = 1 + (second_ends || second_fused) as u32;
        let fused = fuses_first_bounce(caps.kind, integrator)
            && !options.wavefront
            && (bounces <= fused_bounces
                || (expected_paths >= FUSED_MIN_PATHS
                    && (!partitioned || facts.camera_misses.is_some_and(|m| m <= 1.0 / 3.0))));
        let wavefront_kernels = !fused || bounces > fused_bounces;
        // Deferral pays on the drivers that run a loop's traversal for every SIMD group
        // (DeviceInfo::deferral_pays), where few rays defer and a deferred one costs
        // little to run again: not with a null sphere or cylinder, which every ray that
        // crosses it must trace again past, nor with grid media, whose tracking
        // shade_deferred repeats (docs/performance.md). first_bounce traces its
        // crossings itself.
        let deferring = media
            && integrator.shades_paths()
            && options.deferral.unwrap_or_else(|| {
                caps.deferral_pays
                    && !scene.has_curved_crossings()
                    && facts.medium_features & MEDIUM_FEATURE_GRIDS == 0
            });
        Schedule {
            bounces,
            media,
            thin_null,
            partitioned,
            emitted_only,
            fused,
            fused_bounces,
            second_fused: fused && second_fused,
            wavefront_kernels,
            deferral: wavefront_kernels && deferring,
        }
    }
}

/// Whether a batch's camera rays and first bounce may run in one kernel, `first_bounce`
/// (and the second bounce too where it ends the paths), instead of generate and a
/// dispatch of each stage: on CPU devices, for the integrators of path.glsl (in scenes
/// with media or null surfaces too, with their medium stage). llvmpipe turns each
/// divergent access to the queues into a loop over its SIMD lanes, and at the first
/// bounce every lane has a path to follow, so handing it from kernel to kernel costs
/// and compaction saves nothing. A GPU keeps the wavefront. ([`Schedule`] decides
/// where it pays.)
fn fuses_first_bounce(kind: DeviceKind, integrator: &Integrator) -> bool {
    kind == DeviceKind::Cpu && integrator.shades_paths()
}

/// The fraction of a 16 x 16 grid of camera rays through pixel centres that meet
/// nothing (traced on the host: [`Schedule`] decides with it whether bounce 0 of a
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
/// (shaders/queue/partition.glsl): llvmpipe runs shade's whole code for a lane whose
/// ray left the scene, so path integrators in scenes with an environment shade the
/// rays that found a surface in SIMD groups of their own and the misses in
/// `shade_miss`, a kernel with only the miss code. The partition costs an atomic per
/// ray, which pays where many rays miss and the environment lights them
/// (docs/performance.md); without an environment a miss adds nothing anyway. The
/// first-hit integrators, the photon mappers and scenes with media (whose medium
/// stage turns misses into scattering events) shade every ray of the queue in one
/// kernel.
fn partitions(integrator: &Integrator, has_media: bool, has_environment: bool) -> bool {
    has_environment && integrator.shades_paths() && !has_media
}

/// The constants every kernel of a render gets from its binding layout, whatever its
/// stage (the photon mappers' and the particle tracer's too): what the device does,
/// not what the scene holds. `SUBGROUPS_IN_ORDER`: `thread_index`
/// (shaders/queue/wavefront.glsl) from the subgroup's number and the lane's where the
/// device keeps a workgroup's invocations in order ([`DeviceInfo::subgroups_in_order`];
/// on llvmpipe every kernel then runs without an integer division per lane, the same
/// image bit for bit).
pub fn layout_constants(device: &DeviceInfo) -> SpecValues {
    SpecValues::new().with(Spec::SubgroupsInOrder, device.subgroups_in_order as u32)
}

/// What the traversal (accel/bvh.glsl) specializes on, in every kernel that finds
/// surfaces: `intersect`, `shade`, `shadow`, the particle tracer's.
#[derive(Debug, Clone)]
pub struct TraversalConstants {
    /// The quadric kinds (SURFACE_FEATURE_* bits): the traversal and the hit geometry
    /// compile the others away.
    pub prim_kinds: u32,
    /// The traversal stack holds at most one entry per level above the deepest leaf
    /// (bvh.glsl).
    pub bvh_depth: u32,
    /// A small scene's primitives and their kinds, tested in turn (accel::FlatPrims).
    pub flat_count: u32,
    pub flat_kinds: u32,
    /// Instances: the hit names' shift (0: none) and their records (accel::instance).
    pub instances: [u32; 2],
    /// The vertex words of the primitives tested in turn, as kernel constants
    /// (`FlatPrims::vertex_words`; empty where they are loaded).
    pub flat_vertices: Vec<u32>,
}

impl TraversalConstants {
    /// The constants, by name.
    pub fn specs(&self) -> SpecValues {
        SpecValues::new()
            .with(Spec::PrimKinds, self.prim_kinds)
            .with(Spec::BvhDepth, self.bvh_depth)
            .with(Spec::FlatPrims, self.flat_count)
            .with(Spec::FlatKinds, self.flat_kinds)
            .with(Spec::Instances, self.instances[0])
            .with(Spec::InstanceSlots, self.instances[1])
            .with_flat_vertices(&self.flat_vertices)
    }
}

/// The values the kernels specialize on: code for features the scene lacks is
/// compiled out.
struct Constants {
    integrator: u32,
    bsdf_kinds: u32,
    textures: u32,
    /// The kinds and grid layouts the scene's media use; homogeneous-only scenes
    /// compile tracking away.
    medium_features: u32,
    power_heuristic: u32,
    emitter_kinds: u32,
    /// Quadric kinds, vertex normals and uvs: hit geometry compiles the absent ones
    /// away.
    surface_features: u32,
    sampler: u32,
    has_alpha: u32,
    emitter_prim_kinds: u32,
    traversal: TraversalConstants,
    /// Whether bounce 0 ends the paths.
    ends_at_0: u32,
    /// Whether the sensor samples a shape (an irradiancemeter).
    sensor_shape: u32,
    /// A batch sensor's number of children, or 0.
    sensor_batch: u32,
}

impl Constants {
    fn of(
        integrator: &Integrator,
        records: &SceneRecords,
        sampler: &Sampler,
        facts: &SceneFacts,
        has_alpha: bool,
    ) -> Constants {
        let prim_kinds = records.prim_kinds();
        let [flat_count, flat_kinds] = facts.flat.constants();
        Constants {
            integrator: integrator.id(),
            bsdf_kinds: records.bsdfs.iter().fold(0u32, |m, b| m | 1 << b.kind),
            textures: records.texture_mask(),
            medium_features: facts.medium_features,
            power_heuristic: integrator.power_heuristic() as u32,
            emitter_kinds: records.emitter_kinds(),
            surface_features: records.surface_features() | prim_kinds,
            sampler: sampler::kind_id(sampler),
            has_alpha: has_alpha as u32,
            emitter_prim_kinds: facts.emitter_prim_kinds,
            traversal: TraversalConstants {
                prim_kinds,
                bvh_depth: facts.bvh_depth,
                flat_count,
                flat_kinds,
                instances: facts.instances,
                flat_vertices: facts.flat_vertices.clone(),
            },
            ends_at_0: integrator.ends_paths_at(0) as u32,
            sensor_shape: records.sensor_shape.is_some() as u32,
            sensor_batch: 0,
        }
    }

    /// The constants of `shade`: `last` for shade_last (the bounces that end paths),
    /// `misses` for shade_miss.
    fn shade(&self, s: &Schedule, last: bool, misses: bool) -> SpecValues {
        // SHADE_RAYS_* (path.glsl): all, hits, misses; shade_last meeting the emitters
        // itself runs over all its rays.
        let rays = match (s.partitioned && !(last && s.emitted_only > 0), misses) {
            (false, _) => 0,
            (true, false) => 1,
            (true, true) => 2,
        };
        self.scene(s)
            .with(Spec::Integrator, self.integrator)
            .with(Spec::BsdfKinds, self.bsdf_kinds)
            .with(Spec::MisPower, self.power_heuristic)
            .with(Spec::EmitterKinds, self.emitter_kinds)
            .with(Spec::SamplerKind, self.sampler)
            .with(Spec::FilmAlpha, self.has_alpha)
            .with(Spec::ShadeLast, last as u32)
            .with(Spec::ShadeRays, rays)
            .with(Spec::EmitterPrims, if last { s.emitted_only } else { 0 })
            .with(
                Spec::EmitterPrimKinds,
                if last { self.emitter_prim_kinds } else { 0xf },
            )
            // No deferral but in shade and its twin (`kernels`).
            .with(Spec::Deferral, 0)
    }

    /// What shade and shadow both read of the scene: its textures, media, primitives
    /// and traversal.
    fn scene(&self, s: &Schedule) -> SpecValues {
        SpecValues::new()
            .with(Spec::Textures, self.textures)
            .with(Spec::HasMedia, s.media as u32)
            .with(Spec::MediumFeatures, self.medium_features)
            .with(Spec::ThinNull, s.thin_null as u32)
            .with(Spec::SurfaceFeatures, self.surface_features)
            .with_all(&self.traversal.specs())
    }

    /// The constants of `shadow`, `mode` its deferral mode (deferral.glsl).
    fn shadow(&self, s: &Schedule, mode: u32) -> SpecValues {
        self.scene(s)
            .with(Spec::Deferral, mode)
            .with(Spec::BsdfKinds, self.bsdf_kinds)
    }

    fn intersect(&self, s: &Schedule) -> SpecValues {
        self.traversal
            .specs()
            .with(Spec::Partition, s.partitioned as u32)
            .with(Spec::SecondHits, s.media as u32)
    }
}

/// Checks the AOVs a render asks for (the scene's `aov` integrator's and `--aov`'s):
/// at most MAX_AOVS, no uv partials of a batch sensor, no name twice; returns their
/// number.
fn check_aovs(scene: &Scene, options: &RenderOptions) -> Result<usize> {
    let outputs = &scene.integrator.outputs;
    let aov_count = outputs.aovs.len() + options.aovs.len();
    if aov_count > crate::scene::integrator::aov::MAX_AOVS {
        return Err(Error::Options(format!(
            "{aov_count} AOVs requested (the scene's aov integrator's and --aov's); \
             wavetrace writes at most {}",
            crate::scene::integrator::aov::MAX_AOVS
        )));
    }
    // aov.comp traces the camera paths' rays again (sensor/sensor_ray.glsl), a batch
    // sensor's children's too, but has the ray differentials of one camera only.
    let partials = outputs.aovs.iter().chain(&options.aovs).find(|a| {
        matches!(
            a.kind,
            crate::scene::integrator::aov::AovKind::DuvDx
                | crate::scene::integrator::aov::AovKind::DuvDy
        )
    });
    if let (Some(a), false) = (partials, scene.camera.batch.is_empty()) {
        return Err(Error::Options(format!(
            "the AOV '{}' of a batch sensor is not supported yet (uv partials need each \
             child camera's ray differentials): render each of its cameras as a sensor \
             of its own",
            a.name
        )));
    }
    if let Some(a) = options
        .aovs
        .iter()
        .find(|a| outputs.aovs.iter().any(|b| b.name == a.name))
    {
        return Err(Error::Options(format!(
            "--aov names '{}', which the scene's aov integrator already writes",
            a.name
        )));
    }
    Ok(aov_count)
}

/// The constants of `aov.comp`: the scene's (as shade's), the film's filter and the
/// AOV kinds (4 bits each, the scene's `aov` first, then `--aov`'s), moments.
fn aov_constants(
    scene: &Scene,
    options: &RenderOptions,
    c: &Constants,
    s: &Schedule,
    filter: &crate::scene::film::Filter,
) -> SpecValues {
    let outputs = &scene.integrator.outputs;
    let kinds =
        outputs
            .aovs
            .iter()
            .chain(&options.aovs)
            .enumerate()
            .fold([0u32; 2], |mut w, (i, a)| {
                w[i / 8] |= (a.kind as u32) << (4 * (i % 8));
                w
            });
    c.scene(s)
        .with(Spec::BsdfKinds, c.bsdf_kinds)
        .with(Spec::EmitterKinds, c.emitter_kinds)
        .with(Spec::SamplerKind, c.sampler)
        .with(Spec::FilmFilter, film::filter_constants(filter).0)
        .with(Spec::FilmFromPaths, film::reads_paths(filter) as u32)
        .with(Spec::FilmAovsLo, kinds[0])
        .with(Spec::FilmAovsHi, kinds[1])
        .with(Spec::FilmMoment, outputs.moment.is_some() as u32)
        .with(Spec::SensorShape, c.sensor_shape)
        .with(Spec::SensorBatch, c.sensor_batch)
}

/// Every kernel a render with `schedule` makes, the largest first; `gather`: the
/// constants of `film_gather`, `reads_paths`: whether it reads the paths itself.
fn kernels(
    integrator: &Integrator,
    s: &Schedule,
    c: &Constants,
    gather: SpecValues,
    reads_paths: bool,
) -> Vec<PlannedKernel> {
    let mut k = Vec::new();
    let mut add = |stage, spec: SpecValues| k.push(PlannedKernel { stage, spec });
    let wavefront = s.wavefront_kernels;
    let paths = !integrator.is_photon_mapper();
    if s.fused {
        // Shade's constants, saying whether bounce 0 or bounce 1 ends the paths, and
        // the emitter primitives bounce 1 meets.
        let second_ends = s.fused_bounces == 2 && !s.second_fused;
        let spec = c
            .shade(s, second_ends, false)
            .with(Spec::FirstEnds, c.ends_at_0)
            .with(Spec::SecondEnds, second_ends as u32)
            .with(Spec::SecondFused, s.second_fused as u32)
            .with(Spec::SensorShape, c.sensor_shape)
            .with(Spec::SensorBatch, c.sensor_batch);
        add(Stage::FirstBounce, spec);
    }
    let shade_with = |mode: u32| c.shade(s, false, false).with(Spec::Deferral, mode);
    if wavefront && paths {
        add(Stage::Shade, shade_with(s.deferral as u32));
    }
    if s.deferral && paths {
        add(Stage::ShadeDeferred, shade_with(2));
    }
    if wavefront && (0..s.bounces).any(|d| integrator.ends_paths_at(d)) {
        add(Stage::ShadeLast, c.shade(s, true, false));
    }
    if wavefront && s.partitioned {
        add(Stage::ShadeMiss, c.shade(s, false, true));
    }
    if wavefront {
        add(Stage::Shadow, c.shadow(s, s.deferral as u32));
    }
    if s.deferral {
        add(Stage::ShadowDeferred, c.shadow(s, 2));
    }
    if wavefront {
        add(Stage::Intersect, c.intersect(s));
    }
    let sampler = SpecValues::new().with(Spec::SamplerKind, c.sampler);
    if !s.fused {
        // An irradiancemeter's generate reads the scene (its shape's points; without
        // one, that code compiles away).
        let generate = c
            .scene(s)
            .with(Spec::SamplerKind, c.sampler)
            .with(Spec::EmitterKinds, c.emitter_kinds)
            .with(Spec::SensorShape, c.sensor_shape)
            .with(Spec::SensorBatch, c.sensor_batch);
        add(Stage::Generate, generate);
    }
    add(Stage::FilmGather, gather);
    if !reads_paths {
        add(Stage::Accumulate, sampler);
    }
    add(Stage::QueueArgs, SpecValues::new());
    if wavefront && s.partitioned {
        add(Stage::ShadeArgs, SpecValues::new());
    }
    k
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::gpu::layout::HitItem;
    use crate::render::wavefront::SECOND_HIT_BYTES;

    /// lavapipe's capabilities (Mesa 22.3.6).
    fn lavapipe() -> DeviceInfo {
        DeviceInfo::lavapipe_for_tests()
    }

    /// llvmpipe at 512 bits (16 lanes) reading the scene from storage buffers (Mesa 26).
    fn wide_llvmpipe() -> DeviceInfo {
        DeviceInfo {
            name: "llvmpipe (LLVM 22.1.8, 512 bits)".into(),
            scene_storage: true,
            deferral_pays: false,
            ..lavapipe()
        }
    }

    /// A discrete GPU's.
    fn gpu() -> DeviceInfo {
        DeviceInfo {
            name: "a discrete GPU".into(),
            kind: DeviceKind::Discrete,
            max_storage_buffer_range: 4 << 30,
            max_texel_buffer_elements: 1 << 27,
            max_memory_allocation_size: 4 << 30,
            device_memory: 16 << 30,
            ..lavapipe()
        }
    }

    /// A shipped scene (scenes/), loaded at a small size.
    fn scene(path: &str) -> Scene {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes")
            .join(path);
        let defines = [("res".to_string(), "32".to_string())];
        crate::scene::load(&path, &defines).unwrap_or_else(|e| panic!("{path:?}: {e}"))
    }

    fn plan(scene: &Scene, options: &RenderOptions, caps: &DeviceInfo) -> RenderPlan {
        RenderPlan::new(scene, options, caps).unwrap_or_else(|e| panic!("plan: {e}"))
    }

    /// The Cornell box's 32 triangles are tested in turn, without the tree, on
    /// llvmpipe at 512 bits reading the scene from storage buffers, and walked in their
    /// tree at 256 bits, from texel buffers, and on a GPU.
    #[test]
    fn small_scenes_go_without_their_tree_on_wide_llvmpipe() {
        let cbox = scene("cbox/cbox_path.xml");
        let wide = wide_llvmpipe();
        let flat = plan(&cbox, &RenderOptions::default(), &wide).flat;
        assert_eq!((flat.count, flat.flat_only), (32, true));
        let texels = DeviceInfo {
            scene_storage: false,
            ..wide.clone()
        };
        let narrow = DeviceInfo {
            name: "llvmpipe (LLVM 22.1.8, 256 bits)".into(),
            ..wide.clone()
        };
        for caps in [texels, narrow, gpu()] {
            let flat = plan(&cbox, &RenderOptions::default(), &caps).flat;
            assert_eq!((flat.count, flat.flat_only), (0, false), "{}", caps.name);
        }
        // RenderOptions::traverse_small_scenes keeps the tree.
        let options = RenderOptions {
            traverse_small_scenes: true,
            ..RenderOptions::default()
        };
        assert!(!plan(&cbox, &options, &wide).flat.flat_only);
    }

    /// On llvmpipe at 16 lanes reading the scene from storage buffers, the vertices of
    /// the primitives tested in turn are constants of the kernels, those of the
    /// Cornell box's first and last (32nd) triangles among them; elsewhere none.
    #[test]
    fn wide_llvmpipe_gets_the_flat_vertices_as_constants() {
        let cbox = scene("cbox/cbox_path.xml");
        let wide = wide_llvmpipe();
        let p = plan(&cbox, &RenderOptions::default(), &wide);
        assert!(p.flat.vertices && p.flat.constants()[0] & accel::FLAT_VERTEX_CONSTANTS != 0);
        let shade = p.kernel(Stage::Shade).expect("shade");
        let ids = shade.spec.ids();
        let bvh = crate::accel::instance::scene_bvh(&cbox).expect("bvh");
        assert_eq!(bvh.prims.len(), 32);
        for k in [0, 31] {
            let p = bvh.prims[k];
            for (i, w) in [p.p0, p.p1, p.p2].into_iter().flatten().enumerate() {
                let id = crate::gpu::spec_ids::flat_vertex(k as u32, i as u32).0;
                assert!(ids.contains(&(id, w.to_bits())), "primitive {k}, word {i}");
            }
        }
        for caps in [lavapipe(), gpu()] {
            let p = plan(&cbox, &RenderOptions::default(), &caps);
            assert!(!p.flat.vertices, "{}", caps.name);
            let ids = p.kernel(Stage::Shade).expect("shade").spec.ids();
            assert!(!ids
                .iter()
                .any(|&(id, _)| id >= crate::gpu::spec_ids::FLAT_VERTEX_BASE));
        }
    }

    #[test]
    fn cornell_box_runs_no_media_code() {
        let p = plan(
            &scene("cbox/cbox_path.xml"),
            &RenderOptions::default(),
            &lavapipe(),
        );
        assert!(!p.schedule.media && !p.schedule.deferral && !p.schedule.partitioned);
        assert!(!p.has(Stage::ShadeDeferred) && !p.has(Stage::ShadowDeferred));
        assert!(!p.has(Stage::ShadeMiss) && !p.has(Stage::ShadeArgs));
        // No second hits: the hit queue holds one hit per path.
        let q = p.queue_bytes();
        assert_eq!(
            q.hits,
            p.capacity as u64 * std::mem::size_of::<HitItem>() as u64
        );
        // shade and shadow with media off and no medium features.
        for stage in [Stage::Shade, Stage::Shadow] {
            let spec = &p.kernel(stage).expect("made").spec;
            let media = (spec.get(Spec::HasMedia), spec.get(Spec::MediumFeatures));
            assert_eq!(media, (Some(0), Some(0)), "{stage:?}");
        }
        assert!(p.has(Stage::Intersect) && p.has(Stage::QueueArgs));
        // The path tracer ends its paths at max_depth: shade_last.
        assert!(p.has(Stage::ShadeLast));
    }

    #[test]
    fn media_cube_defers() {
        let p = plan(
            &scene("media/cube.xml"),
            &RenderOptions::default(),
            &lavapipe(),
        );
        assert!(p.schedule.media && p.schedule.deferral);
        assert!(p.has(Stage::ShadeDeferred) && p.has(Stage::ShadowDeferred));
        // Shade and shadow leave the rays to their twins (mode 1), which run mode 2.
        let mode = |stage| p.kernel(stage).expect("made").spec.get(Spec::Deferral);
        assert_eq!(mode(Stage::Shade), Some(1));
        assert_eq!(mode(Stage::ShadeDeferred), Some(2));
        assert_eq!(mode(Stage::Shadow), Some(1));
        assert_eq!(mode(Stage::ShadowDeferred), Some(2));
        // The medium stage needs the second hits; media scenes never partition.
        let q = p.queue_bytes();
        assert_eq!(
            q.hits,
            p.capacity as u64 * (std::mem::size_of::<HitItem>() as u64 + SECOND_HIT_BYTES)
        );
        assert!(!p.schedule.partitioned);
        let never = RenderOptions {
            deferral: Some(false),
            ..Default::default()
        };
        let p = plan(&scene("media/cube.xml"), &never, &lavapipe());
        assert!(p.schedule.media && !p.schedule.deferral);
        assert!(!p.has(Stage::ShadeDeferred) && !p.has(Stage::ShadowDeferred));
        // Not by default on Mesa 26's lavapipe, where it does not pay; asked for, yes.
        let p = plan(
            &scene("media/cube.xml"),
            &RenderOptions::default(),
            &wide_llvmpipe(),
        );
        assert!(p.schedule.media && !p.schedule.deferral);
        let always = RenderOptions {
            deferral: Some(true),
            ..Default::default()
        };
        let p = plan(&scene("media/cube.xml"), &always, &wide_llvmpipe());
        assert!(p.schedule.deferral && p.has(Stage::ShadowDeferred));
    }

    #[test]
    fn queues_scale_with_the_batch() {
        let cbox = scene("cbox/cbox_path.xml");
        let with = |paths| {
            let options = RenderOptions {
                max_batch_paths: Some(paths),
                ..Default::default()
            };
            plan(&cbox, &options, &lavapipe())
        };
        let (small, large) = (with(1000), with(3000));
        assert_eq!((small.capacity, large.capacity), (1000, 3000));
        assert_eq!(3 * small.queue_bytes().total(), large.queue_bytes().total());
        assert_eq!(
            small.queue_bytes().total(),
            1000 * BYTES_PER_PATH,
            "every path slot's bytes (no second hits)"
        );
        // No queue outgrows one storage binding, nor a batch MAX_BATCH_PATHS.
        let huge = with(u32::MAX);
        assert!(huge.capacity <= MAX_BATCH_PATHS);
        assert!(huge.queue_bytes().rays <= lavapipe().max_storage_buffer_range);
        // Without a size asked for, a render of few paths gets the least batch.
        let default = plan(&cbox, &RenderOptions::default(), &lavapipe());
        let per_path = BYTES_PER_PATH + BYTES_PER_SAMPLE_SLOT;
        assert_eq!(default.capacity as u64, (40 << 20) / per_path);
    }

    #[test]
    fn a_cpu_device_fuses_the_first_bounce_of_direct_lighting() {
        let veach = scene("veach/veach.xml");
        let p = plan(&veach, &RenderOptions::default(), &lavapipe());
        assert!(p.schedule.fused && p.has(Stage::FirstBounce));
        assert!(!p.has(Stage::Generate));
        // A GPU keeps the wavefront, and so does --wavefront.
        let p = plan(&veach, &RenderOptions::default(), &gpu());
        assert!(!p.schedule.fused && !p.has(Stage::FirstBounce));
        assert!(p.has(Stage::Generate) && p.has(Stage::Intersect));
        let wavefront = RenderOptions {
            wavefront: true,
            ..Default::default()
        };
        let p = plan(&veach, &wavefront, &lavapipe());
        assert!(!p.schedule.fused && p.has(Stage::Generate));
    }

    #[test]
    fn a_small_path_traced_render_keeps_the_wavefront() {
        // Fewer than FUSED_MIN_PATHS paths: the fused kernel would not pay.
        let p = plan(
            &scene("cbox/cbox_path.xml"),
            &RenderOptions::default(),
            &lavapipe(),
        );
        assert!(!p.schedule.fused && p.has(Stage::Generate));
        let many = RenderOptions {
            expected_spp: Some((FUSED_MIN_PATHS / (32 * 32)) as u32),
            ..Default::default()
        };
        let p = plan(&scene("cbox/cbox_path.xml"), &many, &lavapipe());
        assert!(p.schedule.fused && p.has(Stage::FirstBounce) && p.has(Stage::Shade));
    }

    #[test]
    fn a_closed_scene_fuses_bounce_1_too() {
        let many = RenderOptions {
            expected_spp: Some((FUSED_MIN_PATHS / (32 * 32)) as u32),
            ..Default::default()
        };
        // The Cornell box: every camera ray finds a wall.
        let p = plan(&scene("cbox/cbox_path.xml"), &many, &lavapipe());
        assert!(p.schedule.second_fused && p.schedule.fused_bounces == 2);
        assert!(p.has(Stage::Shadow) && p.has(Stage::Shade));
        // A quarter of the camera rays of the textures scene miss; the normal map
        // scene has an environment.
        for file in [
            "textures/textures.xml",
            "textures/normalmap.xml",
            "media/cube.xml",
        ] {
            let p = plan(&scene(file), &many, &lavapipe());
            assert!(!p.schedule.second_fused, "{file}");
        }
        // A GPU keeps the wavefront.
        let p = plan(&scene("cbox/cbox_path.xml"), &many, &gpu());
        assert!(!p.schedule.second_fused);
    }

    #[test]
    fn photon_mappers_refuse_media() {
        let options = RenderOptions {
            integrator: Some("photonmapper".into()),
            ..Default::default()
        };
        let e = RenderPlan::new(&scene("media/cube.xml"), &options, &lavapipe())
            .err()
            .expect("refused")
            .to_string();
        assert!(e.contains("participating media"), "{e}");
        // In a scene without media: no shade, the photon kernels shade.
        let p = plan(&scene("cbox/cbox_path.xml"), &options, &lavapipe());
        assert!(!p.has(Stage::Shade) && !p.has(Stage::ShadeDeferred));
    }

    /// The Rust side sets every constant each kernel declares (none is left at its
    /// GLSL default), by the table's ids.
    #[test]
    fn every_kernel_gets_each_constant_it_declares() {
        let many = RenderOptions {
            expected_spp: Some(4096),
            ..Default::default()
        };
        for (file, options) in [
            ("cbox/cbox_path.xml", RenderOptions::default()),
            ("cbox/cbox_path.xml", many.clone()),
            ("media/cube.xml", RenderOptions::default()),
            ("media/cube.xml", many),
            ("veach/veach.xml", RenderOptions::default()),
            ("envmap/envmap_glossy.xml", RenderOptions::default()),
        ] {
            let p = plan(&scene(file), &options, &lavapipe());
            for k in &p.kernels {
                let layout = layout_constants(&lavapipe());
                for (id, name) in crate::gpu::spec::declared(k.stage.spirv()) {
                    // The vertex constants of the primitives tested in turn are read
                    // only where the plan sets them (wide_llvmpipe_gets_the_first_
                    // vertices_as_constants).
                    if name.starts_with("FLAT_P") && !p.flat.vertices {
                        continue;
                    }
                    let set = k
                        .spec
                        .ids()
                        .into_iter()
                        .chain(layout.ids())
                        .any(|(s, _)| s == id);
                    assert!(
                        set,
                        "{file}: {} declares {name} ({id}), unset",
                        k.stage.name()
                    );
                }
            }
        }
    }
}
