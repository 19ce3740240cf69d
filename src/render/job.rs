//! A render job: some sample ranges of one render, on one device or spread over
//! several, stopping at a clean sample boundary when asked and handing out
//! checkpoints of the samples done.
//!
//! On one device the ranges are rendered in order, each continuing the film of the
//! ones before ([`Renderer::render_film_controlled`]): the sums are those of an
//! uninterrupted render bit for bit, also when the job continues a partial (resume).
//!
//! On several devices (one [`Renderer`] per device, each on its own thread) the
//! ranges are cut into chunks of `ceil(samples / (4 devices))` samples, which the
//! devices take in order as they become free (a fast GPU takes more than a slow one);
//! each chunk is rendered from zero and the chunks' sums are added in the order of
//! their samples, whichever device rendered them. The result is therefore the same
//! bits for the same device list and ranges (on devices that compute the same values,
//! e.g. two of one model or one opened twice), the same as `wavetrace merge` of the
//! same chunks rendered with `--samples`, and equal to the one-device render up to
//! the rounding of the regrouped float32 sums (see [`super::partial`]).

use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Mutex};
use std::time::{Duration, Instant};

use super::film::FilmSums;
use super::partial::SampleRanges;
use super::{Error, RenderOptions, RenderStats, Renderer, Result};
use crate::gpu::Device;
use crate::scene::sampler::SampleCount;
use crate::scene::Scene;

/// How a job is driven from outside.
pub struct JobControl<'a> {
    /// Set to stop at the next clean sample boundary.
    pub stop: &'a AtomicBool,
    /// Write a checkpoint at the first sample boundary after every this long.
    pub checkpoint_every: Option<Duration>,
    /// Receives a checkpoint: the sums of the samples done (with the job's start) and
    /// which samples those are.
    pub checkpoint: &'a (dyn Fn(&FilmSums, &SampleRanges) -> Result<()> + Sync),
    /// Called at every sample boundary of a device with (samples per pixel done by the
    /// job so far, samples per pixel the job renders).
    pub boundary: &'a (dyn Fn(u64, u64) + Sync),
    /// Called after every batch with (paths done, paths in all).
    pub progress: &'a (dyn Fn(u64, u64) + Sync),
    /// On one device: shown the sums of the samples done at the first sample boundary
    /// after every this long (an image in progress, e.g. for tev).
    pub preview: Option<(Duration, &'a Preview<'a>)>,
}

/// What [`JobControl::preview`] calls with the sums of the samples done.
pub type Preview<'a> = dyn Fn(&FilmSums) + Sync + 'a;

/// What a job rendered.
pub struct JobResult {
    /// The sums of `done` (and of the job's start), if any sample was rendered or the
    /// job started from sums.
    pub sums: Option<FilmSums>,
    /// The samples rendered, with the start's.
    pub done: SampleRanges,
    pub stats: RenderStats,
    /// Whether the job stopped before rendering all its ranges.
    pub stopped: bool,
}

/// Adds `b`'s counts to `a` (seconds excepted: a job's are its wall time).
fn add_stats(a: &mut RenderStats, b: &RenderStats) {
    a.spp += b.spp;
    a.rays += b.rays;
    a.discarded += b.discarded;
    a.batches += b.batches;
    a.cut_paths += b.cut_paths;
    a.deferred += b.deferred;
    a.kernel_times.add(&b.kernel_times);
    if a.photons.is_none() {
        a.photons = b.photons.clone();
    }
}

/// Renders `ranges` on `renderer` (whose sample count must be the whole render's,
/// [`Renderer::set_sample_count`]), continuing `start` (a partial of samples
/// `start_done`).
pub fn render_on_one(
    renderer: &mut Renderer,
    ranges: &SampleRanges,
    start: Option<FilmSums>,
    start_done: &SampleRanges,
    control: &JobControl,
) -> Result<JobResult> {
    let t = Instant::now();
    let pixels = u64::from(renderer.film_geometry().region_pixels());
    let total = ranges.count();
    let mut acc = start;
    let mut done = start_done.clone();
    let mut stats = RenderStats::default();
    let mut stopped = false;
    let mut last_checkpoint = Instant::now();
    let mut last_preview = Instant::now();
    let mut finished = 0u64;
    for r in ranges.ranges() {
        if control.stop.load(Ordering::SeqCst) {
            stopped = true;
            break;
        }
        let mut progress =
            |d: u64, _: u64| (control.progress)(finished * pixels + d, total * pixels);
        let done_before = done.clone();
        let mut boundary = |rr: &Renderer, n: u32| -> Result<bool> {
            (control.boundary)(finished + u64::from(n), total);
            if let Some(every) = control.checkpoint_every {
                if last_checkpoint.elapsed() >= every {
                    let mut d = done_before.clone();
                    d.add(r.start..r.start + n);
                    (control.checkpoint)(&rr.read_film()?, &d)?;
                    last_checkpoint = Instant::now();
                }
            }
            if let Some((every, show)) = control.preview {
                if last_preview.elapsed() >= every {
                    show(&rr.read_film()?);
                    last_preview = Instant::now();
                }
            }
            Ok(control.stop.load(Ordering::SeqCst))
        };
        let (sums, s) = renderer.render_film_controlled(
            r.start,
            r.end - r.start,
            acc.as_ref(),
            &mut progress,
            &mut boundary,
        )?;
        done.add(r.start..r.start + s.spp);
        finished += u64::from(s.spp);
        add_stats(&mut stats, &s);
        acc = Some(sums);
        if s.spp < r.end - r.start {
            stopped = true;
            break;
        }
    }
    stats.seconds = t.elapsed().as_secs_f64();
    Ok(JobResult {
        sums: acc,
        done,
        stats,
        stopped,
    })
}

/// The chunks a job over `devices` devices cuts `ranges` into (see the module note).
pub fn chunks(ranges: &SampleRanges, devices: usize) -> Vec<Range<u32>> {
    let size = ranges
        .count()
        .div_ceil(4 * devices.max(1) as u64)
        .clamp(1, u64::from(u32::MAX)) as u32;
    let mut out = Vec::new();
    for r in ranges.ranges() {
        let mut a = r.start;
        while a < r.end {
            let b = a.saturating_add(size).min(r.end);
            out.push(a..b);
            a = b;
        }
    }
    out
}

/// What a device thread reports: a chunk's samples done and sums, or an error.
enum Report {
    Ready(String),
    Chunk {
        index: usize,
        done: u32,
        sums: FilmSums,
        stats: RenderStats,
    },
    Failed(Error),
}

/// Renders `ranges` of the render of `scene` with `options` at `count` samples per
/// pixel (the whole render's, as the sampler rounds it) on every device `selectors`
/// names, one thread and [`Renderer`] each, continuing `start` (a partial of
/// `start_done`). `ready` is told each device's name as its renderer is set up.
#[allow(clippy::too_many_arguments)]
pub fn render_on_many(
    scene: &Scene,
    options: &RenderOptions,
    selectors: &[String],
    count: SampleCount,
    ranges: &SampleRanges,
    start: Option<FilmSums>,
    start_done: &SampleRanges,
    control: &JobControl,
    ready: &mut dyn FnMut(&str),
) -> Result<JobResult> {
    let t = Instant::now();
    let work = chunks(ranges, selectors.len());
    let next = Mutex::new(0usize);
    let total = ranges.count();
    let spp_done = Mutex::new(0u64);
    let (tx, rx) = mpsc::channel::<Report>();
    let mut results: Vec<Option<(u32, FilmSums)>> = vec![None; work.len()];
    let mut stats = RenderStats::default();
    let mut failure: Option<Error> = None;
    std::thread::scope(|scope| {
        for selector in selectors {
            let tx = tx.clone();
            let (work, next, spp_done) = (&work, &next, &spp_done);
            let count = count.clone();
            scope.spawn(move || {
                let run = || -> Result<()> {
                    let device = Device::new(Some(selector))?;
                    let mut renderer = Renderer::new(&device, scene, options)?;
                    renderer.set_sample_count(count)?;
                    tx.send(Report::Ready(format!("[{selector}] {}", device.info())))
                        .ok();
                    let pixels = u64::from(renderer.film_geometry().region_pixels());
                    loop {
                        if control.stop.load(Ordering::SeqCst) {
                            return Ok(());
                        }
                        let index = {
                            let mut n = next.lock().unwrap_or_else(|e| e.into_inner());
                            *n += 1;
                            *n - 1
                        };
                        let Some(r) = work.get(index) else {
                            return Ok(());
                        };
                        // Samples of this chunk already counted in `spp_done`.
                        let mut counted = 0u32;
                        let mut count_to = |n: u32| {
                            let mut d = spp_done.lock().unwrap_or_else(|e| e.into_inner());
                            *d += u64::from(n - counted);
                            counted = n;
                            (control.boundary)(*d, total);
                            (control.progress)(*d * pixels, total * pixels);
                        };
                        let mut progress = |_: u64, _: u64| {};
                        let mut boundary = |_: &Renderer, n: u32| -> Result<bool> {
                            count_to(n);
                            Ok(control.stop.load(Ordering::SeqCst))
                        };
                        let (sums, s) = renderer.render_film_controlled(
                            r.start,
                            r.end - r.start,
                            None,
                            &mut progress,
                            &mut boundary,
                        )?;
                        if s.spp == r.end - r.start {
                            // The last samples: no boundary call there.
                            count_to(s.spp);
                        }
                        tx.send(Report::Chunk {
                            index,
                            done: s.spp,
                            sums,
                            stats: s,
                        })
                        .ok();
                    }
                };
                if let Err(e) = run() {
                    control.stop.store(true, Ordering::SeqCst);
                    tx.send(Report::Failed(e)).ok();
                }
            });
        }
        drop(tx);
        let mut last_checkpoint = Instant::now();
        loop {
            let wait = control
                .checkpoint_every
                .map(|e| e.saturating_sub(last_checkpoint.elapsed()))
                .unwrap_or(Duration::from_secs(3600));
            match rx.recv_timeout(wait) {
                Ok(Report::Ready(name)) => ready(&name),
                Ok(Report::Chunk {
                    index,
                    done,
                    sums,
                    stats: s,
                }) => {
                    add_stats(&mut stats, &s);
                    results[index] = Some((done, sums));
                }
                Ok(Report::Failed(e)) => {
                    failure.get_or_insert(e);
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    if failure.is_none() {
                        let (sums, done) = fold(&work, &results, start.as_ref(), start_done);
                        if let Some(sums) = sums {
                            if let Err(e) = (control.checkpoint)(&sums, &done) {
                                control.stop.store(true, Ordering::SeqCst);
                                failure.get_or_insert(e);
                            }
                        }
                    }
                    last_checkpoint = Instant::now();
                }
                Err(mpsc::RecvTimeoutError::Disconnected) => break,
            }
        }
    });
    if let Some(e) = failure {
        return Err(e);
    }
    let (sums, done) = fold(&work, &results, start.as_ref(), start_done);
    stats.seconds = t.elapsed().as_secs_f64();
    let stopped = done.count() < start_done.count() + total;
    Ok(JobResult {
        sums,
        done,
        stats,
        stopped,
    })
}

/// The start's sums plus the chunks' rendered so far, added in the order of the
/// chunks, and the samples they hold.
fn fold(
    work: &[Range<u32>],
    results: &[Option<(u32, FilmSums)>],
    start: Option<&FilmSums>,
    start_done: &SampleRanges,
) -> (Option<FilmSums>, SampleRanges) {
    let mut sums = start.cloned();
    let mut done = start_done.clone();
    for (r, result) in work.iter().zip(results) {
        let Some((n, s)) = result else { continue };
        if *n == 0 {
            continue;
        }
        done.add(r.start..r.start + n);
        match &mut sums {
            // Chunks of one render are of one film: merge cannot fail.
            Some(acc) => acc.merge(s).unwrap_or(()),
            None => sums = Some(s.clone()),
        }
    }
    (sums, done)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_cover_the_ranges_in_order() {
        let mut r = SampleRanges::of(0..10);
        r.add(20..23);
        let c = chunks(&r, 2);
        // 13 samples over 8 chunks of 2.
        assert_eq!(c, vec![0..2, 2..4, 4..6, 6..8, 8..10, 20..22, 22..23]);
        assert_eq!(chunks(&SampleRanges::of(0..3), 4), vec![0..1, 1..2, 2..3]);
    }
}
