//! Rendering in steps of bounded work, for the viewer and for tev: the film keeps
//! accumulating between steps and can be shown ([`Renderer::film_sums_buffer`]) or
//! read ([`Renderer::read_film`]) at any point.
//!
//! A step renders the same batches [`Renderer::render_film`] would (whole samples of
//! every pixel where at most `max_paths` paths hold them, else runs of pixels of one
//! sample), through the same kernels and film; `film_gather` adds every sample in
//! the same order whatever the batching, so samples `0..n` rendered in steps are the
//! render of `0..n`.

use glam::Mat4;

use super::error::{Error, Result};
use super::film::FilmSums;
use super::{Integrator, RenderStats, Renderer};
use crate::gpu::layout::Frame;
use crate::gpu::{Buffer, CommandList};

/// Where a progressive render stands.
pub struct Progressive {
    cmd: CommandList,
    /// The next sample index to render, and (when a sample is rendered in runs of
    /// pixels) the next pixel of it.
    sample: u32,
    pixel_base: u32,
    /// The film's sample slot of the next batch's first path.
    slot: u32,
    /// Samples `0..end` in all; `None`: no end.
    end: Option<u32>,
    /// What the steps so far did (rays, batches, discarded samples, cut paths).
    pub stats: RenderStats,
}

impl Progressive {
    /// Samples of every pixel finished.
    pub fn samples_done(&self) -> u32 {
        self.sample
    }

    /// The sample count it stops at, if any.
    pub fn end(&self) -> Option<u32> {
        self.end
    }

    /// Whether every sample asked for is rendered.
    pub fn finished(&self) -> bool {
        self.end.is_some_and(|e| self.sample >= e)
    }
}

impl Renderer {
    /// Whether the integrator renders in steps ([`Renderer::start_progressive`]): all
    /// but the photon mappers (the particle tracer's samples are independent: it is).
    pub fn is_progressive(&self) -> bool {
        !self.integrator.is_photon_mapper() || matches!(self.integrator, Integrator::Ptracer(_))
    }

    /// Starts rendering samples `0..end` (`None`: without end) in steps: clears the
    /// film. The sampler's pattern is the one [`Renderer::set_sample_count`] set last.
    /// The photon mappers render their photon passes whole and are not progressive.
    pub fn start_progressive(&mut self, end: Option<u32>) -> Result<Progressive> {
        if !self.is_progressive() {
            return Err(Error::Options(format!(
                "integrator '{}' renders its photon passes whole and cannot be shown \
                 progressively; use `wavetrace render` (with --tev to watch it finish)",
                self.integrator.name()
            )));
        }
        if end == Some(0) {
            return Err(Error::Options(
                "samples per pixel must be at least 1".into(),
            ));
        }
        let mut cmd = CommandList::new(&self.device)?;
        self.film.clear(&mut cmd);
        cmd.barrier();
        if let Integrator::Ptracer(_) = self.integrator {
            self.ptracer_clear(&mut cmd);
        }
        cmd.submit_and_wait()?;
        Ok(Progressive {
            cmd,
            sample: 0,
            pixel_base: 0,
            slot: 0,
            end,
            stats: RenderStats::default(),
        })
    }

    /// Renders the next batch of at most `max_paths` paths (at least one path;
    /// never more than a batch holds) and returns how many it rendered: 0 once the
    /// render is finished.
    pub fn step(&mut self, p: &mut Progressive, max_paths: u32) -> Result<u64> {
        if p.finished() {
            return Ok(0);
        }
        let cap = self.wavefront.capacity.min(max_paths.max(1));
        if let Integrator::Ptracer(_) = self.integrator {
            // Light paths of the current sample index; its splats join the film
            // after its last ones.
            let paths = self.ptracer_paths();
            let n = cap.min(paths - p.pixel_base);
            self.ptracer_batch(&mut p.cmd, p.sample, p.pixel_base, n, &mut p.stats)?;
            p.pixel_base += n;
            if p.pixel_base == paths {
                self.ptracer_fold(&mut p.cmd, &mut p.stats)?;
                p.sample += 1;
                p.pixel_base = 0;
            }
            p.stats.spp = p.sample;
            return Ok(n as u64);
        }
        let pixels = self.film.geometry.region_pixels();
        let left = p.end.map_or(u32::MAX, |e| e - p.sample);
        let (base, n) = if p.pixel_base == 0 && pixels <= cap {
            // Whole samples of every pixel.
            (0, (cap / pixels).min(left) * pixels)
        } else {
            (p.pixel_base, cap.min(pixels - p.pixel_base))
        };
        self.run_batch(&mut p.cmd, p.sample, base, n, p.slot, &mut p.stats)?;
        p.slot = self.film.next_slot(p.slot, n);
        let end = base as u64 + n as u64;
        p.sample += (end / pixels as u64) as u32;
        p.pixel_base = (end % pixels as u64) as u32;
        p.stats.spp = p.sample;
        Ok(n as u64)
    }

    /// The film's sums as they stand.
    pub fn read_film(&self) -> Result<FilmSums> {
        self.film.read(&self.device)
    }

    /// The film's sums on the device: per crop pixel (Σ w r, Σ w g, Σ w b, Σ w), four
    /// floats, row-major; what the viewer's tonemap kernel reads.
    pub fn film_sums_buffer(&self) -> &Buffer {
        &self.film.sums
    }

    /// Moves the camera: `to_world` (camera to world, as `scene::Camera::to_world`)
    /// and the horizontal field of view in degrees. Start a new progressive render
    /// after it: the film still holds the old view.
    pub fn set_camera(&mut self, to_world: Mat4, fov_x_deg: f32) -> Result<()> {
        let tan_x = (fov_x_deg.to_radians() * 0.5).tan();
        if !(tan_x.is_finite() && tan_x > 0.0 && to_world.is_finite()) {
            return Err(Error::Options(format!(
                "invalid camera: field of view {fov_x_deg} degrees"
            )));
        }
        self.frame.camera_to_world = to_world.to_cols_array_2d();
        self.frame.tan_half_fov = [tan_x, tan_x * self.height as f32 / self.width as f32];
        // Only the camera's fields: the rest of the uploaded frame stays as it is.
        let frame = &self.wavefront.frame;
        frame.write(
            &self.device,
            std::mem::offset_of!(Frame, camera_to_world) as u64,
            bytemuck::bytes_of(&self.frame.camera_to_world),
        )?;
        frame.write(
            &self.device,
            std::mem::offset_of!(Frame, tan_half_fov) as u64,
            bytemuck::bytes_of(&self.frame.tan_half_fov),
        )?;
        Ok(())
    }
}
