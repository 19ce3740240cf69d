//! The wavefront renderer: queues, per-bounce dispatch, integrators, film.
//!
//! A batch of paths runs as `generate -> (intersect -> shade -> queue_args -> shadow)
//! per bounce -> accumulate (not with the box filter) -> film_gather`, every stage one
//! dispatch over a queue in GPU memory. Queue lengths stay on the GPU and drive
//! indirect dispatch, so a whole batch is one submission with no read-back between
//! bounces (Laine, Karras and Aila 2013, "Megakernels Considered Harmful").

pub mod alias;
mod batch;
pub mod emitter_probe;
pub mod error;
pub mod film;
pub mod integrator;
pub mod job;
pub mod partial;
pub mod photon;
pub mod plan;
pub mod progressive;
pub mod sampler;
pub mod scene_buffers;
pub mod scene_parts;
pub mod wavefront;

pub use batch::BoundaryFn;
pub use error::{Error, Result};
pub use film::FilmSums;
pub use integrator::Integrator;
pub use plan::{plan_render, RenderPlan, MAX_BATCH_PATHS};

use std::time::Instant;

use crate::accel::{BvhStats, FlatPrims};
use crate::gpu::layout::{Counters, Frame, Push, WORKGROUP_SIZE};
use crate::gpu::{
    BindingKind, BindingLayout, CommandList, DescriptorSet, Device, Kernel, KernelSpec,
    KernelTimes, SceneAccess,
};
use crate::image::Image;
use crate::scene::sampler::{SampleCount, Sampler, SamplerKind};
use crate::scene::Scene;

use batch::SHORT_BOUNCE_CHUNKS;
use film::{film_binding_kinds, Film, FilmGeometry};
use photon::{photon_binding_kinds, PhotonStats, Photons};
use plan::{PlannedKernel, Schedule, Stage};
use scene_buffers::SceneBuffers;
use scene_parts::{scene_binding_kinds_for, take_scene_arrays, ScenePlan};
use wavefront::{wavefront_binding_kinds, Wavefront};

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
    /// would test each in turn ([`accel::FLAT_PRIMS_MAX`] or
    /// [`accel::FLAT_PRIMS_MAX_WIDE`], `plan::flat_prims_max`; bvh.glsl's
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
    /// AOVs to write beside the radiance (`render --aov`; scene::integrator::aov),
    /// after those of the scene's `aov` integrator.
    pub aovs: Vec<crate::scene::integrator::aov::Aov>,
}

/// Time spent before the first sample, in seconds.
#[derive(Debug, Clone, Default)]
pub struct SetupStats {
    pub bvh: BvhStats,
    /// The primitives the kernels test in turn: every one, instead of traversing the
    /// BVH (`flat.flat_only`), or the few quadrics kept out of the tree (`Bvh::apart`),
    /// before it.
    pub flat: FlatPrims,
    /// How the kernels read the scene's arrays (`ScenePlan::access`).
    pub scene_access: SceneAccess,
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
    /// Where the film has AOV or moment channels: their gather (shaders/kernels/aov.comp).
    aov: Option<Kernel>,
    /// Where AOVs go through a filter wider than the box: their per-path pass into the
    /// ring (aov.comp with FILM_AOV_SAMPLES).
    aov_samples: Option<Kernel>,
    /// Where a CPU device runs a batch's camera rays and first bounce in one kernel
    /// (shaders/kernels/first_bounce.comp; see [`fuses_first_bounce`]): it, in place of
    /// generate and bounce 0 (and of bounce 1 where that ends the paths).
    first_bounce: Option<Kernel>,
    /// The bounces `first_bounce` runs: 1, or 2 where bounce 1 ends the paths or it
    /// shades bounce 1 in full (`Schedule::second_fused`).
    fused_bounces: u32,
    /// Whether `first_bounce` shades bounce 1 in full, leaving its shadow rays to the
    /// shadow queue.
    second_fused: bool,
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

/// Creates the kernels of `planned` in parallel ([`Kernel::new_all`]), every one
/// inlined before the driver sees it, since that makes the pipelines much faster to
/// create on lavapipe (docs/performance.md, "Renderer decisions").
fn make_kernels(
    device: &Device,
    layout: &BindingLayout,
    planned: &[PlannedKernel],
    schedule: &Schedule,
) -> Result<Kernels> {
    let specs: Vec<KernelSpec> = planned
        .iter()
        .map(|k| KernelSpec::named(k.stage.name(), k.stage.spirv(), &k.spec).inlined(true))
        .collect();
    let mut made: Vec<(Stage, Option<Kernel>)> = planned
        .iter()
        .map(|k| k.stage)
        .zip(
            Kernel::new_all(device, layout, &specs)?
                .into_iter()
                .map(Some),
        )
        .collect();
    let mut take = |stage: Stage| {
        made.iter_mut()
            .find(|(s, _)| *s == stage)
            .and_then(|(_, k)| k.take())
    };
    let required = |kernel: Option<Kernel>, stage: Stage| {
        kernel.ok_or_else(|| {
            Error::Options(format!(
                "internal error: the render plan has no '{}' kernel",
                stage.name()
            ))
        })
    };
    Ok(Kernels {
        generate: take(Stage::Generate),
        intersect: take(Stage::Intersect),
        shade: take(Stage::Shade),
        shade_last: take(Stage::ShadeLast),
        last_meets_emitters: schedule.emitted_only > 0,
        shade_args: take(Stage::ShadeArgs),
        shade_miss: take(Stage::ShadeMiss),
        shadow: take(Stage::Shadow),
        shade_deferred: take(Stage::ShadeDeferred),
        shadow_deferred: take(Stage::ShadowDeferred),
        queue_args: required(take(Stage::QueueArgs), Stage::QueueArgs)?,
        accumulate: take(Stage::Accumulate),
        film_gather: required(take(Stage::FilmGather), Stage::FilmGather)?,
        aov: take(Stage::Aov),
        aov_samples: take(Stage::AovSamples),
        first_bounce: take(Stage::FirstBounce),
        fused_bounces: schedule.fused_bounces,
        second_fused: schedule.second_fused,
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

/// Workgroups for `n` threads on a 2D grid (at most 65535 per dimension); the same
/// rule as `groups_for` in queue_args.comp.
pub(crate) fn groups_for(n: u32) -> [u32; 3] {
    let groups = n.div_ceil(WORKGROUP_SIZE);
    let x = groups.min(65535);
    let y = if x == 0 { 1 } else { groups.div_ceil(x) };
    [x, y, 1]
}

impl Renderer {
    /// Prepares `scene` on `device`: plans the render ([`RenderPlan::new`]) and builds
    /// the plan ([`Renderer::build`]).
    pub fn new(device: &Device, scene: &Scene, options: &RenderOptions) -> Result<Renderer> {
        let plan = RenderPlan::new(scene, options, device.info())?;
        Renderer::build(device, plan, options)
    }

    /// Allocates the buffers and creates the pipelines `plan` says on `device`, and
    /// dispatches every kernel once (see [`Renderer::warm_up`]).
    pub fn build(device: &Device, plan: RenderPlan, options: &RenderOptions) -> Result<Renderer> {
        let RenderPlan {
            integrator,
            film_spec,
            geometry,
            sampler,
            sample_count,
            bvh,
            mut records,
            bvh_stats,
            flat,
            scene_bounds,
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
        } = plan;
        let t = Instant::now();
        let others = [
            wavefront_binding_kinds(),
            photon_binding_kinds(),
            film_binding_kinds(),
        ];
        let other_storage = others
            .iter()
            .flatten()
            .filter(|&&k| k == BindingKind::Storage)
            .count();
        let scene_access = scene_plan.access(device.info(), other_storage as u32);
        let mut kinds = vec![scene_binding_kinds_for(scene_access)];
        kinds.extend(others);
        let mut layout_spec = scene_plan.spec();
        layout_spec.extend(plan::layout_constants(device.info()).ids());
        let layout = BindingLayout::with_spec(
            device,
            &kinds,
            std::mem::size_of::<Push>() as u32,
            &layout_spec,
            scene_access,
        )?;
        // The BVH and the large records are moved into the upload, which frees each
        // once it is on the device.
        let arrays = take_scene_arrays(bvh, &mut records);
        let scene_buffers = SceneBuffers::upload_planned(device, &layout, arrays, scene_plan)?;
        let wavefront = Wavefront::new(device, &layout, capacity, &frame, schedule.media)?;
        let key_size = geometry.key_size();
        let film = Film::new(
            device,
            &layout,
            geometry,
            film_spec.filter,
            has_alpha,
            covered,
            capacity,
            extra,
            &shape_first,
        )?;
        let upload_seconds = t.elapsed().as_secs_f64();

        let t = Instant::now();
        let kernels = make_kernels(device, &layout, &kernels, &schedule)?;
        // The photon mappers' kernels and buffers (their buffers are small until a
        // photon map needs more).
        let photon = if integrator.is_photon_mapper() {
            Some(Photons::new(
                device,
                &layout,
                &integrator,
                features,
                scene_bounds,
                frame.width * frame.height,
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
            bounces: schedule.bounces,
            integrator,
            kernels,
            scene_buffers,
            wavefront,
            photon,
            film,
            width: frame.width,
            height: frame.height,
            key_size,
            timestamps: options.timestamps,
            frame,
            sampler,
            seed: options.seed,
            sample_count,
            setup: SetupStats {
                bvh: bvh_stats,
                flat,
                scene_access,
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
        kernels.extend(&k.aov);
        kernels.extend(&k.aov_samples);
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
            Integrator::Ptracer(_) => {
                return self.render_ptracer(first, count, start, progress, boundary)
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
}
