//! A render's batches: how the samples of a range split into batches of paths, and how
//! each batch is recorded: its start (camera rays, or the fused first bounce), its
//! bounces in chunks of submissions, the film's gather and the batch's statistics.

use super::*;

impl Renderer {
    /// Calls `batch(self, cmd, sample_base, pixel_base, path_count, slot, stats)` for
    /// batches covering samples `first .. first + count` of every pixel the film
    /// samples: whole samples of every pixel per batch where they fit, else runs of
    /// pixels of one sample. `slot`: the film's sample slot of the batch's first path.
    /// After each batch that completes samples (a clean sample boundary) calls
    /// `boundary(self, samples done)` and stops if it returns true. Returns the
    /// samples done.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn for_each_batch(
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
    pub(super) fn start_batch(
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
    pub(super) fn start_batch_fused(
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
        // Bounce 1's shadow rays, which first_bounce leaves to the shadow queue where
        // it shades bounce 1 in full.
        if let (true, Some(shadow)) = (self.kernels.second_fused, &self.kernels.shadow) {
            let p = Push { depth: 1, ..*push };
            let p = bytemuck::bytes_of(&p);
            cmd.dispatch_indirect(shadow, sets, p, &wf.dispatch_args, Wavefront::SHADOW_ARGS);
            cmd.barrier();
        }
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
    pub(super) fn run_bounces(
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
    pub(super) fn run_batch(
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
                // Its rays for the wavefront go to the queue of bounce fused_bounces.
                let fused_push = Push {
                    queue_in: (k.fused_bounces + 1) % 2,
                    ..push
                };
                self.start_batch_fused(cmd, &sets, &fused_push, fused);
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
    pub(super) fn bounce_stages<'a>(
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
    pub(super) fn record_film(&self, cmd: &mut CommandList, sets: &[&DescriptorSet], push: &Push) {
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
        if let Some(samples) = &k.aov_samples {
            cmd.dispatch(
                samples,
                sets,
                bytemuck::bytes_of(push),
                groups_for(push.path_count),
            );
            cmd.barrier();
        }
        if let Some(aov) = &k.aov {
            self.film.record_gather(cmd, aov, sets, push);
        }
        self.film.record_gather(cmd, &k.film_gather, sets, push);
    }

    /// Submits the rest of a batch that ran `depth` bounces and adds its counters.
    pub(super) fn finish_batch(
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
pub(super) type BatchFn<'a> = &'a mut dyn FnMut(
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
pub(super) const SHORT_BOUNCE_CHUNKS: (u32, u32) = (4, BOUNCE_CHUNK);

/// The chunks of bounces of path batches whose budget exceeds one chunk (paths of
/// unbounded length, ended by Russian roulette): most paths end within a few bounces,
/// so submissions after 8, 24 and 56 bounces let a batch stop at the first that finds
/// no path left (docs/performance.md, "Renderer decisions").
const LONG_BUDGET_CHUNKS: (u32, u32) = (8, BOUNCE_CHUNK);
