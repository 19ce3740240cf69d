//! Stochastic progressive photon mapping on the wavefront (`sppm`,
//! [`Integrator::Sppm`]; Hachisuka and Jensen 2009, with pbrt-v4's update rules).
//!
//! Each iteration (sample index i of every pixel):
//! 1. camera paths, one per pixel: per bounce `intersect -> sppm_shade -> queue_args ->
//!    shadow`, the vertex of `path_mis` plus the pixel's visible point; `sppm_record`
//!    adds the light they found to the pixel's Ld;
//! 2. a photon map of photon stream i (emitters chosen by power, photons stored from
//!    the second surface on: direct light is Ld's), in passes if it does not fit; each
//!    pass's grid is built with cells for the largest radius, and `sppm_gather` adds
//!    its photons within each pixel's radius to the pixel's Φ and M;
//! 3. `sppm_update` shrinks each radius and rescales τ.
//!
//! The image is Ld / iterations + τ / (N_p π r²), N_p the photon paths emitted over
//! all iterations, per pixel, as pbrt-v4 writes it.
//!
//! The pixel filter: SPPM's estimate belongs to its pixel (its radius and flux), so
//! its camera rays start at uniform positions inside the pixel (a box filter) and each
//! pixel's image is its own estimate, as pbrt-v4's SPPM keeps one visible point per
//! pixel. A scene's reconstruction filter does not apply to `sppm` (`render` says so).
//!
//! Where the visible points and pixel states of the whole image do not fit one
//! storage binding each (images of millions of pixels on lavapipe), the image is
//! rendered in tiles of pixels, each through all its iterations; the photon maps of
//! every tile are the same (their random numbers depend on the iteration only).
//!
//! [`Integrator::Sppm`]: crate::render::Integrator::Sppm

use std::f32::consts::PI;
use std::mem::size_of;
use std::time::Instant;

use crate::gpu::layout::{PhotonCounters, PhotonParams, Push, SppmPixel, VisiblePoint};
use crate::gpu::CommandList;
use crate::image::Image;
use crate::render::film::FilmSums;
use crate::render::integrator::{PhotonBudget, SppmParams, MAX_BOUNCES};

use super::super::error::{Error, Result};
use super::super::{groups_for, Over, RenderStats, Renderer, SHORT_BOUNCE_CHUNKS};
use super::{Budget, IntegratorKernels, PhotonStats};

/// Mitsuba 0.6's automatic initial radius: 5 × the scene's bounding-sphere radius /
/// the film's larger side (in pixels), about five pixels' footprint at the scene's
/// scale.
pub fn automatic_radius(scene_radius: f32, width: u32, height: u32) -> f32 {
    5.0 * scene_radius / width.max(height) as f32
}

impl Renderer {
    /// Renders iterations `0 .. count` of SPPM (`first` must be 0: an iteration
    /// needs the radii and fluxes the ones before it left).
    pub(in crate::render) fn render_sppm(
        &mut self,
        params: SppmParams,
        first: u32,
        count: u32,
        progress: &mut dyn FnMut(u64, u64),
    ) -> Result<(FilmSums, RenderStats)> {
        if first != 0 {
            return Err(Error::Options(format!(
                "sppm renders its iterations in order from the first; samples from \
                 {first} on cannot be rendered without those before them"
            )));
        }
        let start = Instant::now();
        let mut stats = RenderStats {
            spp: count,
            ..Default::default()
        };
        let ph = self.photons();
        let pixels = self.width * self.height;
        let r0 = params
            .radius
            .unwrap_or_else(|| automatic_radius(ph.bounds.radius, self.width, self.height));
        let budget = match params.photons {
            PhotonBudget::Emitted(n) => Budget::Paths(n.unwrap_or(pixels)),
            PhotonBudget::Stored(n) => Budget::Stored(n),
        };
        // pbrt's photon paths meet at most maxdepth surfaces.
        let photon_bounces = params.max_depth.unwrap_or(MAX_BOUNCES).min(MAX_BOUNCES);
        let tile = ph.map.sppm_pixels_held;
        let mut rgb = vec![0f32; 3 * pixels as usize];
        let mut cmd = self.command_list()?;
        let mut done = 0u64;
        let total = pixels as u64 * count as u64;
        for tile_start in (0..pixels).step_by(tile as usize) {
            let tile_n = tile.min(pixels - tile_start);
            let fresh = SppmPixel {
                radius: r0,
                ..Default::default()
            };
            self.photons().map.sppm_pixels.write(
                &self.device,
                0,
                bytemuck::cast_slice(&vec![fresh; tile_n as usize]),
            )?;
            let mut max_radius = r0;
            let mut emitted = 0u64;
            let tile_push = Push {
                path_count: tile_n,
                ..Default::default()
            };
            for iteration in 0..count {
                let base = PhotonParams {
                    first_pixel: tile_start,
                    ..self.photons().base_params(iteration, false, photon_bounces)
                };
                // 1. Camera paths and visible points.
                let vp_bytes = tile_n as u64 * size_of::<VisiblePoint>() as u64;
                cmd.fill(&self.photons().map.visible_points, 0, vp_bytes, u32::MAX);
                self.write_photon_params(&mut cmd, &base);
                let mut b = 0;
                while b < tile_n {
                    let n = self.wavefront.capacity.min(tile_n - b);
                    self.sppm_camera_batch(&mut cmd, iteration, tile_start + b, n, &mut stats)?;
                    b += n;
                }
                // 2. Photons, gathered pass by pass.
                let plan = self.photon_plan(&mut cmd, budget, base, &mut stats)?;
                let ph = self.photons();
                let IntegratorKernels::Sppm { gather, update, .. } = &ph.kernels else {
                    unreachable!("the sppm renderer has the sppm kernels")
                };
                let sets = [
                    &self.scene_buffers.set,
                    &self.wavefront.set,
                    &ph.map.set,
                    &self.film.set,
                ];
                for k in 0..plan.passes.len() {
                    self.photon_pass(&mut cmd, &plan, k, base, max_radius, &mut stats)?;
                    let t = Instant::now();
                    cmd.dispatch(
                        gather,
                        &sets,
                        bytemuck::bytes_of(&tile_push),
                        groups_for(tile_n),
                    );
                    cmd.barrier();
                    stats.kernel_times.add(&cmd.submit_and_wait_timed()?);
                    stats
                        .photons
                        .get_or_insert_with(PhotonStats::default)
                        .gather_seconds += t.elapsed().as_secs_f64();
                }
                emitted += plan.emitted as u64;
                // 3. Radii and fluxes.
                cmd.update(
                    &ph.map.counters,
                    0,
                    bytemuck::bytes_of(&PhotonCounters::default()),
                );
                cmd.barrier();
                cmd.dispatch(
                    update,
                    &sets,
                    bytemuck::bytes_of(&tile_push),
                    groups_for(tile_n),
                );
                cmd.barrier();
                stats.kernel_times.add(&cmd.submit_and_wait_timed()?);
                let c: Vec<PhotonCounters> = ph.map.counters.read(&self.device)?;
                max_radius = f32::from_bits(c[0].max_radius);
                done += tile_n as u64;
                progress(done, total);
            }
            stats
                .photons
                .get_or_insert_with(PhotonStats::default)
                .emitted += emitted;
            let state: Vec<SppmPixel> = self.photons().map.sppm_pixels.read(&self.device)?;
            for (q, px) in state[..tile_n as usize].iter().enumerate() {
                let area = emitted as f32 * PI * px.radius * px.radius;
                let o = 3 * (tile_start as usize + q);
                for c in 0..3 {
                    let photons = if area > 0.0 { px.tau[c] / area } else { 0.0 };
                    rgb[o + c] = px.ld[c] / count as f32 + photons;
                }
            }
        }
        self.photon_memory_stats(&mut stats);
        stats.seconds = start.elapsed().as_secs_f64();
        // Each pixel's estimate, weight 1 (the film's geometry is the whole film with
        // a box filter for sppm).
        let film = FilmSums::from_image(&Image {
            width: self.width,
            height: self.height,
            rgb,
        });
        Ok((film, stats))
    }

    /// One batch of SPPM camera paths: `path_count` pixels from `pixel_base` (within
    /// the tile), sample `iteration`.
    fn sppm_camera_batch(
        &self,
        cmd: &mut CommandList,
        iteration: u32,
        pixel_base: u32,
        path_count: u32,
        stats: &mut RenderStats,
    ) -> Result<()> {
        let ph = self.photons();
        let IntegratorKernels::Sppm { shade, record, .. } = &ph.kernels else {
            unreachable!("the sppm renderer has the sppm kernels")
        };
        let wf = &self.wavefront;
        let sets = [
            &self.scene_buffers.set,
            &wf.set,
            &ph.map.set,
            &self.film.set,
        ];
        let mut push = Push {
            path_count,
            pixel_base,
            sample_base: iteration,
            capacity: wf.capacity,
            ..Default::default()
        };
        self.start_batch(cmd, &sets, &push)?;
        let k = &self.kernels;
        let stages = [
            (k.intersect()?, Over::Rays),
            (shade, Over::Rays),
            (&k.queue_args, Over::One),
            (k.shadow()?, Over::Shadows),
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
        cmd.dispatch(
            record,
            &sets,
            bytemuck::bytes_of(&push),
            groups_for(path_count),
        );
        cmd.barrier();
        self.finish_batch(cmd, stats, depth)
    }
}
