//! Photon mapping on the wavefront: Nori's `photonmapper` ([`photonmapper`]) and
//! stochastic progressive photon mapping (`sppm`, [`sppm`]).
//!
//! Photon paths run as a wavefront of their own over the same queues, path-state
//! buffer and `intersect` kernel as camera paths: `photon_emit` writes the first ray of
//! each path of a batch, then per bounce `intersect -> photon_bounce -> queue_args`,
//! where `photon_bounce` appends a photon to the photon buffer at every surface whose
//! BSDF is not a delta and continues the path by BSDF sampling with Russian roulette.
//! The photons of a pass are sorted into a hash grid on the GPU ([`grid`]), and the
//! camera paths' visible points gather from it (`shaders/photon/density.glsl`).
//!
//! A photon path's random numbers depend only on its index and the iteration
//! (`shaders/photon/random.glsl`), so the photons of a map are the same whatever the
//! batch size, and the budget's cut (the path at which enough photons are stored) is
//! found exactly from the per-path counts. The photon buffer holds
//! [`PhotonMap::capacity`] photons, set by the device's binding limit and a memory
//! budget; a map that does not fit is split into passes of whole photon paths, each
//! gathered in turn ([`Renderer::photon_plan`]).
//!
//! Descriptor set 2 (`shaders/photon/bindings.glsl`) holds the photon buffers, the grid,
//! the visible points and SPPM's per-pixel state.

pub mod grid;
mod photonmapper;
mod ptracer;
mod sppm;

use std::mem::size_of;
use std::ops::Range;
use std::time::Instant;

use glam::Vec3;

use crate::accel::Bvh;
use crate::gpu::layout::{
    Counters, Photon, PhotonCounters, PhotonParams, PhotonPath, Push, SppmPixel, VisiblePoint,
};
use crate::gpu::{
    shaders, BindingKind, BindingLayout, Buffer, CommandList, DescriptorSet, Device, DeviceKind,
    Kernel, KernelSpec, Location, Spec,
};

use super::error::{Error, Result};
use super::integrator::PhotonBudget;
use super::plan::TraversalConstants;
use super::{groups_for, Integrator, Over, RenderStats, Renderer, SHORT_BOUNCE_CHUNKS};

pub use grid::{GridKernels, GridShape};

/// Bindings of set 2, in order (`shaders/photon/bindings.glsl`).
pub const PHOTON_BINDINGS: u32 = 13;

/// The kind of each binding of set 2: parameters (uniform), counters, photons and
/// their texel view, grid photons and their texel view, buckets and their word view,
/// visible points and their texel view, SPPM pixels, scan block sums, the particle
/// tracer's splats.
pub fn photon_binding_kinds() -> Vec<BindingKind> {
    (0..PHOTON_BINDINGS)
        .map(|b| match b {
            0 => BindingKind::Uniform,
            3 | 5 | 9 => BindingKind::Texels,
            7 => BindingKind::Words,
            _ => BindingKind::Storage,
        })
        .collect()
}

/// GPU memory a photon slot of a pass takes: the photon as stored, its copy in the
/// grid, and at most four buckets of 4 bytes (twice as many buckets as photons,
/// rounded up to a power of two).
pub const BYTES_PER_PHOTON: u64 = 2 * size_of::<Photon>() as u64 + 16;

/// Photon slots of a pass: what a memory budget (256 MiB on a CPU device, 2 GiB on a
/// GPU) and one storage binding hold, or `requested`.
pub fn photon_capacity(device: &Device, requested: Option<u32>) -> u32 {
    let budget: u64 = match device.info().kind {
        DeviceKind::Cpu => 256 << 20,
        _ => 2 << 30,
    };
    let binding = device.info().max_storage_buffer_range / size_of::<Photon>() as u64;
    let cap = (budget / BYTES_PER_PHOTON)
        .min(binding)
        .min(grid::MAX_BUCKETS as u64 / 2) as u32;
    requested.unwrap_or(cap).clamp(1, cap.max(1))
}

/// A sphere and box around the scene's primitives.
#[derive(Debug, Clone, Copy)]
pub struct SceneBounds {
    pub center: Vec3,
    /// Radius of the bounding sphere of the box (half its diagonal).
    pub radius: f32,
    /// Largest |coordinate| of the box, for the grid's precision.
    pub max_abs: f32,
}

impl SceneBounds {
    /// The bounds of the BVH's primitives (a unit sphere at the origin for an empty scene).
    pub fn of(bvh: &Bvh) -> SceneBounds {
        let (lo, hi) = bvh
            .bounds()
            .filter(|(lo, hi)| lo.is_finite() && hi.is_finite())
            .unwrap_or((Vec3::splat(-1.0), Vec3::splat(1.0)));
        SceneBounds {
            center: 0.5 * (lo + hi),
            radius: (0.5 * (hi - lo).length()).max(f32::MIN_POSITIVE),
            max_abs: lo.abs().max(hi.abs()).max_element(),
        }
    }

    /// Length of the box's diagonal (Nori's `getExtents().norm()`).
    pub fn diagonal(&self) -> f32 {
        2.0 * self.radius
    }
}

/// The photon buffer and the grid of one pass, `capacity` photons.
pub struct PhotonStore {
    pub photons: Buffer,
    pub grid_photons: Buffer,
    pub cells: Buffer,
    pub scan_sums: Buffer,
    /// Photon slots.
    pub capacity: u32,
    /// Most buckets of a grid.
    pub max_buckets: u32,
}

impl PhotonStore {
    fn new(device: &Device, capacity: u32) -> Result<PhotonStore> {
        let binding_words = (device.info().max_storage_buffer_range / 4).saturating_sub(1);
        let max_buckets = (2 * capacity as u64)
            .next_power_of_two()
            .clamp(grid::MIN_BUCKETS as u64, grid::MAX_BUCKETS as u64)
            .min(1u64 << binding_words.max(2).ilog2()) as u32;
        let gpu = |label: &str, bytes: u64| Buffer::new(device, label, bytes, Location::Gpu);
        let photon_bytes = capacity as u64 * size_of::<Photon>() as u64;
        Ok(PhotonStore {
            photons: gpu("photons", photon_bytes)?,
            grid_photons: gpu("grid photons", photon_bytes)?,
            cells: gpu("grid buckets", (max_buckets as u64 + 1) * 4)?,
            scan_sums: gpu(
                "grid scan sums",
                GridShape::scan_sums(max_buckets) as u64 * 4,
            )?,
            capacity,
            max_buckets,
        })
    }

    /// Bytes of the photon buffers and the grid.
    pub fn bytes(&self) -> u64 {
        self.photons.size() + self.grid_photons.size() + self.cells.size() + self.scan_sums.size()
    }
}

/// The photon maps' buffers: descriptor set 2.
pub struct PhotonMap {
    pub params: Buffer,
    pub counters: Buffer,
    pub visible_points: Buffer,
    pub sppm_pixels: Buffer,
    /// The particle tracer's splats of one sample index (`shaders/integrator/ptracer.glsl`).
    pub splats: Buffer,
    pub store: PhotonStore,
    pub set: DescriptorSet,
    /// Visible-point slots.
    pub vp_slots: u32,
    /// SPPM pixels held at once (a tile of the image).
    pub sppm_pixels_held: u32,
}

impl PhotonMap {
    /// Buffers for `capacity` photons per pass, `vp_slots` visible points,
    /// `sppm_pixels` SPPM pixels and the splats of `splat_pixels` pixels, as set `2`
    /// of `layout`.
    pub fn new(
        device: &Device,
        layout: &BindingLayout,
        capacity: u32,
        vp_slots: u32,
        sppm_pixels: u32,
        splat_pixels: u32,
    ) -> Result<PhotonMap> {
        let gpu = |label: &str, bytes: u64| Buffer::new(device, label, bytes, Location::Gpu);
        let params = Buffer::from_slice(device, "photon parameters", &[PhotonParams::default()])?;
        let counters = Buffer::from_slice(device, "photon counters", &[PhotonCounters::default()])?;
        let visible_points = gpu(
            "visible points",
            vp_slots.max(1) as u64 * size_of::<VisiblePoint>() as u64,
        )?;
        let sppm = gpu(
            "sppm pixels",
            sppm_pixels.max(1) as u64 * size_of::<SppmPixel>() as u64,
        )?;
        let splats = gpu(
            "splats",
            splat_pixels.max(1) as u64 * ptracer::BYTES_PER_SPLAT_PIXEL,
        )?;
        let store = PhotonStore::new(device, capacity)?;
        let set = Self::bind(
            layout,
            &params,
            &counters,
            &visible_points,
            &sppm,
            &splats,
            &store,
        )?;
        Ok(PhotonMap {
            params,
            counters,
            visible_points,
            sppm_pixels: sppm,
            splats,
            store,
            set,
            vp_slots,
            sppm_pixels_held: sppm_pixels,
        })
    }

    fn bind(
        layout: &BindingLayout,
        params: &Buffer,
        counters: &Buffer,
        visible_points: &Buffer,
        sppm: &Buffer,
        splats: &Buffer,
        store: &PhotonStore,
    ) -> Result<DescriptorSet> {
        Ok(DescriptorSet::new(
            layout,
            2,
            &[
                params,
                counters,
                &store.photons,
                &store.photons,
                &store.grid_photons,
                &store.grid_photons,
                &store.cells,
                &store.cells,
                visible_points,
                visible_points,
                sppm,
                &store.scan_sums,
                splats,
            ],
        )?)
    }

    /// Replaces the photon buffers and grid by ones of `capacity` photons (their
    /// content is lost; visible points and SPPM pixels stay). No GPU work may use the
    /// old ones.
    pub fn resize(&mut self, device: &Device, layout: &BindingLayout, capacity: u32) -> Result<()> {
        let store = PhotonStore::new(device, capacity)?;
        self.set = Self::bind(
            layout,
            &self.params,
            &self.counters,
            &self.visible_points,
            &self.sppm_pixels,
            &self.splats,
            &store,
        )?;
        self.store = store;
        Ok(())
    }

    /// Photon slots of a pass.
    pub fn capacity(&self) -> u32 {
        self.store.capacity
    }
}

/// The specialization constants of the photon kernels: what the scene uses.
#[derive(Debug, Clone)]
pub struct SceneFeatures {
    pub surface: u32,
    pub textures: u32,
    pub emitters: u32,
    pub bsdfs: u32,
    /// The sampler's `SAMPLER_*` kind (camera paths draw from it).
    pub sampler: u32,
    /// The traversal's (the particle tracer's shadow rays to the camera; every
    /// kernel that finds a surface or an emitter's point reads instances' primitives).
    pub traversal: TraversalConstants,
    /// The film's filter (`FILTER_*`), through which the particle tracer splats.
    pub film_filter: u32,
    /// The particle tracer's camera is a thin lens (PTRACER_THIN_LENS).
    pub thin_lens: u32,
    /// The sensor is an irradiancemeter on a shape (SCENE_SENSOR_SHAPE: the particle
    /// tracer connects to points of it).
    pub sensor_shape: u32,
}

impl SceneFeatures {
    /// The instance constants, for a kernel's specialization.
    pub fn instance_specs(&self) -> [(Spec, u32); 2] {
        [
            (Spec::Instances, self.traversal.instances[0]),
            (Spec::InstanceSlots, self.traversal.instances[1]),
        ]
    }
}

/// The kernels only one of the photon mappers runs.
pub enum IntegratorKernels {
    PhotonMapper {
        camera: Kernel,
        gather: Kernel,
    },
    Sppm {
        shade: Kernel,
        record: Kernel,
        gather: Kernel,
        update: Kernel,
    },
    Ptracer {
        fold: Kernel,
    },
}

/// What a photon mapper needs beyond the path tracers' state.
pub struct Photons {
    pub map: PhotonMap,
    emit: Kernel,
    bounce: Kernel,
    grid: GridKernels,
    kernels: IntegratorKernels,
    pub bounds: SceneBounds,
    /// Most photons a pass may hold ([`photon_capacity`]); the map starts smaller,
    /// sized for the integrator's budget, and grows up to this when it overflows.
    pub max_capacity: u32,
    layout: BindingLayout,
}

impl Photons {
    /// Kernels and buffers for `integrator` (a photon mapper) in a scene with
    /// `features` and `bounds`; `pixels` of film, `paths` path slots per batch; at most
    /// `max_photons` photons per pass and `max_sppm_pixels` SPPM pixels held at once
    /// (see [`RenderOptions`](super::RenderOptions)).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        device: &Device,
        layout: &BindingLayout,
        integrator: &Integrator,
        features: SceneFeatures,
        bounds: SceneBounds,
        pixels: u32,
        paths: u32,
        max_photons: Option<u32>,
        max_sppm_pixels: Option<u32>,
    ) -> Result<Photons> {
        let f = features;
        let uniform_choice = matches!(integrator, Integrator::PhotonMapper(_)) as u32;
        let named = |name, spirv, spec: &[(Spec, u32)]| {
            let spec = spec.iter().copied().chain(f.instance_specs()).collect();
            KernelSpec::named(name, spirv, &spec)
        };
        let (surface, textures) = (
            (Spec::SurfaceFeatures, f.surface),
            (Spec::Textures, f.textures),
        );
        let (emitters, bsdfs) = ((Spec::EmitterKinds, f.emitters), (Spec::BsdfKinds, f.bsdfs));
        // Every kernel of the photon mapper, created in parallel (Kernel::new_all) and
        // taken back below in this order.
        // The particle tracer's light paths start and bounce with kernels of their own.
        let mut specs = if let Integrator::Ptracer(_) = integrator {
            ptracer::kernel_specs(&f)
        } else {
            vec![
                named(
                    "photon_emit",
                    shaders::PHOTON_EMIT,
                    &[
                        surface,
                        textures,
                        emitters,
                        (Spec::UniformEmitterChoice, uniform_choice),
                    ],
                ),
                named(
                    "photon_bounce",
                    shaders::PHOTON_BOUNCE,
                    &[surface, textures, bsdfs],
                ),
            ]
        };
        match integrator {
            Integrator::Ptracer(_) => {}
            Integrator::Sppm(p) => specs.extend([
                named(
                    "sppm_shade",
                    shaders::SPPM_SHADE,
                    &[surface, textures, emitters, bsdfs],
                ),
                named("sppm_record", shaders::SPPM_RECORD, &[]),
                named("sppm_gather", shaders::SPPM_GATHER, &[textures, bsdfs]),
                named(
                    "sppm_update",
                    shaders::SPPM_UPDATE,
                    &[(Spec::SppmAlpha, p.alpha.to_bits())],
                ),
            ]),
            Integrator::PhotonMapper(_) => specs.extend([
                named(
                    "photon_camera",
                    shaders::PHOTON_CAMERA,
                    &[
                        surface,
                        textures,
                        emitters,
                        bsdfs,
                        (Spec::SamplerKind, f.sampler),
                    ],
                ),
                named("photon_gather", shaders::PHOTON_GATHER, &[textures, bsdfs]),
            ]),
            other => {
                return Err(Error::Options(format!(
                    "integrator '{}' is not a photon mapper",
                    other.name()
                )))
            }
        }
        specs.extend(GridKernels::specs());
        let mut made = Kernel::new_all(device, layout, &specs)?.into_iter();
        let mut next = || {
            made.next()
                .unwrap_or_else(|| unreachable!("one kernel per spec"))
        };
        let emit = next();
        let bounce = next();
        // Photons a map is expected to need: the stored budget and an eighth, or four
        // per photon path (paths store about 1 / (1 - albedo) photons each).
        let stored_budget = |n: u32| n as u64 + n as u64 / 8 + 4096;
        let (kernels, vp_slots, sppm_pixels, expected) = match integrator {
            Integrator::Sppm(p) => {
                // The visible points and pixel states of a tile of the image must fit
                // one binding each.
                let binding = device.info().max_storage_buffer_range;
                let tile = (binding / size_of::<VisiblePoint>() as u64)
                    .min(binding / size_of::<SppmPixel>() as u64)
                    .min(pixels as u64)
                    .min(max_sppm_pixels.unwrap_or(u32::MAX).max(1) as u64)
                    as u32;
                let kernels = IntegratorKernels::Sppm {
                    shade: next(),
                    record: next(),
                    gather: next(),
                    update: next(),
                };
                let expected = match p.photons {
                    PhotonBudget::Emitted(n) => 4 * n.unwrap_or(pixels) as u64 + 4096,
                    PhotonBudget::Stored(n) => stored_budget(n),
                };
                (kernels, tile, tile, expected)
            }
            Integrator::PhotonMapper(p) => (
                IntegratorKernels::PhotonMapper {
                    camera: next(),
                    gather: next(),
                },
                paths,
                1,
                stored_budget(p.photon_count),
            ),
            // No photons, no visible points: the splats (below).
            Integrator::Ptracer(_) => (IntegratorKernels::Ptracer { fold: next() }, 1, 1, 1),
            _ => unreachable!("not a photon mapper: returned above"),
        };
        let grid = GridKernels::take(&mut next);
        let max_capacity = photon_capacity(device, max_photons);
        let capacity = expected.min(max_capacity as u64) as u32;
        let splat_pixels = match integrator {
            Integrator::Ptracer(_) => pixels,
            _ => 1,
        };
        let map = PhotonMap::new(
            device,
            layout,
            capacity,
            vp_slots,
            sppm_pixels,
            splat_pixels,
        )?;
        Ok(Photons {
            map,
            emit,
            bounce,
            grid,
            kernels,
            bounds,
            max_capacity,
            layout: layout.clone(),
        })
    }

    /// Every kernel, for the warm-up dispatch.
    pub fn kernels(&self) -> Vec<&Kernel> {
        let mut v = vec![&self.emit, &self.bounce];
        v.extend(self.grid.all());
        match &self.kernels {
            IntegratorKernels::PhotonMapper { camera, gather } => v.extend([camera, gather]),
            IntegratorKernels::Sppm {
                shade,
                record,
                gather,
                update,
            } => v.extend([shade, record, gather, update]),
            IntegratorKernels::Ptracer { fold } => v.push(fold),
        }
        v
    }

    /// Parameters of photon passes in this scene: the bounding sphere, the capacity,
    /// no grid yet, every path's photons in.
    fn base_params(&self, iteration: u32, store_first: bool, max_bounces: u32) -> PhotonParams {
        PhotonParams {
            scene_center: self.bounds.center.into(),
            scene_radius: self.bounds.radius,
            capacity: self.map.capacity(),
            path_limit: u32::MAX,
            store_first: store_first as u32,
            max_bounces,
            iteration,
            ..Default::default()
        }
    }
}

/// How many photons a photon map gets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Budget {
    /// This many photon paths.
    Paths(u32),
    /// Photon paths until this many photons are stored (their last path's photons
    /// all kept).
    Stored(u32),
}

/// The passes of one photon map: photon paths `0 .. emitted`, in path ranges whose
/// photons fit the photon buffer.
#[derive(Debug, Clone, PartialEq)]
pub struct PhotonPlan {
    /// Photon paths emitted (N of the density estimate).
    pub emitted: u32,
    /// Path ranges of the passes, in order.
    pub passes: Vec<Range<u32>>,
    /// Photons each pass stores.
    pub stored: Vec<u64>,
    /// The first pass's photons are in the photon buffer already (traced while
    /// planning), `resident_photons` of them (with photons of paths past `emitted`,
    /// which the grid leaves out).
    pub first_resident: bool,
    pub resident_photons: u32,
}

/// The path at which the stored count reaches `target`, among `counts` of paths from
/// `first` on, with `before` stored before them.
fn stored_cut(counts: &[u32], first: u32, before: u64, target: u64) -> Option<u32> {
    let mut sum = before;
    for (k, &c) in counts.iter().enumerate() {
        sum += c as u64;
        if sum >= target {
            return Some(first + k as u32 + 1);
        }
    }
    None
}

/// Paths of the next photon batch (of at most `batch`), from path `a` on with `stored`
/// photons so far: the rest of a path budget; for a stored budget, about as many paths
/// as the rate so far says are missing, and a tenth more (the batch size changes which
/// paths are traced together, never which photons the map gets: the cut is found from
/// per-path counts).
fn next_photon_batch(budget: Budget, batch: u32, a: u32, stored: u64) -> u32 {
    match budget {
        Budget::Paths(n) => batch.min(n - a),
        Budget::Stored(target) => {
            let want = if a == 0 || stored == 0 {
                target as u64
            } else {
                let missing = (target as u64).saturating_sub(stored);
                missing * a as u64 / stored * 11 / 10 + 256
            };
            (batch as u64).min(want).min((u32::MAX - a) as u64) as u32
        }
    }
}

/// Refuses photon paths that store nothing: `a` paths traced, `stored` photons.
fn check_photons_stored(batch: u32, a: u32, stored: u64) -> Result<()> {
    if a == u32::MAX || (stored == 0 && a as u64 >= 64 * batch as u64) {
        return Err(Error::Options(format!(
            "photon paths store no photons: {a} paths left the emitters and \
             {stored} photons were stored (do they reach a surface that is not a \
             mirror or glass?)"
        )));
    }
    Ok(())
}

/// The passes of a photon map of `emitted` paths, whole paths per pass, as many as fit
/// `capacity`: the resident `first_pass` (with `first_stored` photons), then the paths
/// from `rest_start` on by their photon `counts`. Returns each pass's paths and photons.
fn passes_of(
    first_pass: Range<u32>,
    first_stored: u64,
    rest_start: u32,
    counts: &[u32],
    emitted: u32,
    capacity: u32,
) -> Result<(Vec<Range<u32>>, Vec<u64>)> {
    let mut passes = Vec::new();
    let mut stored = Vec::new();
    if !first_pass.is_empty() {
        passes.push(first_pass);
        stored.push(first_stored);
    }
    let mut start = rest_start;
    let mut sum = 0u64;
    for (k, &c) in counts.iter().enumerate() {
        let path = rest_start + k as u32;
        if c as u64 > capacity as u64 {
            return Err(Error::Options(format!(
                "photon path {path} stored {c} photons, more than a photon pass holds \
                 ({capacity}); raise the photon capacity or lower the paths' length"
            )));
        }
        if sum + c as u64 > capacity as u64 {
            passes.push(start..path);
            stored.push(sum);
            start = path;
            sum = 0;
        }
        sum += c as u64;
    }
    if start < emitted {
        passes.push(start..emitted);
        stored.push(sum);
    }
    Ok((passes, stored))
}

/// What photon passes did, for [`RenderStats::photons`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PhotonStats {
    /// Photon paths emitted (N of the density estimates), over all maps.
    pub emitted: u64,
    /// Photons stored in the maps that were gathered from.
    pub stored: u64,
    /// Photon paths traced a second time: counted without storing when a map did not
    /// fit one pass, then traced again pass by pass.
    pub retraced: u64,
    /// Photon maps built (one per pass).
    pub passes: u32,
    /// Wall time of tracing photon paths (emission and bounces), seconds.
    pub trace_seconds: f64,
    /// Wall time of building grids, seconds.
    pub grid_seconds: f64,
    /// Wall time of the gathers (density estimates at visible points), seconds.
    pub gather_seconds: f64,
    /// Photon slots per pass.
    pub capacity: u32,
    /// GPU memory of the photon buffers and the grid per photon slot, bytes.
    pub bytes_per_photon: f64,
}

impl PhotonStats {
    /// Photon paths emitted per second of photon tracing.
    pub fn emitted_per_second(&self) -> f64 {
        self.emitted as f64 / self.trace_seconds
    }

    /// Photons stored per second of photon tracing.
    pub fn stored_per_second(&self) -> f64 {
        self.stored as f64 / self.trace_seconds
    }
}

impl Renderer {
    fn photons(&self) -> &Photons {
        self.photon
            .as_ref()
            .expect("a photon mapper's renderer has its photon state")
    }

    /// Writes the photon pass parameters (recorded in `cmd`).
    fn write_photon_params(&self, cmd: &mut CommandList, params: &PhotonParams) {
        cmd.update(&self.photons().map.params, 0, bytemuck::bytes_of(params));
        cmd.barrier();
    }

    /// Sets the photon counters' stored count (recorded in `cmd`).
    fn set_photons_stored(&self, cmd: &mut CommandList, stored: u32) {
        cmd.update(&self.photons().map.counters, 0, bytemuck::bytes_of(&stored));
        cmd.barrier();
    }

    fn photons_stored(&self) -> Result<u32> {
        let c: Vec<PhotonCounters> = self.photons().map.counters.read(&self.device)?;
        Ok(c[0].stored)
    }

    /// Traces photon paths `first .. first + count` (count at most the batch capacity)
    /// with the parameters written last, appending their photons: `photon_emit`, then
    /// per bounce `intersect -> photon_bounce -> queue_args`. Returns after the batch
    /// has run. Photon paths still going after `max_bounces` surfaces end there (the
    /// parameters' `max_bounces` already stops them).
    fn trace_photon_batch(
        &self,
        cmd: &mut CommandList,
        first: u32,
        count: u32,
        max_bounces: u32,
        stats: &mut RenderStats,
    ) -> Result<()> {
        let t = Instant::now();
        let wf = &self.wavefront;
        let ph = self.photons();
        wf.reset_queues(cmd, 0, count);
        cmd.barrier();
        // The film's set for the particle tracer's splats.
        let sets = [
            &self.scene_buffers.set,
            &wf.set,
            &ph.map.set,
            &self.film.set,
        ];
        let mut push = Push {
            path_count: count,
            pixel_base: first,
            capacity: wf.capacity,
            ..Default::default()
        };
        cmd.dispatch(
            &ph.emit,
            &sets,
            bytemuck::bytes_of(&push),
            groups_for(count),
        );
        cmd.barrier();
        let k = &self.kernels;
        // The emitted rays' queue (0) folded as a bounce's queue_args folds the next:
        // as if bounce 1 of queue 1 had appended them.
        push.queue_in = 1;
        cmd.dispatch(&k.queue_args, &sets, bytemuck::bytes_of(&push), [1, 1, 1]);
        cmd.barrier();
        let stages = [
            (k.intersect()?, Over::Rays),
            (&ph.bounce, Over::Rays),
            (&k.queue_args, Over::One),
        ];
        self.run_bounces(
            cmd,
            &sets,
            &mut push,
            &stages,
            None,
            0..max_bounces,
            SHORT_BOUNCE_CHUNKS,
            stats,
        )?;
        stats.kernel_times.add(&cmd.submit_and_wait_timed()?);
        let c: Vec<Counters> = wf.counters.read(&self.device)?;
        stats.rays += c[0].rays_traced as u64;
        let p = stats.photons.get_or_insert_with(PhotonStats::default);
        p.trace_seconds += t.elapsed().as_secs_f64();
        Ok(())
    }

    /// Photons stored by each of the last batch's `count` paths.
    fn photon_path_counts(&self, count: u32) -> Result<Vec<u32>> {
        let paths: Vec<PhotonPath> = self.wavefront.paths.read(&self.device)?;
        Ok(paths[..count as usize].iter().map(|p| p.stored).collect())
    }

    /// Plans the passes of a photon map with `budget` and the parameters `base`
    /// (stream, first-surface storage, bounces), tracing its first pass into the
    /// photon buffer. Batches of paths are traced while their photons fit; once they
    /// do not, the rest of the map is traced counting only (no photon written), and
    /// the per-path counts cut it into passes of whole paths that fit.
    ///
    /// While the photon buffer is smaller than it may grow ([`Photons::max_capacity`]),
    /// a batch that does not fit grows it instead and the planning starts over.
    fn photon_plan(
        &mut self,
        cmd: &mut CommandList,
        budget: Budget,
        base: PhotonParams,
        stats: &mut RenderStats,
    ) -> Result<PhotonPlan> {
        loop {
            match self.photon_plan_at_capacity(cmd, budget, base, stats)? {
                Ok(plan) => return Ok(plan),
                Err(wanted) => {
                    // At least twice the size, and a quarter more than the photons the
                    // overflowing batch brought the count to.
                    let ph = self.photon.as_mut().expect("a photon mapper");
                    let grown = (2 * ph.map.capacity() as u64)
                        .max(wanted + wanted / 4)
                        .min(ph.max_capacity as u64) as u32;
                    ph.map.resize(&self.device, &ph.layout, grown)?;
                }
            }
        }
    }

    /// [`Self::photon_plan`] with the photon buffer as it is; `Err(photons)` if the first
    /// pass overflowed a buffer that may still grow, at `photons` photons.
    fn photon_plan_at_capacity(
        &self,
        cmd: &mut CommandList,
        budget: Budget,
        base: PhotonParams,
        stats: &mut RenderStats,
    ) -> Result<std::result::Result<PhotonPlan, u64>> {
        let ph = self.photons();
        let capacity = ph.map.capacity();
        let may_grow = capacity < ph.max_capacity;
        let base = PhotonParams { capacity, ..base };
        let batch = self.wavefront.capacity;
        let max_bounces = base.max_bounces;
        self.write_photon_params(cmd, &base);
        self.set_photons_stored(cmd, 0);
        let next_count = |a: u32, stored: u64| next_photon_batch(budget, batch, a, stored);
        let no_photons = |a: u32, stored: u64| check_photons_stored(batch, a, stored);

        // The first pass: store while the photons fit.
        let mut a = 0u32;
        let mut before = 0u64;
        loop {
            let n = next_count(a, before);
            if n == 0 {
                return Ok(Ok(PhotonPlan {
                    emitted: a,
                    passes: std::iter::once(0..a).collect(),
                    stored: vec![before],
                    first_resident: true,
                    resident_photons: before as u32,
                }));
            }
            self.trace_photon_batch(cmd, a, n, max_bounces, stats)?;
            let after = self.photons_stored()? as u64;
            if after > capacity as u64 && may_grow {
                // Trace the map again into a larger buffer.
                let p = stats.photons.get_or_insert_with(PhotonStats::default);
                p.retraced += (a + n) as u64;
                return Ok(Err(after));
            }
            if after > capacity as u64 {
                // This batch does not fit: drop its photons, count from here on.
                self.set_photons_stored(cmd, before as u32);
                break;
            }
            if let Budget::Stored(target) = budget {
                if after >= target as u64 {
                    let counts = self.photon_path_counts(n)?;
                    let end = stored_cut(&counts, a, before, target as u64)
                        .expect("the batch reached the target");
                    let stored = before
                        + counts[..(end - a) as usize]
                            .iter()
                            .map(|&c| c as u64)
                            .sum::<u64>();
                    return Ok(Ok(PhotonPlan {
                        emitted: end,
                        passes: std::iter::once(0..end).collect(),
                        stored: vec![stored],
                        first_resident: true,
                        resident_photons: after as u32,
                    }));
                }
            }
            before = after;
            a += n;
            no_photons(a, before)?;
        }

        // The rest, counting only.
        let first_pass = 0..a;
        let first_stored = before;
        let mut counts: Vec<u32> = Vec::new();
        let rest_start = a;
        let counting = PhotonParams {
            capacity: 0,
            ..base
        };
        self.write_photon_params(cmd, &counting);
        let mut total = before;
        let emitted = loop {
            let n = next_count(a, total);
            if n == 0 {
                break a;
            }
            self.trace_photon_batch(cmd, a, n, max_bounces, stats)?;
            let c = self.photon_path_counts(n)?;
            if let Budget::Stored(target) = budget {
                if let Some(end) = stored_cut(&c, a, total, target as u64) {
                    counts.extend_from_slice(&c[..(end - a) as usize]);
                    break end;
                }
            }
            total += c.iter().map(|&x| x as u64).sum::<u64>();
            counts.extend_from_slice(&c);
            a += n;
            no_photons(a, total)?;
        };
        let p = stats.photons.get_or_insert_with(PhotonStats::default);
        p.retraced += (emitted - rest_start) as u64;

        // Whole paths per pass, as many as fit.
        let (passes, stored) = passes_of(
            first_pass,
            first_stored,
            rest_start,
            &counts,
            emitted,
            capacity,
        )?;
        Ok(Ok(PhotonPlan {
            emitted,
            first_resident: rest_start > 0,
            resident_photons: first_stored as u32,
            passes,
            stored,
        }))
    }

    /// Makes pass `k` of `plan` the photon buffer's content (tracing it unless it is
    /// the resident first pass) and builds its grid for gathers within `max_radius`;
    /// writes `params` with the grid's shape and the plan's path limit, and returns
    /// them.
    fn photon_pass(
        &self,
        cmd: &mut CommandList,
        plan: &PhotonPlan,
        k: usize,
        params: PhotonParams,
        max_radius: f32,
        stats: &mut RenderStats,
    ) -> Result<PhotonParams> {
        let ph = self.photons();
        let range = plan.passes[k].clone();
        let in_buffer = if k == 0 && plan.first_resident {
            plan.resident_photons
        } else {
            self.write_photon_params(cmd, &params);
            self.set_photons_stored(cmd, 0);
            let mut a = range.start;
            while a < range.end {
                let n = self.wavefront.capacity.min(range.end - a);
                self.trace_photon_batch(cmd, a, n, params.max_bounces, stats)?;
                a += n;
            }
            self.photons_stored()?
        };
        if in_buffer > ph.map.capacity() {
            return Err(Error::Options(format!(
                "photon pass {k} stored {in_buffer} photons where its plan fit {} \
                 (photon paths are not deterministic on this device?)",
                ph.map.capacity()
            )));
        }
        let t = Instant::now();
        let shape = GridShape::new(
            plan.stored[k] as u32,
            max_radius,
            ph.bounds.max_abs,
            ph.map.store.max_buckets,
        );
        let params = PhotonParams {
            cell_size: shape.cell,
            inv_cell_size: 1.0 / shape.cell,
            table_mask: shape.buckets - 1,
            path_limit: plan.emitted,
            ..params
        };
        self.write_photon_params(cmd, &params);
        ph.grid
            .record(cmd, &ph.map, &ph.map.set, in_buffer, shape.buckets);
        stats.kernel_times.add(&cmd.submit_and_wait_timed()?);
        let p = stats.photons.get_or_insert_with(PhotonStats::default);
        p.grid_seconds += t.elapsed().as_secs_f64();
        p.passes += 1;
        p.stored += plan.stored[k];
        Ok(params)
    }

    /// Fills in the photon statistics that describe the map's memory.
    fn photon_memory_stats(&self, stats: &mut RenderStats) {
        let map = &self.photons().map;
        let p = stats.photons.get_or_insert_with(PhotonStats::default);
        p.capacity = map.capacity();
        p.bytes_per_photon = map.store.bytes() as f64 / map.capacity() as f64;
    }
}
