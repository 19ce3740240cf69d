//! Mitsuba 3's particle tracer on the photon mappers' wavefront (`ptracer`,
//! [`Integrator::Ptracer`]).
//!
//! Sample index `s` of a render is the light paths `0 .. width × height` of stream
//! `s` (`PhotonParams::iteration`): `ptracer_emit` connects a point on an emitter to
//! the camera and starts each path, then per bounce `intersect -> ptracer_bounce ->
//! queue_args` connects every surface the path meets to the camera and scatters
//! (`shaders/integrator/ptracer.glsl`). Connections are splatted into the pixel they
//! land in as 64-bit fixed-point integers (atomic adds with a carry), whose sums do not
//! depend on the order the threads add them in; after the sample's last batch
//! `ptracer_fold` adds each pixel's splats to the film sums as one sample of unit
//! weight. The film is then a float left fold over sample indices as for camera paths, so
//! partial renders, resumes and merges behave exactly as the path tracers'
//! (`render::partial`), and the image is the same bits whatever the batch size.
//!
//! [`Integrator::Ptracer`]: crate::render::Integrator::Ptracer

use std::time::Instant;

use crate::gpu::layout::{PhotonParams, Push};
use crate::gpu::{shaders, CommandList, KernelSpec, Spec, SpecValues};
use crate::render::film::FilmSums;

use super::super::error::Result;
use super::super::{groups_for, BoundaryFn, RenderStats, Renderer};
use super::{IntegratorKernels, SceneFeatures};

/// Bytes of splats per pixel: three channels of two 32-bit words.
pub const BYTES_PER_SPLAT_PIXEL: u64 = 24;

/// The particle tracer's kernels, in the order `Photons::new` takes them back: its
/// emission and bounce (in the photon mappers' places), then `ptracer_fold`.
pub fn kernel_specs(f: &SceneFeatures) -> Vec<KernelSpec<'static>> {
    let scene = f
        .traversal
        .specs()
        .with(Spec::SurfaceFeatures, f.surface)
        .with(Spec::Textures, f.textures)
        .with(Spec::FilmFilter, f.film_filter);
    let named = |name, spirv, extra: &[(Spec, u32)]| {
        let spec = extra
            .iter()
            .fold(scene.clone(), |spec, &(s, v)| spec.with(s, v));
        KernelSpec::named(name, spirv, &spec)
    };
    vec![
        named(
            "ptracer_emit",
            shaders::PTRACER_EMIT,
            &[
                (Spec::EmitterKinds, f.emitters),
                (Spec::PtracerThinLens, f.thin_lens),
                (Spec::SensorShape, f.sensor_shape),
            ],
        ),
        named(
            "ptracer_bounce",
            shaders::PTRACER_BOUNCE,
            &[
                (Spec::BsdfKinds, f.bsdfs),
                (Spec::EmitterKinds, f.emitters),
                (Spec::PtracerThinLens, f.thin_lens),
                (Spec::SensorShape, f.sensor_shape),
            ],
        ),
        KernelSpec::named("ptracer_fold", shaders::PTRACER_FOLD, &SpecValues::new()),
    ]
}

impl Renderer {
    /// Light paths per sample index: the full film's pixels.
    pub(in crate::render) fn ptracer_paths(&self) -> u32 {
        self.width * self.height
    }

    /// Records clearing the splats (the start of a render).
    pub(in crate::render) fn ptracer_clear(&self, cmd: &mut CommandList) {
        let splats = &self.photons().map.splats;
        cmd.fill(splats, 0, splats.size(), 0);
        cmd.barrier();
    }

    /// Traces light paths `first .. first + count` (at most a batch) of sample index
    /// `sample`, splatting them; returns after they have run.
    pub(in crate::render) fn ptracer_batch(
        &self,
        cmd: &mut CommandList,
        sample: u32,
        first: u32,
        count: u32,
        stats: &mut RenderStats,
    ) -> Result<()> {
        let base = self.photons().base_params(0, false, self.bounces);
        self.write_photon_params(
            cmd,
            &PhotonParams {
                iteration: sample,
                ..base
            },
        );
        self.trace_photon_batch(cmd, first, count, self.bounces, stats)?;
        stats.batches += 1;
        // trace_photon_batch's photon statistics: no photon is stored here.
        stats.photons = None;
        Ok(())
    }

    /// Adds the splats of the sample index whose light paths all ran to the film, as
    /// one sample, and clears them; returns after it has run.
    pub(in crate::render) fn ptracer_fold(
        &self,
        cmd: &mut CommandList,
        stats: &mut RenderStats,
    ) -> Result<()> {
        let ph = self.photons();
        let IntegratorKernels::Ptracer { fold } = &ph.kernels else {
            unreachable!("the particle tracer's renderer has its kernels")
        };
        let sets = [
            &self.scene_buffers.set,
            &self.wavefront.set,
            &ph.map.set,
            &self.film.set,
        ];
        let push = Push {
            capacity: self.wavefront.capacity,
            ..Default::default()
        };
        let pixels = self.film.geometry.crop_pixels();
        cmd.dispatch(fold, &sets, bytemuck::bytes_of(&push), groups_for(pixels));
        cmd.barrier();
        stats.kernel_times.add(&cmd.submit_and_wait_timed()?);
        Ok(())
    }

    /// Renders samples `first .. first + count` of every pixel with the particle
    /// tracer, continuing from `start`'s sums if given; `boundary` may stop it after any
    /// whole sample index (see [`Renderer::render_film_controlled`]).
    pub(in crate::render) fn render_ptracer(
        &mut self,
        first: u32,
        count: u32,
        start: Option<&FilmSums>,
        progress: &mut dyn FnMut(u64, u64),
        boundary: BoundaryFn,
    ) -> Result<(FilmSums, RenderStats)> {
        let t = Instant::now();
        let mut stats = RenderStats {
            spp: count,
            ..Default::default()
        };
        let mut cmd = self.command_list()?;
        self.start_film(&mut cmd, start)?;
        self.ptracer_clear(&mut cmd);
        let paths = self.ptracer_paths();
        let batch = self.wavefront.capacity;
        let total = paths as u64 * count as u64;
        let mut done = 0u64;
        let end = first + count;
        for sample in first..end {
            let mut a = 0;
            while a < paths {
                let n = batch.min(paths - a);
                self.ptracer_batch(&mut cmd, sample, a, n, &mut stats)?;
                a += n;
                done += n as u64;
                progress(done, total);
            }
            self.ptracer_fold(&mut cmd, &mut stats)?;
            let rendered = sample + 1 - first;
            if sample + 1 < end && boundary(self, rendered)? {
                stats.spp = rendered;
                break;
            }
        }
        let film = self.film.read(&self.device)?;
        stats.seconds = t.elapsed().as_secs_f64();
        Ok((film, stats))
    }
}
