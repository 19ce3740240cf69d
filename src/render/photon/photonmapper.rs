//! Nori's photon mapper on the wavefront (`photonmapper`, [`Integrator::PhotonMapper`]).
//!
//! One photon map of `photonCount` stored photons (photon paths from emitters chosen
//! uniformly, storing at every non-delta surface, the first included), then camera
//! paths: per bounce `intersect -> photon_camera -> queue_args`, where
//! `photon_camera` adds emission, follows delta BSDFs and writes the path's visible
//! point at its first other surface; then `photon_gather` adds the density estimate
//! there, and `accumulate` and `film_gather` put the paths on the film (through its
//! reconstruction filter, as the path tracers' samples).
//!
//! A map split into P passes is gathered P times over the same camera paths (their
//! random numbers repeat), each pass's photons once. The film averages the P samples of
//! a camera path (P times its weight, once per pass), so each pass adds P times its
//! share: the emission P times in the
//! first pass (none in the others), the photons of pass k with the factor
//! P / (π r² N) (`PhotonParams::gather_scale`, `emission_scale`). The mean over the
//! passes is then the emission plus Σ f Φ / (π r² N) over every photon.
//!
//! [`Integrator::PhotonMapper`]: crate::render::Integrator::PhotonMapper

use std::f32::consts::PI;
use std::mem::size_of;
use std::time::Instant;

use crate::gpu::layout::{PhotonParams, Push, VisiblePoint};
use crate::gpu::CommandList;
use crate::render::film::FilmSums;
use crate::render::integrator::{PhotonMapperParams, MAX_BOUNCES};

use super::super::error::Result;
use super::super::{groups_for, BoundaryFn, Over, RenderStats, Renderer, SHORT_BOUNCE_CHUNKS};
use super::{Budget, IntegratorKernels, PhotonStats};

impl Renderer {
    /// Renders samples `first .. first + count` of every pixel with the photon mapper.
    pub(in crate::render) fn render_photonmapper(
        &mut self,
        params: PhotonMapperParams,
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
        let ph = self.photons();
        let radius = params.radius.unwrap_or(ph.bounds.diagonal() / 500.0);
        let mut cmd = self.command_list()?;
        let base = PhotonParams {
            radius,
            ..ph.base_params(0, true, MAX_BOUNCES)
        };
        let plan = self.photon_plan(
            &mut cmd,
            Budget::Stored(params.photon_count),
            base,
            &mut stats,
        )?;
        let passes = plan.passes.len();
        self.start_film(&mut cmd, start)?;
        // Passes gather every sample from their part of the photon map: a render can
        // stop between samples only where the map is one pass.
        let mut never = |_: &Renderer, _: u32| Ok(false);
        let boundary: BoundaryFn = if passes == 1 { boundary } else { &mut never };
        for k in 0..passes {
            let grid = self.photon_pass(&mut cmd, &plan, k, base, radius, &mut stats)?;
            let pass_params = PhotonParams {
                gather_scale: passes as f32 / (PI * radius * radius * plan.emitted as f32),
                emission_scale: if k == 0 { passes as f32 } else { 0.0 },
                ..grid
            };
            self.write_photon_params(&mut cmd, &pass_params);
            let mut pass_progress =
                |done: u64, total: u64| progress(k as u64 * total + done, passes as u64 * total);
            stats.spp = self.for_each_batch(
                &mut cmd,
                first,
                count,
                &mut stats,
                &mut pass_progress,
                &mut |r, cmd, sample, base, n, slot, stats| {
                    r.photon_camera_batch(cmd, sample, base, n, slot, stats)
                },
                &mut *boundary,
            )?;
        }
        stats
            .photons
            .get_or_insert_with(PhotonStats::default)
            .emitted += plan.emitted as u64;
        self.photon_memory_stats(&mut stats);
        let film = self.film.read(&self.device)?;
        stats.seconds = t.elapsed().as_secs_f64();
        Ok((film, stats))
    }

    /// One batch of the photon mapper's camera paths (see [`Renderer::run_batch`] for
    /// the arguments), gathered from the grid built last.
    fn photon_camera_batch(
        &self,
        cmd: &mut CommandList,
        sample_base: u32,
        pixel_base: u32,
        path_count: u32,
        slot: u32,
        stats: &mut RenderStats,
    ) -> Result<()> {
        let ph = self.photons();
        let IntegratorKernels::PhotonMapper { camera, gather } = &ph.kernels else {
            unreachable!("the photon mapper's renderer has the photon mapper's kernels")
        };
        let wf = &self.wavefront;
        let sets = [
            &self.scene_buffers.set,
            &wf.set,
            &ph.map.set,
            &self.film.set,
        ];
        // No visible point yet: bsdf = NONE.
        let vp_bytes = path_count as u64 * size_of::<VisiblePoint>() as u64;
        cmd.fill(&ph.map.visible_points, 0, vp_bytes, u32::MAX);
        let mut push = Push {
            path_count,
            pixel_base,
            sample_base,
            capacity: wf.capacity,
            sample_slot: slot,
            ..Default::default()
        };
        self.start_batch(cmd, &sets, &push)?;
        let k = &self.kernels;
        let stages = [
            (k.intersect()?, Over::Rays),
            (camera, Over::Rays),
            (&k.queue_args, Over::One),
        ];
        let depth = self.run_bounces(
            cmd,
            &sets,
            &mut push,
            &stages,
            None,
            0..self.bounces,
            SHORT_BOUNCE_CHUNKS,
            stats,
        )?;
        stats.kernel_times.add(&cmd.submit_and_wait_timed()?);
        let t = Instant::now();
        let p = bytemuck::bytes_of(&push);
        cmd.dispatch(gather, &sets, p, groups_for(path_count));
        cmd.barrier();
        self.record_film(cmd, &sets, &push);
        self.finish_batch(cmd, stats, depth)?;
        stats
            .photons
            .get_or_insert_with(PhotonStats::default)
            .gather_seconds += t.elapsed().as_secs_f64();
        Ok(())
    }
}
