//! The film on the GPU: per pixel the filter-weighted sum of sample values and the sum
//! of weights (and of covered weights, for alpha), the one representation every
//! render ends in; the image is their quotient ([`FilmSums::develop`]).
//!
//! How a sample reaches the pixels around it, without atomics and the same whatever
//! the batching (`shaders/film/film.glsl`, `shaders/kernels/film_gather.comp`):
//! 1. `generate` starts each camera ray at the sample's position in its pixel
//!    (`film_sample_position`: the sampler's offset, kept to 1/32768 pixel);
//! 2. `accumulate` stores each finished sample in its slot of a ring buffer: value,
//!    position (the same function again) and flags (finite? covered?), 16 bytes;
//! 3. `film_gather` adds to each crop pixel, for every sample index whose last
//!    neighbouring pixel the batch rendered, the filter-weighted values of all its
//!    neighbours (the pixels within the filter's reach). The ring is large enough to
//!    still hold the previous batch's samples a pixel needs.
//!
//! The box filter skips step 2: a sample weighs 1 in its own pixel and no other,
//! so `film_gather` reads the pixel's samples from the batch's paths directly
//! ([`Film::reads_paths`]), with the same sums in the same order and one store and
//! one load of every sample fewer (callgrind, see the commit that made it).
//!
//! Speed (lavapipe, one thread, 64 x 64 pixels at 64 spp of Mitsuba's Cornell box):
//! storing each sample's 2 (2n + 1) filter weights instead of its position made the
//! gather no faster: llvmpipe gathers a texel or a word alike, and the loads, not the
//! filter, cost most. One texel per neighbour is the floor.
//!
//! Which pixels are sampled ([`FilmGeometry`]): those of the crop window and those
//! around it whose samples its pixels' filter reaches, within the film (or, with
//! `sample_border`, within the film and its border, as Mitsuba samples it). Every
//! pixel draws its random numbers by its key in the full film, so a crop window is
//! bit for bit the same window of the full render. Mitsuba instead samples only the
//! crop window (and its border with `sample_border`): without `sample_border`, its
//! crop's edge pixels see samples from one side only and differ (in expectation
//! slightly, in noise entirely) from its full render.

use crate::gpu::layout::{
    FilmParams, Push, FILTER_BOX, FILTER_GAUSSIAN, FILTER_LANCZOS, FILTER_MITCHELL, FILTER_TENT,
};
use crate::gpu::{
    BindingKind, BindingLayout, Buffer, CommandList, DescriptorSet, Device, DeviceInfo, Kernel,
    Spec, SpecValues,
};
use crate::image::{self, Image};
use crate::scene::film::{ComponentFormat, Crop, FileFormat, Filter, PixelFormat};
use crate::scene::integrator::aov::{Aov, Outputs};

use super::error::{Error, Result};
use super::groups_for;

/// Bytes of one slot of the sample ring: value, position and flags.
pub const BYTES_PER_SAMPLE_SLOT: u64 = 16;

/// The kinds of the film's bindings (descriptor set 3, `shaders/film/film.glsl`):
/// parameters, sums, alpha sums, the sample ring written as a storage buffer and
/// read through a texel view.
pub fn film_binding_kinds() -> Vec<BindingKind> {
    vec![
        BindingKind::Uniform,
        BindingKind::Storage,
        BindingKind::Storage,
        BindingKind::Storage,
        BindingKind::Texels,
        // aov.comp's AOV sums, moment sums, shapes' first triangles and AOV ring.
        BindingKind::Storage,
        BindingKind::Storage,
        BindingKind::Storage,
        BindingKind::Storage,
    ]
}

/// The descriptor set of the film (after the photon mappers' set 2).
pub const FILM_SET: u32 = 3;

/// Which pixels a render samples and which it keeps, in full-film pixel coordinates
/// (the top-left pixel is (0, 0); a sampled border lies at negative coordinates and
/// past the width and height).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FilmGeometry {
    /// The full film's size.
    pub width: u32,
    pub height: u32,
    /// The pixels kept (the output image).
    pub crop: Crop,
    /// The pixels sampled: origin and size.
    pub region_x: i32,
    pub region_y: i32,
    pub region_width: u32,
    pub region_height: u32,
    /// Pixels sampled beyond each edge of the film (`sample_border`).
    pub border: u32,
    /// Pixels a sample reaches on each side of its own ([`Filter::reach`]).
    pub reach: u32,
}

/// Most pixels a render may sample (2^30: the kernels index them with 32-bit ints).
const MAX_REGION_PIXELS: u64 = 1 << 30;

impl FilmGeometry {
    /// The grid of pixel keys (`film_pixel_key` in shaders/film/film.glsl): the full
    /// film with its sampled border on every side. The sampler draws each key's
    /// numbers, so a crop window draws those of the full render.
    pub fn key_size(&self) -> (u32, u32) {
        (self.width + 2 * self.border, self.height + 2 * self.border)
    }

    /// The geometry of a `width` x `height` film rendering `crop` (`None`: all of it)
    /// with `filter`, sampling the border if `sample_border`.
    pub fn new(
        width: u32,
        height: u32,
        crop: Option<Crop>,
        filter: &Filter,
        sample_border: bool,
    ) -> Result<FilmGeometry> {
        if width == 0 || height == 0 {
            return Err(Error::Options(format!(
                "film of {width}x{height} pixels is empty"
            )));
        }
        let crop = crop.unwrap_or(Crop {
            x: 0,
            y: 0,
            width,
            height,
        });
        if crop.width == 0
            || crop.height == 0
            || u64::from(crop.x) + u64::from(crop.width) > u64::from(width)
            || u64::from(crop.y) + u64::from(crop.height) > u64::from(height)
        {
            return Err(Error::Options(format!(
                "the crop window {}x{} at ({}, {}) does not fit in the {width}x{height} film",
                crop.width, crop.height, crop.x, crop.y
            )));
        }
        let border = if sample_border {
            filter.border_size()
        } else {
            0
        };
        let reach = filter.reach();
        // The crop window grown by the reach, within the film and its border.
        let span = |start: u32, len: u32, size: u32| {
            let lo = (i64::from(start) - i64::from(reach)).max(-i64::from(border));
            let hi = (i64::from(start) + i64::from(len) + i64::from(reach))
                .min(i64::from(size) + i64::from(border));
            (lo, hi - lo)
        };
        let (x, w) = span(crop.x, crop.width, width);
        let (y, h) = span(crop.y, crop.height, height);
        let key_pixels = (u64::from(width) + 2 * u64::from(border))
            * (u64::from(height) + 2 * u64::from(border));
        if (w as u64) * (h as u64) > MAX_REGION_PIXELS || key_pixels > u64::from(u32::MAX) {
            return Err(Error::Options(format!(
                "film of {width}x{height} pixels is too large"
            )));
        }
        Ok(FilmGeometry {
            width,
            height,
            crop,
            region_x: x as i32,
            region_y: y as i32,
            region_width: w as u32,
            region_height: h as u32,
            border,
            reach,
        })
    }

    /// Pixels sampled.
    pub fn region_pixels(&self) -> u32 {
        self.region_width * self.region_height
    }

    /// Pixels kept.
    pub fn crop_pixels(&self) -> u32 {
        self.crop.width * self.crop.height
    }

    /// The key pixel (x, y) draws its random numbers with: its row-major index in the
    /// film with its sampled border (`film_pixel_key` in film.glsl). Without a border
    /// it is y * width + x.
    pub fn key(&self, x: i32, y: i32) -> u32 {
        let b = self.border as i32;
        (y + b) as u32 * (self.width + 2 * self.border) + (x + b) as u32
    }

    /// The most samples by which a pixel's first neighbour precedes its last in the
    /// order samples are rendered: what the ring must hold beyond one batch.
    pub fn ring_span(&self) -> u32 {
        2 * self.reach * self.region_width + 2 * self.reach
    }

    /// The crop rows `film_gather` must visit after a batch of `count` samples
    /// starting at sample `first` of the region's pixels (of one sample index, or
    /// whole sample indices from pixel 0): (first row, rows). The rows whose pixels'
    /// last neighbour lies in the batch; the kernel picks the pixels exactly.
    pub fn gather_rows(&self, first: u32, count: u32) -> (u32, u32) {
        let pixels = self.region_pixels();
        if first == 0 && count.is_multiple_of(pixels) {
            return (0, self.crop.height);
        }
        let w = self.region_width as i64;
        let (first_row, last_row) = (first as i64 / w, (first + count - 1) as i64 / w);
        let n = self.reach as i64;
        // A pixel in region row y has its last neighbour in row min(y + n, h - 1).
        let lo = first_row - n;
        let hi = if last_row >= self.region_height as i64 - 1 {
            self.region_height as i64 - 1
        } else {
            last_row - n
        };
        // Region rows to crop rows.
        let shift = self.crop.y as i64 - self.region_y as i64;
        let lo = (lo - shift).max(0);
        let hi = (hi - shift).min(self.crop.height as i64 - 1);
        if hi < lo {
            (0, 0)
        } else {
            (lo as u32, (hi - lo + 1) as u32)
        }
    }
}

/// The specialization constant of `film_gather` for a filter, and its parameters
/// (`FilmParams::filter_params`, read by `shaders/film/filter.glsl`).
pub fn filter_constants(filter: &Filter) -> (u32, [f32; 4]) {
    match *filter {
        Filter::Box => (FILTER_BOX, [0.0; 4]),
        Filter::Tent { radius } => (FILTER_TENT, [1.0 / radius, 0.0, 0.0, 0.0]),
        Filter::Gaussian { stddev, radius } => {
            let alpha = -1.0 / (2.0 * stddev * stddev);
            (
                FILTER_GAUSSIAN,
                [alpha, (alpha * radius * radius).exp(), 0.0, 0.0],
            )
        }
        Filter::Mitchell { b, c, radius } => (FILTER_MITCHELL, [b, c, 2.0 / radius, 0.0]),
        Filter::Lanczos { lobes } => (FILTER_LANCZOS, [lobes as f32, 0.0, 0.0, 0.0]),
    }
}

/// The film's GPU buffers and their descriptor set ([`FILM_SET`]).
pub struct Film {
    pub geometry: FilmGeometry,
    pub filter: Filter,
    /// Whether alpha sums are kept (and `shade` marks covered paths).
    pub has_alpha: bool,
    /// Slots of the sample ring.
    pub slots: u32,
    pub params: Buffer,
    pub sums: Buffer,
    pub alpha_sums: Buffer,
    pub samples: Buffer,
    /// The AOV and moment channels (none: empty) and their sums' buffers
    /// (`aov.comp`), and per shape the global number of its first triangle.
    pub extra: ExtraChannels,
    pub aov_sums: Buffer,
    pub moment_sums: Buffer,
    pub shape_first: Buffer,
    /// Per ring slot its sample's AOVs (filters wider than the box).
    pub aov_ring: Buffer,
    pub set: DescriptorSet,
}

/// The specialization constants of `film_gather` for a film with `filter`: the
/// filter, whether alpha is kept, whether it reads the samples from the paths
/// ([`reads_paths`]).
pub fn gather_constants(filter: &Filter, has_alpha: bool) -> SpecValues {
    SpecValues::new()
        .with(Spec::FilmFilter, filter_constants(filter).0)
        .with(Spec::FilmAlpha, has_alpha as u32)
        .with(Spec::FilmFromPaths, reads_paths(filter) as u32)
}

/// Whether `film_gather` reads each pixel's samples from the batch's paths, with no
/// `accumulate` and no ring: the box filter, whose sample weighs 1 in its own pixel
/// and reaches no other (its position in the pixel does not matter).
pub fn reads_paths(filter: &Filter) -> bool {
    matches!(filter, Filter::Box)
}

impl Film {
    /// Most paths a batch may hold so that the sample ring fits one storage-buffer
    /// binding on `device`.
    pub fn max_batch_paths(caps: &DeviceInfo, geometry: &FilmGeometry) -> u32 {
        let slots = caps.max_storage_buffer_range / BYTES_PER_SAMPLE_SLOT;
        slots
            .saturating_sub(u64::from(geometry.ring_span()))
            .min(u64::from(u32::MAX / 4)) as u32
    }

    /// The film of `geometry` with `filter`, for batches of at most `capacity` paths.
    /// `has_alpha`: keep the alpha sums; `covered`: every camera path counts as
    /// covered from the start (a visible environment, for the integrators where
    /// Mitsuba counts it).
    #[allow(clippy::too_many_arguments)] // each is one of the film's facts
    pub fn new(
        device: &Device,
        layout: &BindingLayout,
        geometry: FilmGeometry,
        filter: Filter,
        has_alpha: bool,
        covered: bool,
        capacity: u32,
        extra: ExtraChannels,
        shape_first: &[u32],
    ) -> Result<Film> {
        let slots = capacity
            .checked_add(geometry.ring_span())
            .filter(|&s| s < u32::MAX / 4)
            .ok_or_else(|| Error::Options("film sample ring too large".into()))?;
        let (_, filter_params) = filter_constants(&filter);
        let b = geometry.border as i32;
        let params = FilmParams {
            region_x: geometry.region_x,
            region_y: geometry.region_y,
            region_width: geometry.region_width,
            region_height: geometry.region_height,
            crop_x: geometry.crop.x,
            crop_y: geometry.crop.y,
            crop_width: geometry.crop.width,
            crop_height: geometry.crop.height,
            key_x: -b,
            key_y: -b,
            key_width: geometry.width + 2 * geometry.border,
            reach: geometry.reach,
            slots,
            coverage: covered as u32,
            filter_params,
            ..Default::default()
        };
        let pixels = u64::from(geometry.crop_pixels());
        let params = Buffer::from_slice(device, "film parameters", &[params])?;
        let sums = Buffer::new(device, "film sums", pixels * 16, crate::gpu::Location::Gpu)?;
        let alpha_sums = Buffer::new(
            device,
            "film alpha sums",
            if has_alpha { pixels * 4 } else { 4 },
            crate::gpu::Location::Gpu,
        )?;
        let samples = Buffer::new(
            device,
            "film samples",
            u64::from(slots) * BYTES_PER_SAMPLE_SLOT,
            crate::gpu::Location::Gpu,
        )?;
        let gpu = crate::gpu::Location::Gpu;
        let aov_sums = Buffer::new(
            device,
            "film AOV sums",
            (extra.aovs.len() as u64 * 4).max(4),
            gpu,
        )?;
        let moment_sums = Buffer::new(
            device,
            "film moment sums",
            if extra.moment.is_some() {
                pixels * 16
            } else {
                4
            },
            gpu,
        )?;
        let shape_first = if shape_first.is_empty() {
            Buffer::from_slice(device, "film AOV shapes", &[0u32])?
        } else {
            Buffer::from_slice(device, "film AOV shapes", shape_first)?
        };
        let aov_ring = Buffer::new(
            device,
            "film AOV ring",
            if reads_paths(&filter) {
                4
            } else {
                (u64::from(slots) * extra.aov_names.len() as u64 * 4).max(4)
            },
            gpu,
        )?;
        let set = DescriptorSet::new(
            layout,
            FILM_SET,
            &[
                &params,
                &sums,
                &alpha_sums,
                &samples,
                &samples,
                &aov_sums,
                &moment_sums,
                &shape_first,
                &aov_ring,
            ],
        )?;
        Ok(Film {
            geometry,
            filter,
            has_alpha,
            slots,
            params,
            sums,
            alpha_sums,
            samples,
            extra,
            aov_sums,
            moment_sums,
            shape_first,
            aov_ring,
            set,
        })
    }

    /// The specialization constants of `film_gather`: the filter, whether alpha is
    /// kept, whether it reads the samples from the paths ([`Film::reads_paths`]).
    pub fn gather_constants(&self) -> SpecValues {
        gather_constants(&self.filter, self.has_alpha)
    }

    /// Whether `film_gather` reads each pixel's samples from the batch's paths, with
    /// no `accumulate` and no ring: the box filter, whose sample weighs 1 in its own
    /// pixel and reaches no other (its position in the pixel does not matter).
    pub fn reads_paths(&self) -> bool {
        reads_paths(&self.filter)
    }

    /// Records zeroing every sum.
    pub fn clear(&self, cmd: &mut CommandList) {
        cmd.fill(&self.sums, 0, self.sums.size(), 0);
        cmd.fill(&self.alpha_sums, 0, self.alpha_sums.size(), 0);
        cmd.fill(&self.aov_sums, 0, self.aov_sums.size(), 0);
        cmd.fill(&self.moment_sums, 0, self.moment_sums.size(), 0);
    }

    /// The ring slot that follows a batch of `paths` paths starting at `slot`.
    pub fn next_slot(&self, slot: u32, paths: u32) -> u32 {
        ((u64::from(slot) + u64::from(paths)) % u64::from(self.slots)) as u32
    }

    /// Records `film_gather` (`kernel`) after the batch that `push` describes
    /// (`pixel_base`, `path_count`, `sample_slot`); `sets` are the kernel's descriptor
    /// sets (this film's among them).
    pub fn record_gather(
        &self,
        cmd: &mut CommandList,
        kernel: &Kernel,
        sets: &[&DescriptorSet],
        push: &Push,
    ) {
        let (row, rows) = self.geometry.gather_rows(push.pixel_base, push.path_count);
        if rows == 0 {
            return;
        }
        let push = Push {
            film_row: row,
            film_rows: rows,
            ..*push
        };
        let threads = rows * self.geometry.crop.width;
        cmd.dispatch(kernel, sets, bytemuck::bytes_of(&push), groups_for(threads));
        cmd.barrier();
    }

    /// Writes `sums` (of this film: its size, window and alpha) into the film, for a
    /// render that continues them.
    pub fn load(&self, device: &Device, sums: &FilmSums) -> Result<()> {
        let g = &self.geometry;
        if (sums.film_width, sums.film_height, sums.crop) != (g.width, g.height, g.crop)
            || sums.alpha.is_some() != self.has_alpha
            || sums.sums.len() != g.crop_pixels() as usize
        {
            return Err(Error::Options(format!(
                "cannot continue a render from the sums of another film (a {}x{} window of \
                 a {}x{} film{}; this one renders a {}x{} window of a {}x{} film{})",
                sums.crop.width,
                sums.crop.height,
                sums.film_width,
                sums.film_height,
                if sums.alpha.is_some() {
                    " with alpha"
                } else {
                    ""
                },
                g.crop.width,
                g.crop.height,
                g.width,
                g.height,
                if self.has_alpha { " with alpha" } else { "" },
            )));
        }
        self.sums
            .write(device, 0, bytemuck::cast_slice(&sums.sums))?;
        if let Some(alpha) = &sums.alpha {
            self.alpha_sums
                .write(device, 0, bytemuck::cast_slice(alpha))?;
        }
        let (a, b) = (&sums.extra, &self.extra);
        if (&a.aov_names, a.moment.as_ref().map(|m| &m.0))
            != (&b.aov_names, b.moment.as_ref().map(|m| &m.0))
        {
            return Err(Error::Options(
                "cannot continue a render from the sums of a film with other AOV or moment channels"
                    .into(),
            ));
        }
        if !a.aovs.is_empty() {
            self.aov_sums
                .write(device, 0, bytemuck::cast_slice(&a.aovs))?;
        }
        if let Some((_, m)) = &a.moment {
            let m: Vec<[f32; 4]> = m.iter().map(|v| [v[0], v[1], v[2], 0.0]).collect();
            self.moment_sums
                .write(device, 0, bytemuck::cast_slice(&m))?;
        }
        Ok(())
    }

    /// Reads the sums back.
    pub fn read(&self, device: &Device) -> Result<FilmSums> {
        let n = self.geometry.crop_pixels() as usize;
        let mut sums: Vec<[f32; 4]> = self.sums.read(device)?;
        sums.truncate(n);
        let alpha = if self.has_alpha {
            let mut a: Vec<f32> = self.alpha_sums.read(device)?;
            a.truncate(n);
            Some(a)
        } else {
            None
        };
        let mut extra = Box::new(self.extra.clone());
        if !extra.aovs.is_empty() {
            let mut a: Vec<f32> = self.aov_sums.read(device)?;
            a.truncate(extra.aovs.len());
            extra.aovs = a;
        }
        if let Some((_, m)) = &mut extra.moment {
            let v: Vec<[f32; 4]> = self.moment_sums.read(device)?;
            *m = v[..n].iter().map(|p| [p[0], p[1], p[2]]).collect();
        }
        let g = &self.geometry;
        Ok(FilmSums {
            film_width: g.width,
            film_height: g.height,
            crop: g.crop,
            sums,
            alpha,
            extra,
        })
    }
}

/// A film read back: per pixel of the crop window the filter-weighted sums.
/// Renders of disjoint sample ranges of the same film add up ([`FilmSums::merge`]) to
/// the film of their union.
#[derive(Debug, Clone, PartialEq)]
pub struct FilmSums {
    /// The full film's size.
    pub film_width: u32,
    pub film_height: u32,
    /// The window these pixels are.
    pub crop: Crop,
    /// Per pixel, row-major: (Σ w r, Σ w g, Σ w b, Σ w).
    pub sums: Vec<[f32; 4]>,
    /// Per pixel: Σ w over the covered samples, if the film keeps alpha.
    pub alpha: Option<Vec<f32>>,
    /// The AOV and second-moment sums and how their channels are named (empty for a
    /// render without them).
    pub extra: Box<ExtraChannels>,
}

/// What a film holds beyond its radiance: Mitsuba's `aov` and `moment` channels
/// (scene::integrator::aov), as filter-weighted sums beside the film's, developed
/// with the film's weight sums.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ExtraChannels {
    /// The AOV channels' names, in order (`dd.T`, `nn.X`, ...).
    pub aov_names: Vec<String>,
    /// Per pixel, row-major, `aov_names.len()` values: Σ w v.
    pub aovs: Vec<f32>,
    /// A `moment`'s channel prefix and per pixel (Σ w X², Σ w Y², Σ w Z²) of its
    /// samples' CIE XYZ.
    pub moment: Option<(String, Vec<[f32; 3]>)>,
    /// An `aov`'s nested integrator: the prefix of its RGBA channels.
    pub inner_rgba: Option<String>,
    /// An `aov` without a nested integrator: R, G, B are 0.
    pub no_radiance: bool,
}

impl ExtraChannels {
    /// The layout of `outputs` (AOVs first as the spec lists them, then `extra`'s,
    /// as `render --aov` adds them) for `pixels` pixels, every sum 0.
    pub fn of(outputs: &Outputs, extra: &[Aov], pixels: usize) -> ExtraChannels {
        let aov_names: Vec<String> = outputs
            .aovs
            .iter()
            .chain(extra)
            .flat_map(Aov::channels)
            .collect();
        ExtraChannels {
            aovs: vec![0.0; aov_names.len() * pixels],
            aov_names,
            moment: outputs
                .moment
                .as_ref()
                .map(|name| (name.clone(), vec![[0.0; 3]; pixels])),
            inner_rgba: outputs.inner_rgba.clone(),
            no_radiance: outputs.no_radiance,
        }
    }

    /// Whether the film has any.
    pub fn is_empty(&self) -> bool {
        *self == ExtraChannels::default()
    }

    /// The names of the channels that hold these sums in a partial render's EXR.
    fn sum_names(&self) -> Vec<String> {
        let mut names: Vec<String> = self
            .aov_names
            .iter()
            .map(|n| format!("sum.aov.{n}"))
            .collect();
        if let Some((m, _)) = &self.moment {
            names.extend(["X", "Y", "Z"].map(|c| format!("sum.m2.{m}.{c}")));
        }
        if let Some(inner) = &self.inner_rgba {
            names.push(format!("sum.rgba.{inner}"));
        }
        if self.no_radiance {
            names.push("sum.no_radiance".into());
        }
        names
    }

    /// Pixel i's values of [`Self::sum_names`].
    fn sum_values(&self, i: usize, out: &mut Vec<f32>) {
        let n = self.aov_names.len();
        out.extend_from_slice(&self.aovs[i * n..(i + 1) * n]);
        if let Some((_, m)) = &self.moment {
            out.extend_from_slice(&m[i]);
        }
        out.extend(self.inner_rgba.iter().map(|_| 0.0));
        if self.no_radiance {
            out.push(0.0);
        }
    }

    /// The sums of the channels a partial EXR holds ([`Self::sum_names`]); `None`
    /// where one has the wrong size.
    fn from_sum_channels(channels: &[image::exr::Channel], n: usize) -> Option<ExtraChannels> {
        let mut extra = ExtraChannels::default();
        let aovs: Vec<&image::exr::Channel> = channels
            .iter()
            .filter(|c| c.name.starts_with("sum.aov."))
            .collect();
        if aovs.iter().any(|c| c.values.len() != n) {
            return None;
        }
        extra.aov_names = aovs
            .iter()
            .map(|c| c.name["sum.aov.".len()..].to_string())
            .collect();
        extra.aovs = (0..n)
            .flat_map(|i| aovs.iter().map(move |c| c.values[i]))
            .collect();
        let m2: Vec<&image::exr::Channel> = channels
            .iter()
            .filter(|c| c.name.starts_with("sum.m2."))
            .collect();
        if let [x, y, z] = m2.as_slice() {
            if [x, y, z].iter().any(|c| c.values.len() != n) {
                return None;
            }
            let name = x.name["sum.m2.".len()..x.name.len() - 2].to_string();
            extra.moment = Some((
                name,
                (0..n)
                    .map(|i| [x.values[i], y.values[i], z.values[i]])
                    .collect(),
            ));
        }
        extra.inner_rgba = channels
            .iter()
            .find_map(|c| c.name.strip_prefix("sum.rgba.").map(str::to_string));
        extra.no_radiance = channels.iter().any(|c| c.name == "sum.no_radiance");
        Some(extra)
    }
}

/// Mitsuba's sRGB luminance weights (`hdrfilm`'s "Y" channel).
const LUMINANCE: [f32; 3] = [0.212_671, 0.715_160, 0.072_169];
/// Mitsuba's `srgb_to_xyz` (linear sRGB, D65) rows.
const SRGB_TO_XYZ: [[f32; 3]; 3] = [
    [0.412_453, 0.357_580, 0.180_423],
    [0.212_671, 0.715_160, 0.072_169],
    [0.019_334, 0.119_193, 0.950_227],
];

impl FilmSums {
    /// The sums of a finished image of a whole film, each pixel weight 1 (an
    /// integrator that keeps its own per-pixel estimate, as SPPM does).
    pub fn from_image(image: &Image) -> FilmSums {
        FilmSums {
            film_width: image.width,
            film_height: image.height,
            crop: Crop {
                x: 0,
                y: 0,
                width: image.width,
                height: image.height,
            },
            sums: image
                .rgb
                .chunks_exact(3)
                .map(|p| [p[0], p[1], p[2], 1.0])
                .collect(),
            alpha: None,
            extra: Box::default(),
        }
    }

    pub fn width(&self) -> u32 {
        self.crop.width
    }

    pub fn height(&self) -> u32 {
        self.crop.height
    }

    /// The image: each pixel's weighted sum divided by its weight sum, as Mitsuba's
    /// `HDRFilm::develop` divides (0 where no sample weighs the pixel; a negative
    /// weight sum, possible with few samples of a negative-lobed filter, divides as
    /// it is).
    pub fn develop(&self) -> Image {
        let mut rgb = Vec::with_capacity(self.sums.len() * 3);
        for s in &self.sums {
            let w = if s[3] != 0.0 { s[3] } else { 1.0 };
            rgb.extend_from_slice(&[s[0] / w, s[1] / w, s[2] / w]);
        }
        Image {
            width: self.crop.width,
            height: self.crop.height,
            rgb,
        }
    }

    /// Alpha per pixel (covered weight over weight), if the film keeps it.
    pub fn develop_alpha(&self) -> Option<Vec<f32>> {
        let alpha = self.alpha.as_ref()?;
        Some(
            alpha
                .iter()
                .zip(&self.sums)
                .map(|(a, s)| if s[3] != 0.0 { a / s[3] } else { 0.0 })
                .collect(),
        )
    }

    /// Adds `other`'s sums (a render of other samples of the same film) to these.
    pub fn merge(&mut self, other: &FilmSums) -> Result<()> {
        if (self.film_width, self.film_height, self.crop)
            != (other.film_width, other.film_height, other.crop)
            || self.alpha.is_some() != other.alpha.is_some()
        {
            return Err(Error::Options(format!(
                "cannot merge a {}x{} window at ({}, {}) of a {}x{} film{} with a {}x{} window at ({}, {}) of a {}x{} film{}",
                self.crop.width, self.crop.height, self.crop.x, self.crop.y,
                self.film_width, self.film_height,
                if self.alpha.is_some() { " with alpha" } else { "" },
                other.crop.width, other.crop.height, other.crop.x, other.crop.y,
                other.film_width, other.film_height,
                if other.alpha.is_some() { " with alpha" } else { "" },
            )));
        }
        for (a, b) in self.sums.iter_mut().zip(&other.sums) {
            (0..4).for_each(|c| a[c] += b[c]);
        }
        if let (Some(a), Some(b)) = (self.alpha.as_mut(), other.alpha.as_ref()) {
            a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
        }
        let (a, b) = (&mut self.extra, &other.extra);
        if (
            &a.aov_names,
            a.moment.as_ref().map(|m| &m.0),
            &a.inner_rgba,
            a.no_radiance,
        ) != (
            &b.aov_names,
            b.moment.as_ref().map(|m| &m.0),
            &b.inner_rgba,
            b.no_radiance,
        ) {
            return Err(Error::Options(format!(
                "cannot merge films with different AOV or moment channels ({:?} and {:?})",
                a.sum_names(),
                b.sum_names()
            )));
        }
        a.aovs.iter_mut().zip(&b.aovs).for_each(|(x, y)| *x += y);
        if let (Some((_, x)), Some((_, y))) = (a.moment.as_mut(), b.moment.as_ref()) {
            for (p, q) in x.iter_mut().zip(y) {
                (0..3).for_each(|c| p[c] += q[c]);
            }
        }
        Ok(())
    }

    /// The developed AOV and moment channels, as Mitsuba names them, interleaved per
    /// pixel: an `aov`'s nested integrator's R, G, B, A, the AOVs, a `moment`'s mean
    /// and second moment in CIE XYZ. Each sum is divided by the film's weight sum.
    pub fn extra_channels(&self) -> (Vec<String>, Vec<f32>) {
        let e = &self.extra;
        let mut names = Vec::new();
        if let Some(inner) = &e.inner_rgba {
            names.extend(["R", "G", "B", "A"].map(|c| format!("{inner}.{c}")));
        }
        names.extend(e.aov_names.iter().cloned());
        if let Some((m, _)) = &e.moment {
            names.extend(["X", "Y", "Z"].map(|c| format!("{m}.{c}")));
            names.extend(["X", "Y", "Z"].map(|c| format!("m2_{m}.{c}")));
        }
        let image = self.develop();
        let alpha = self.develop_alpha();
        let n = e.aov_names.len();
        let mut data = Vec::with_capacity(names.len() * self.sums.len());
        for (i, s) in self.sums.iter().enumerate() {
            let w = if s[3] != 0.0 { s[3] } else { 1.0 };
            let rgb = &image.rgb[3 * i..3 * i + 3];
            if e.inner_rgba.is_some() {
                data.extend_from_slice(rgb);
                data.push(alpha.as_ref().map_or(1.0, |a| a[i]));
            }
            data.extend(e.aovs[i * n..(i + 1) * n].iter().map(|v| v / w));
            if let Some((_, m2)) = &e.moment {
                data.extend(
                    SRGB_TO_XYZ
                        .iter()
                        .map(|row| row[0] * rgb[0] + row[1] * rgb[1] + row[2] * rgb[2]),
                );
                data.extend(m2[i].iter().map(|v| v / w));
            }
        }
        (names, data)
    }

    /// The developed pixels in `format`: channel names (as Mitsuba's `hdrfilm` names
    /// them) and their values, interleaved per pixel. Alpha formats need alpha sums
    /// (else alpha is 1).
    pub fn channels(&self, format: PixelFormat) -> (Vec<&'static str>, Vec<f32>) {
        let image = self.develop();
        let alpha = self.develop_alpha();
        let names = format.channel_names();
        let dot = |w: &[f32; 3], p: &[f32]| w[0] * p[0] + w[1] * p[1] + w[2] * p[2];
        let mut data = Vec::with_capacity(names.len() * image.pixel_count());
        for (i, p) in image.rgb.chunks_exact(3).enumerate() {
            match format {
                PixelFormat::Luminance | PixelFormat::LuminanceAlpha => {
                    data.push(dot(&LUMINANCE, p))
                }
                PixelFormat::Rgb | PixelFormat::Rgba => data.extend_from_slice(p),
                PixelFormat::Xyz | PixelFormat::Xyza => {
                    data.extend(SRGB_TO_XYZ.iter().map(|row| dot(row, p)))
                }
            }
            if self.extra.no_radiance {
                let len = data.len();
                data[len - names.len() + format.has_alpha() as usize..]
                    .iter_mut()
                    .for_each(|v| *v = 0.0);
            }
            if format.has_alpha() {
                data.push(alpha.as_ref().map_or(1.0, |a| a[i]));
            }
        }
        (names, data)
    }

    /// The names of the channels that hold the sums themselves in a partial render's
    /// EXR (float32, exact): Σ w r, Σ w g, Σ w b, Σ w, and Σ w over covered samples
    /// where the film keeps alpha.
    pub const SUM_CHANNELS: [&'static str; 5] = ["sum.R", "sum.G", "sum.B", "sum.W", "sum.A"];

    /// The sums as channels ([`Self::SUM_CHANNELS`], without `sum.A` if there is no
    /// alpha), interleaved per pixel.
    pub fn sum_channels(&self) -> (Vec<String>, Vec<f32>) {
        let n = if self.alpha.is_some() { 5 } else { 4 };
        let mut names: Vec<String> = Self::SUM_CHANNELS[..n]
            .iter()
            .map(|s| s.to_string())
            .collect();
        names.extend(self.extra.sum_names());
        let mut data = Vec::with_capacity(names.len() * self.sums.len());
        for (i, s) in self.sums.iter().enumerate() {
            data.extend_from_slice(s);
            if let Some(a) = &self.alpha {
                data.push(a[i]);
            }
            self.extra.sum_values(i, &mut data);
        }
        (names, data)
    }

    /// The sums of a `crop` window of a `film_width` x `film_height` film from the
    /// channels of an EXR file ([`Self::sum_channels`]); `None` if they are missing
    /// or of the wrong size.
    pub fn from_sum_channels(
        film_width: u32,
        film_height: u32,
        crop: Crop,
        channels: &[image::exr::Channel],
    ) -> Option<FilmSums> {
        let n = crop.width as usize * crop.height as usize;
        let find = |name: &str| {
            channels
                .iter()
                .find(|c| c.name == name && c.values.len() == n && !c.half)
        };
        let [r, g, b, w] = [0, 1, 2, 3].map(|c| find(Self::SUM_CHANNELS[c]));
        let (r, g, b, w) = (r?, g?, b?, w?);
        let sums = (0..n)
            .map(|i| [r.values[i], g.values[i], b.values[i], w.values[i]])
            .collect();
        Some(FilmSums {
            film_width,
            film_height,
            crop,
            sums,
            alpha: find(Self::SUM_CHANNELS[4]).map(|a| a.values.clone()),
            extra: Box::new(ExtraChannels::from_sum_channels(channels, n)?),
        })
    }

    /// Writes the film as `file_format` in `pixel_format` and `component_format`
    /// (OpenEXR; RGBE and PFM are float32 RGB, PFM also luminance), and an sRGB
    /// PNG to look at beside it (`png`, if given): grey for luminance formats, with
    /// alpha for alpha formats (colour divided by alpha there, as PNG stores it
    /// straight); values outside [0, 1] clip.
    pub fn write(
        &self,
        path: &std::path::Path,
        pixel_format: PixelFormat,
        component_format: ComponentFormat,
        file_format: FileFormat,
        png: Option<&std::path::Path>,
    ) -> std::result::Result<(), image::Error> {
        self.write_with(
            path,
            pixel_format,
            component_format,
            file_format,
            png,
            &ExrExtras::default(),
        )
    }

    /// [`Self::write`], with `extras` in an OpenEXR file (ignored by the other
    /// formats): text attributes in its header and, for a partial render, the sums
    /// themselves ([`Self::sum_channels`]; the file is then all float32).
    pub fn write_with(
        &self,
        path: &std::path::Path,
        pixel_format: PixelFormat,
        component_format: ComponentFormat,
        file_format: FileFormat,
        png: Option<&std::path::Path>,
        extras: &ExrExtras,
    ) -> std::result::Result<(), image::Error> {
        let (w, h) = (self.width(), self.height());
        let (names, data) = self.channels(pixel_format);
        let (extra_names, extra) = self.extra_channels();
        match file_format {
            FileFormat::OpenExr if extras.sums || !extra_names.is_empty() => {
                let (mut sum_names, mut sums) = self.sum_channels();
                if !extras.sums {
                    (sum_names, sums) = (Vec::new(), Vec::new());
                }
                let (e, b) = (extra_names.len(), sum_names.len());
                let a = names.len();
                let mut all = Vec::with_capacity(data.len() + extra.len() + sums.len());
                for (i, p) in data.chunks_exact(a).enumerate() {
                    all.extend_from_slice(p);
                    all.extend_from_slice(&extra[i * e..(i + 1) * e]);
                    all.extend_from_slice(&sums[i * b..(i + 1) * b]);
                }
                let all_names: Vec<&str> = names
                    .iter()
                    .copied()
                    .chain(extra_names.iter().map(String::as_str))
                    .chain(sum_names.iter().map(String::as_str))
                    .collect();
                image::exr::write_channels_with_text(
                    path,
                    w,
                    h,
                    &all_names,
                    &all,
                    if extras.sums || component_format == ComponentFormat::Float32 {
                        image::exr::Precision::Float
                    } else {
                        image::exr::Precision::Half
                    },
                    &extras.text_pairs(),
                )?
            }
            FileFormat::OpenExr => image::exr::write_channels_with_text(
                path,
                w,
                h,
                &names,
                &data,
                match component_format {
                    ComponentFormat::Float16 => image::exr::Precision::Half,
                    ComponentFormat::Float32 => image::exr::Precision::Float,
                },
                &extras.text_pairs(),
            )?,
            FileFormat::Pfm => image::pfm::write(path, w, h, names.len(), &data)?,
            FileFormat::Rgbe => image::rgbe::write(&self.develop(), path)?,
        }
        if let Some(png) = png {
            let (png_names, mut png_data) = match pixel_format {
                PixelFormat::Xyz => self.channels(PixelFormat::Rgb),
                PixelFormat::Xyza => self.channels(PixelFormat::Rgba),
                _ => (names, data),
            };
            let n = png_names.len();
            if pixel_format.has_alpha() {
                for p in png_data.chunks_exact_mut(n) {
                    let a = p[n - 1];
                    if a > 0.0 {
                        p[..n - 1].iter_mut().for_each(|v| *v /= a);
                    }
                }
            }
            image::png::write_channels(png, w, h, n, &png_data, 0.0)?;
        }
        Ok(())
    }
}

/// What an OpenEXR film file may hold beyond its pixels ([`FilmSums::write_with`]).
#[derive(Debug, Clone, Default)]
pub struct ExrExtras {
    /// Text attributes of the header: (name, value).
    pub text: Vec<(String, String)>,
    /// Whether to store the sums ([`FilmSums::sum_channels`]) too.
    pub sums: bool,
}

impl ExrExtras {
    fn text_pairs(&self) -> Vec<(&str, &str)> {
        self.text
            .iter()
            .map(|(k, v)| (k.as_str(), v.as_str()))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geometry(w: u32, h: u32, crop: Option<Crop>, filter: Filter, border: bool) -> FilmGeometry {
        FilmGeometry::new(w, h, crop, &filter, border).unwrap()
    }

    #[test]
    fn box_samples_the_crop_only_with_keys_of_the_full_film() {
        let crop = Crop {
            x: 3,
            y: 2,
            width: 4,
            height: 5,
        };
        let g = geometry(10, 8, Some(crop), Filter::Box, true);
        assert_eq!(
            (g.region_x, g.region_y, g.region_width, g.region_height),
            (3, 2, 4, 5)
        );
        assert_eq!((g.border, g.reach, g.ring_span()), (0, 0, 0));
        // Without a border, keys are y * width + x: the random numbers of every
        // render before filters existed.
        assert_eq!(g.key(3, 2), 2 * 10 + 3);
    }

    #[test]
    fn gaussian_samples_around_the_crop_within_the_film() {
        let crop = Crop {
            x: 1,
            y: 5,
            width: 4,
            height: 3,
        };
        let g = geometry(10, 8, Some(crop), Filter::DEFAULT, false);
        // Reach 2: x from max(1 - 2, 0) to 1 + 4 + 2 = 7; y from 3 to min(10, 8).
        assert_eq!(
            (g.region_x, g.region_y, g.region_width, g.region_height),
            (0, 3, 7, 5)
        );
        assert_eq!(g.ring_span(), 2 * 2 * 7 + 4);
        // With sample_border: the film's border of 2 pixels is sampled too.
        let g = geometry(10, 8, Some(crop), Filter::DEFAULT, true);
        assert_eq!(
            (g.region_x, g.region_y, g.region_width, g.region_height),
            (-1, 3, 8, 7)
        );
        assert_eq!(g.key(-2, -2), 0);
        assert_eq!(g.key(0, 0), 2 * 14 + 2);
        // The full film with a border.
        let g = geometry(10, 8, None, Filter::DEFAULT, true);
        assert_eq!(
            (g.region_x, g.region_y, g.region_width, g.region_height),
            (-2, -2, 14, 12)
        );
    }

    #[test]
    fn bad_crops_and_films_are_errors() {
        let crop = Crop {
            x: 8,
            y: 0,
            width: 4,
            height: 1,
        };
        let e = FilmGeometry::new(10, 8, Some(crop), &Filter::Box, false).unwrap_err();
        assert!(e.to_string().contains("does not fit"), "{e}");
        assert!(FilmGeometry::new(0, 8, None, &Filter::Box, false).is_err());
        assert!(FilmGeometry::new(1 << 16, 1 << 16, None, &Filter::Box, false).is_err());
    }

    /// Every (sample, pixel) pair is gathered exactly once whatever the batches:
    /// simulate the renderer's batching with the kernel's rule.
    #[test]
    fn gather_rows_cover_every_pixel_once_per_sample() {
        for (filter, border, crop) in [
            (Filter::DEFAULT, false, None),
            (Filter::Lanczos { lobes: 3 }, true, None),
            (
                Filter::Tent { radius: 1.0 },
                false,
                Some(Crop {
                    x: 2,
                    y: 3,
                    width: 5,
                    height: 4,
                }),
            ),
            (Filter::Box, false, None),
        ] {
            let g = geometry(9, 11, crop, filter, border);
            let p = g.region_pixels();
            for batch in [7u32, 13, p, 3 * p] {
                let spp = 3u32;
                let mut seen = vec![0u32; g.crop_pixels() as usize];
                // Batches as Renderer::render_range makes them.
                let mut runs = Vec::new();
                if p <= batch {
                    let k = batch / p;
                    let mut s = 0;
                    while s < spp {
                        let n = k.min(spp - s);
                        runs.push((0u32, n * p, s));
                        s += n;
                    }
                } else {
                    for s in 0..spp {
                        let mut base = 0;
                        while base < p {
                            let n = batch.min(p - base);
                            runs.push((base, n, s));
                            base += n;
                        }
                    }
                }
                for (base, count, _) in runs {
                    let (row, rows) = g.gather_rows(base, count);
                    for cy in row..row + rows {
                        for cx in 0..g.crop.width {
                            // The kernel's test (film_gather.comp).
                            let sx = (g.crop.x + cx) as i64 - g.region_x as i64;
                            let sy = (g.crop.y + cy) as i64 - g.region_y as i64;
                            let n = g.reach as i64;
                            let hx = (sx + n).min(g.region_width as i64 - 1);
                            let hy = (sy + n).min(g.region_height as i64 - 1);
                            let last = hy * g.region_width as i64 + hx - base as i64;
                            if last >= count as i64 {
                                continue;
                            }
                            let k_first = if last >= 0 { 0 } else { 1 };
                            let k_last = (count as i64 - 1 - last) / p as i64;
                            if k_last >= k_first {
                                seen[(cy * g.crop.width + cx) as usize] +=
                                    (k_last - k_first + 1) as u32;
                            }
                        }
                    }
                }
                assert!(
                    seen.iter().all(|&n| n == spp),
                    "{filter:?} border {border} batch {batch}: {seen:?}"
                );
            }
        }
    }

    fn sums(alpha: bool) -> FilmSums {
        FilmSums {
            film_width: 2,
            film_height: 1,
            crop: Crop {
                x: 0,
                y: 0,
                width: 2,
                height: 1,
            },
            sums: vec![[1.0, 2.0, 4.0, 2.0], [0.0, 0.0, 0.0, 0.0]],
            alpha: alpha.then(|| vec![1.0, 0.0]),
            extra: Box::default(),
        }
    }

    #[test]
    fn develop_divides_by_the_weight() {
        let s = sums(true);
        assert_eq!(s.develop().rgb, vec![0.5, 1.0, 2.0, 0.0, 0.0, 0.0]);
        assert_eq!(s.develop_alpha(), Some(vec![0.5, 0.0]));
        let (names, data) = s.channels(PixelFormat::LuminanceAlpha);
        assert_eq!(names, ["Y", "A"]);
        let y = 0.212_671 * 0.5 + 0.715_160 + 0.072_169 * 2.0;
        assert!((data[0] - y).abs() < 1e-6 && data[1] == 0.5);
        let (names, data) = s.channels(PixelFormat::Xyz);
        assert_eq!(names, ["X", "Y", "Z"]);
        assert!((data[1] - y).abs() < 1e-6);
        assert_eq!(data.len(), 6);
        assert_eq!(sums(false).channels(PixelFormat::Rgba).1[3], 1.0);
    }

    #[test]
    fn merge_adds_sums_of_the_same_film_only() {
        let mut a = sums(true);
        a.merge(&sums(true)).unwrap();
        assert_eq!(a.sums[0], [2.0, 4.0, 8.0, 4.0]);
        assert_eq!(a.alpha.as_ref().unwrap()[0], 2.0);
        assert_eq!(a.develop(), sums(true).develop());
        assert!(a.merge(&sums(false)).is_err());
        let mut other = sums(true);
        other.crop.x = 1;
        other.crop.width = 1;
        assert!(a.merge(&other).is_err());
    }
}
