//! `wavetrace render` and `wavetrace merge`: whole renders, sample ranges, partial
//! EXRs, interruption, checkpoints, resuming, several devices.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use indicatif::{ProgressBar, ProgressStyle};

use wavetrace::gpu::Device;
use wavetrace::image::tev::{self, TevStream};
use wavetrace::render::job::{self, JobControl, JobResult};
use wavetrace::render::partial::{self, Partial, RenderRecord, SampleRanges};
use wavetrace::render::{FilmSums, RenderStats, Renderer};
use wavetrace::scene::film::{FileFormat, PixelFormat};
use wavetrace::scene::{self, Scene};

use crate::{describe_film, output_path, parse_defines, RunArgs};

/// The arguments of `wavetrace render`.
#[derive(clap::Args)]
pub struct RenderArgs {
    /// Scene file (Mitsuba 3 or Nori XML); not with --resume.
    #[arg(required_unless_present = "resume")]
    pub scene: Option<PathBuf>,
    /// Override a scene default: -D spp=64 (Mitsuba `<default name= value=>`).
    #[arg(short = 'D', value_name = "NAME=VALUE")]
    pub define: Vec<String>,
    /// Output file (default: the scene's name in the current folder); its
    /// extension becomes the film's file format's (exr, rgbe or pfm), as in
    /// Mitsuba. Partial renders are always EXR.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Samples per pixel of the whole render (default: the scene's sampler).
    #[arg(long)]
    pub spp: Option<u32>,
    /// Render only samples A to B-1 of every pixel (of the whole render's --spp)
    /// into a partial EXR for `wavetrace merge`.
    #[arg(long, value_name = "A..B")]
    pub samples: Option<String>,
    /// Render part I of N equal parts of the samples (0 <= I < N: samples
    /// I*S/N to (I+1)*S/N - 1 of the whole render's S), into a partial EXR: what a
    /// Slurm array task renders (tools/slurm).
    #[arg(long, value_name = "I/N", conflicts_with = "samples")]
    pub part: Option<String>,
    /// Render the samples a partial EXR lacks and write the whole image (scene,
    /// seed and options come from the partial; default output: the partial).
    #[arg(long, value_name = "PARTIAL.exr", conflicts_with_all = ["spp", "samples", "part"])]
    pub resume: Option<PathBuf>,
    /// Render sensor I of a scene with several (0: the first, the default; in the
    /// order of the file, sensors nested in shapes included, as Mitsuba's
    /// `mi.render(scene, sensor=I)` counts them).
    #[arg(long, value_name = "I")]
    pub sensor: Option<u32>,
    /// Write the partial EXR of the samples done so far every SECONDS (at the
    /// next sample boundary; atomically: a crash leaves the previous one).
    #[arg(long, value_name = "SECONDS")]
    pub checkpoint: Option<f64>,
    #[command(flatten)]
    pub run: RunArgs,
    /// Print GPU time per kernel (timestamp queries).
    #[arg(long)]
    pub profile: bool,
    /// No progress bar.
    #[arg(short, long)]
    pub quiet: bool,
    /// Stream the image in progress to tev (the HDR viewer) listening at HOST:PORT
    /// (default 127.0.0.1:14158); without tev the render goes on, with a warning.
    #[arg(long, value_name = "HOST:PORT", num_args = 0..=1,
          default_missing_value = tev::DEFAULT_ADDRESS)]
    pub tev: Option<String>,
}

/// Set by the first SIGINT/SIGTERM: stop at the next sample boundary.
static STOP: AtomicBool = AtomicBool::new(false);
/// Signals received.
static SIGNALS: AtomicUsize = AtomicUsize::new(0);
/// Whether the render in progress can stop at a sample boundary (not SPPM).
static STOPPABLE: AtomicBool = AtomicBool::new(true);

/// The first SIGINT or SIGTERM asks the render to stop at the next sample boundary;
/// the second exits at once (status 130).
fn install_signal_handler() -> Result<()> {
    ctrlc::set_handler(|| {
        if SIGNALS.fetch_add(1, Ordering::SeqCst) == 0 {
            STOP.store(true, Ordering::SeqCst);
            if STOPPABLE.load(Ordering::SeqCst) {
                eprintln!(
                    "\ninterrupted: finishing the samples in flight, then writing what is \
                     done (Ctrl-C again aborts at once)"
                );
            } else {
                eprintln!(
                    "\ninterrupted: sppm cannot stop between iterations (its radii shrink \
                     over them); Ctrl-C again aborts at once, losing the render"
                );
            }
        } else {
            eprintln!("aborted");
            std::process::exit(130);
        }
    })
    .context("installing the Ctrl-C handler")
}

/// What the render is of: the scene, the options, the whole render's sample count
/// as asked, and what is done already (a resumed partial).
struct Plan {
    scene: Scene,
    /// The scene file as given, and absolute (recorded for resuming).
    scene_path: PathBuf,
    defines: Vec<(String, String)>,
    spp: u32,
    /// `--samples`.
    samples: Option<std::ops::Range<u32>>,
    /// `--part I/N`.
    part: Option<(u32, u32)>,
    /// The samples a resumed render was asked for (`None`: all).
    target: SampleRanges,
    /// A resumed partial.
    resumed: Option<(PathBuf, Partial)>,
    /// `--sensor` (or the resumed partial's).
    sensor: Option<u32>,
}

fn plan(args: &mut RenderArgs) -> Result<Plan> {
    let Some(resume) = args.resume.clone() else {
        let scene_path = args.scene.clone().context("no scene file given")?;
        let defines = parse_defines(&args.define)?;
        let mut scene = scene::load(&scene_path, &defines)?;
        if let Some(i) = args.sensor {
            scene
                .select_sensor(i as usize)
                .map_err(|e| anyhow::anyhow!("--sensor: {}: {e}", scene_path.display()))?;
        }
        let spp = args.spp.unwrap_or(scene.spp);
        let samples = args
            .samples
            .as_deref()
            .map(partial::parse_range)
            .transpose()
            .map_err(anyhow::Error::msg)
            .context("--samples")?;
        let part = args.part.as_deref().map(parse_part).transpose()?;
        let target = samples.clone().map(SampleRanges::of).unwrap_or_default();
        return Ok(Plan {
            scene,
            scene_path,
            defines,
            spp,
            samples,
            part,
            target,
            resumed: None,
            sensor: args.sensor,
        });
    };
    let r = &args.run;
    let given: Vec<&str> = [
        (args.scene.is_some(), "a scene file"),
        (!args.define.is_empty(), "-D"),
        (r.seed.is_some(), "--seed"),
        (r.integrator.is_some(), "--integrator"),
        (r.sampler.is_some(), "--sampler"),
        (r.max_bounces.is_some(), "--max-bounces"),
        (r.aov.is_some(), "--aov"),
        (args.sensor.is_some(), "--sensor"),
    ]
    .into_iter()
    .filter_map(|(given, name)| given.then_some(name))
    .collect();
    if !given.is_empty() {
        bail!(
            "--resume takes the scene and how to render it from the partial; drop {}",
            given.join(", ")
        );
    }
    let p = Partial::read(&resume)?;
    let rec = &p.record;
    if rec.to_do().is_empty() {
        bail!(
            "{} holds all the samples it was rendered for ({}): nothing to resume \
             (`wavetrace merge` merges it with other parts)",
            resume.display(),
            rec.samples_in_words()
        );
    }
    let hash = partial::file_sha256(&rec.scene)
        .with_context(|| format!("reading the scene file {}", rec.scene.display()))?;
    if hash != rec.scene_sha256 {
        bail!(
            "{} changed since {} was rendered (its sha256 is {hash}, the partial's {}): \
             resuming would mix two scenes",
            rec.scene.display(),
            resume.display(),
            rec.scene_sha256
        );
    }
    let mut scene = scene::load(&rec.scene, &rec.defines)?;
    if let Some(i) = rec.sensor {
        scene
            .select_sensor(i as usize)
            .map_err(anyhow::Error::msg)?;
    }
    args.sensor = rec.sensor;
    args.run.seed = Some(rec.seed);
    args.run.integrator = rec.integrator_option.clone();
    args.run.sampler = rec.sampler_option.clone();
    args.run.max_bounces = rec.max_bounces;
    args.run.aov = rec
        .aov_option
        .as_deref()
        .map(crate::parse_aovs)
        .transpose()
        .map_err(anyhow::Error::msg)?;
    if args.output.is_none() {
        args.output = Some(resume.clone());
    }
    Ok(Plan {
        scene,
        scene_path: rec.scene.clone(),
        defines: rec.defines.clone(),
        spp: rec.spp,
        samples: None,
        part: None,
        target: rec.target.clone(),
        sensor: rec.sensor,
        resumed: Some((resume, p)),
    })
}

/// Parses `--part I/N` (0 <= I < N).
fn parse_part(text: &str) -> Result<(u32, u32)> {
    let bad = || anyhow::anyhow!("--part expects I/N with 0 <= I < N (part I of N), got '{text}'");
    let (i, n) = text.split_once('/').ok_or_else(bad)?;
    let (i, n): (u32, u32) = (
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if i >= n {
        return Err(bad());
    }
    Ok((i, n))
}

/// The devices `--device` names: one selector, or several (a comma list, `all`).
fn device_list(device: Option<&str>) -> Result<Vec<String>> {
    match device {
        Some("all") => Ok(Device::list()?
            .iter()
            .map(|d| d.index.to_string())
            .collect()),
        Some(list) if list.contains(',') => {
            let v: Vec<String> = list
                .split(',')
                .map(|s| s.trim().to_string())
                .filter(|s| !s.is_empty())
                .collect();
            if v.is_empty() {
                bail!("--device {list:?} names no device");
            }
            Ok(v)
        }
        Some(one) => Ok(vec![one.to_string()]),
        None => Ok(Vec::new()),
    }
}

pub fn run(mut args: RenderArgs) -> Result<()> {
    let t_load = Instant::now();
    let plan = plan(&mut args)?;
    let load_seconds = t_load.elapsed().as_secs_f64();
    let sc = &plan.scene;
    if plan.spp == 0 {
        bail!("--spp must be at least 1");
    }
    // A render of some samples (now or when the resumed partial was started) writes a
    // partial; an empty target is the whole render.
    let partial_mode = plan.samples.is_some()
        || plan.part.is_some()
        || plan
            .resumed
            .as_ref()
            .is_some_and(|(_, p)| p.record.target != SampleRanges::of(0..p.record.spp));
    let (output, partial_path) = outputs(&plan, args.output.clone(), partial_mode);
    let run = args.run;
    let seed = run.seed.unwrap_or(0);
    let record_base = (
        run.integrator.clone(),
        run.sampler.clone(),
        run.max_bounces,
        run.aov
            .as_ref()
            .map(|a| wavetrace::scene::integrator::aov::list(&a.0)),
    );
    let (mut options, device) = run.options(args.profile);
    // The batches are sized for the whole render's samples (a range needs fewer).
    options.expected_spp = Some(plan.spp);
    let devices = device_list(device.as_deref())?;
    install_signal_handler()?;

    // What the render uses, checked before any device is opened.
    let (integrator, sampler, geometry) = wavetrace::render::plan_render(sc, &options)?;
    let (kw, kh) = geometry.key_size();
    let count = sampler
        .sample_count(plan.spp, kw, kh)
        .map_err(anyhow::Error::msg)?;
    if let Some(w) = &count.warning {
        eprintln!("warning: {w}");
    }
    let spp = count.count;
    if integrator.name() == "sppm" {
        refuse_sppm_parts(
            &plan,
            partial_mode,
            args.checkpoint.is_some(),
            devices.len(),
        )?;
        STOPPABLE.store(false, Ordering::SeqCst);
    }
    let target = sample_share(&plan, spp, &sampler)?;

    // One device: its renderer here; several: one per thread (job::render_on_many).
    let mut single = if devices.len() <= 1 {
        Some(open_renderer(devices.first(), sc, &options, load_seconds)?)
    } else {
        None
    };
    let what = Rendered {
        integrator: &integrator,
        sampler: &sampler,
        geometry: &geometry,
        spp,
    };
    let record = render_record(&plan, &what, &target, seed, record_base)?;
    let (start, start_done) = match &plan.resumed {
        Some((_, p)) => (Some(p.sums.clone()), p.record.samples.clone()),
        None => (None, SampleRanges::default()),
    };
    let ranges = RenderRecord {
        samples: start_done.clone(),
        ..record.clone()
    }
    .to_do();
    announce(
        &plan,
        &what,
        single.as_ref().map(Renderer::capacity),
        &ranges,
    );

    let every = match args.checkpoint {
        Some(s) if !(s.is_finite() && s > 0.0) => {
            bail!("--checkpoint takes a positive number of seconds, not {s}")
        }
        s => s.map(Duration::from_secs_f64),
    };
    let job = Job {
        plan: &plan,
        options: &options,
        devices: &devices,
        count: &count,
        ranges: &ranges,
        start_done: &start_done,
        record: &record,
        partial_path: &partial_path,
        output: &output,
        every,
        pixels: u64::from(geometry.region_pixels()),
        quiet: args.quiet,
        tev: args.tev.as_deref(),
        profile: args.profile,
    };
    let result = run_job(&job, single.as_mut(), start)?;
    let Some(sums) = result.sums else {
        eprintln!("interrupted before the first sample was done: nothing written");
        std::process::exit(130);
    };
    let done = Partial {
        record: RenderRecord {
            samples: result.done.clone(),
            ..record.clone()
        },
        sums,
    };
    let outputs = Outputs {
        output: &output,
        partial: &partial_path,
        partial_mode,
        remove_partial: every.is_some() || plan.resumed.is_some(),
    };
    write_outputs(&done, result.stopped, &outputs)
}

/// Where the render writes (`asked`: `-o`): its output, and its partial (when
/// interrupted, or checkpoints). Partials are EXRs; the whole image is in the film's
/// format, its partial an EXR beside it when that is another format.
fn outputs(plan: &Plan, asked: Option<PathBuf>, partial_mode: bool) -> (PathBuf, PathBuf) {
    let format = plan.scene.film.file_format;
    let asked_output = asked.unwrap_or_else(|| {
        let stem = crate::default_output(&plan.scene_path).with_extension("");
        match (&plan.samples, plan.part) {
            (Some(r), _) => PathBuf::from(format!("{}_{}-{}.exr", stem.display(), r.start, r.end)),
            (_, Some((i, n))) => PathBuf::from(format!("{}_part{i}of{n}.exr", stem.display())),
            _ => crate::default_output(&plan.scene_path),
        }
    });
    let output = if partial_mode {
        output_path(&asked_output, FileFormat::OpenExr)
    } else {
        output_path(&asked_output, format)
    };
    if output != asked_output {
        eprintln!(
            "note: {} {}: writing {}",
            if partial_mode {
                "a partial render is an"
            } else {
                "the film's file format is"
            },
            if partial_mode {
                "EXR".to_string()
            } else {
                format.extension().to_string()
            },
            output.display()
        );
    }
    let partial_path = output_path(&output, FileFormat::OpenExr);
    (output, partial_path)
}

/// Why sppm cannot render this (parts of an image, a resumed or checkpointed render,
/// several devices), if it cannot.
fn refuse_sppm_parts(
    plan: &Plan,
    partial_mode: bool,
    checkpoint: bool,
    devices: usize,
) -> Result<()> {
    let what = if partial_mode {
        Some("--samples")
    } else if plan.resumed.is_some() {
        Some("--resume")
    } else if checkpoint {
        Some("--checkpoint")
    } else if devices > 1 {
        Some("several devices")
    } else {
        None
    };
    if let Some(what) = what {
        bail!(
            "sppm cannot render parts of an image ({what}): each iteration shrinks \
             every pixel's radius from the one before, so its samples are not \
             independent and do not merge; render it whole, or use path_mis or \
             photonmapper"
        );
    }
    Ok(())
}

/// The samples this render does of the whole render's `spp` (`--samples`, or
/// `--part I/N`: its share of the rounded count), checked to lie within it.
fn sample_share(
    plan: &Plan,
    spp: u32,
    sampler: &wavetrace::scene::sampler::Sampler,
) -> Result<SampleRanges> {
    // --part I/N: its share of the rounded count.
    let (samples, target) = match plan.part {
        Some((i, n)) => {
            if n > spp {
                bail!(
                    "--part {i}/{n}: the render's {spp} samples per pixel cannot be cut into \
                 {n} parts (at most one part per sample)"
                );
            }
            let at = |k: u32| (u64::from(k) * u64::from(spp) / u64::from(n)) as u32;
            let r = at(i)..at(i + 1);
            (Some(r.clone()), SampleRanges::of(r))
        }
        None => (plan.samples.clone(), plan.target.clone()),
    };
    if let Some(r) = &samples {
        if r.end > spp {
            bail!(
                "--samples {}..{} reaches past the render's {spp} samples per pixel (--spp, \
                 as the sampler '{}' rounds it): samples are numbered 0..{spp}",
                r.start,
                r.end,
                sampler.kind.name()
            );
        }
    }
    Ok(target)
}

/// The renderer of `sc` on `device` (`None`: the default device), with its start-up
/// printed (`load_seconds`: reading the scene).
fn open_renderer(
    device: Option<&String>,
    sc: &Scene,
    options: &wavetrace::render::RenderOptions,
    load_seconds: f64,
) -> Result<Renderer> {
    let device = Device::new(device.map(String::as_str))?;
    eprintln!("device: {}", device.info());
    if let Some(note) = wavetrace::gpu::driver_choice::chosen_note() {
        eprintln!("driver: {note}");
    }
    let renderer = Renderer::new(&device, sc, options)?;
    let s = &renderer.setup;
    eprintln!(
        "start-up: scene {:.0} ms, vulkan {:.0} ms, bvh {:.0} ms ({} nodes, SAH {:.1}{}), upload {:.0} ms{}, \
         pipelines {:.0} ms ({}), first dispatch (kernel compile) {:.0} ms",
        load_seconds * 1e3,
        device.info().startup_seconds * 1e3,
        s.bvh.build_seconds * 1e3,
        s.bvh.node_count,
        s.bvh.sah_cost,
        if s.flat.flat_only {
            format!("; its {} primitives tested in turn", s.flat.count)
        } else if s.flat.count > 0 {
            format!(
                "; {} quadric{} tested apart",
                s.flat.count,
                if s.flat.count == 1 { "" } else { "s" }
            )
        } else {
            String::new()
        },
        s.upload_seconds * 1e3,
        match s.scene_access {
            wavetrace::gpu::SceneAccess::Texels => "",
            wavetrace::gpu::SceneAccess::Split => " (arrays split over bindings)",
            wavetrace::gpu::SceneAccess::Storage => " (into storage buffers)",
        },
        s.pipeline_seconds * 1e3,
        crate::specialization_summary(),
        s.first_dispatch_seconds * 1e3,
    );
    if let Some(why) = wavetrace::gpu::specialize::stats().unavailable {
        eprintln!("note: kernels were specialized by the driver (slower start-up): {why}");
    }
    if let Some(lost) = renderer.film_overridden(&sc.film) {
        eprintln!(
            "warning: '{}' does not render this film's {lost}",
            renderer.integrator().name()
        );
    }
    Ok(renderer)
}

/// A progress bar of `len` steps where `draw` (a terminal), else a hidden one.
fn progress_bar(draw: bool, len: u64) -> ProgressBar {
    if draw {
        let bar = ProgressBar::new(len);
        bar.set_style(
            ProgressStyle::with_template(
                "{bar:40} {percent:>3}% {msg} [{elapsed_precise} < {eta_precise}]",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        bar
    } else {
        ProgressBar::hidden()
    }
}

/// The stream of the render's images to tev at `address`, named after `output`;
/// `None` (with a warning) where tev cannot be reached.
fn open_tev(address: &str, output: &Path, sc: &Scene, w: u32, h: u32) -> Option<Mutex<TevStream>> {
    let name = output.file_name().map_or_else(
        || "wavetrace".to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let names = sc.film.pixel_format.channel_names();
    match TevStream::create(address, &name, w, h, &names) {
        Ok(t) => {
            eprintln!("streaming to tev at {address} as '{name}'");
            Some(Mutex::new(t))
        }
        Err(e) => {
            eprintln!("warning: {e}; rendering without it");
            None
        }
    }
}

/// Where a render's images go.
struct Outputs<'a> {
    output: &'a Path,
    partial: &'a Path,
    /// The render is of some samples: its output is a partial.
    partial_mode: bool,
    /// Remove the partial once the whole image is written (checkpoints, a resume).
    remove_partial: bool,
}

/// Writes what a render did: the whole image, a partial render's EXR, or (`stopped`)
/// the partial to resume from (then exits with 130).
fn write_outputs(done: &Partial, stopped: bool, outputs: &Outputs) -> Result<()> {
    let png = outputs.output.with_extension("png");
    if stopped {
        let png = outputs.partial.with_extension("png");
        done.write(outputs.partial, Some(&png))?;
        eprintln!(
            "stopped: wrote {} and {} ({}, a partial render)",
            outputs.partial.display(),
            png.display(),
            done.record.samples_in_words()
        );
        eprintln!(
            "resume with: wavetrace render --resume {}{}",
            outputs.partial.display(),
            if outputs.partial == outputs.output || outputs.partial_mode {
                String::new()
            } else {
                format!(" -o {}", outputs.output.display())
            }
        );
        std::process::exit(130);
    }
    if outputs.partial_mode {
        done.write(outputs.output, Some(&png))?;
        eprintln!(
            "wrote {} and {} ({}; merge the parts with `wavetrace merge`)",
            outputs.output.display(),
            png.display(),
            done.record.samples_in_words()
        );
        return Ok(());
    }
    write_image(done, outputs.output, &png)?;
    if outputs.partial != outputs.output && outputs.partial.exists() && outputs.remove_partial {
        std::fs::remove_file(outputs.partial).ok();
        std::fs::remove_file(outputs.partial.with_extension("png")).ok();
    }
    eprintln!("wrote {} and {}", outputs.output.display(), png.display());
    Ok(())
}

/// What a render renders, as [`wavetrace::render::plan_render`] resolves it.
struct Rendered<'a> {
    integrator: &'a wavetrace::render::Integrator,
    sampler: &'a wavetrace::scene::sampler::Sampler,
    geometry: &'a wavetrace::render::film::FilmGeometry,
    /// The whole render's samples per pixel, as the sampler rounds them.
    spp: u32,
}

/// The record of the render (written into its partials), checked against a resumed
/// partial's.
fn render_record(
    plan: &Plan,
    what: &Rendered,
    target: &SampleRanges,
    seed: u32,
    (integrator_option, sampler_option, max_bounces, aov_option): (
        Option<String>,
        Option<String>,
        Option<u32>,
        Option<String>,
    ),
) -> Result<RenderRecord> {
    let film_dbg = format!("{:?}", plan.scene.film);
    let (pixel_name, component_name, file_name) = partial::format_names(
        plan.scene.film.pixel_format,
        plan.scene.film.component_format,
        plan.scene.film.file_format,
    );
    let scene_abs = std::fs::canonicalize(&plan.scene_path)
        .with_context(|| format!("finding {}", plan.scene_path.display()))?;
    let record = RenderRecord {
        scene: scene_abs.clone(),
        scene_sha256: partial::file_sha256(&scene_abs)
            .with_context(|| format!("reading {}", scene_abs.display()))?,
        defines: plan.defines.clone(),
        seed,
        integrator_option,
        sampler_option,
        max_bounces,
        aov_option,
        sensor: plan.sensor,
        integrator: format!("{:?}", what.integrator),
        sampler: format!("{:?}", what.sampler),
        film: film_dbg,
        spp: what.spp,
        film_size: (what.geometry.width, what.geometry.height),
        crop: what.geometry.crop,
        pixel_format: pixel_name,
        component_format: component_name,
        file_format: file_name,
        samples: SampleRanges::default(),
        target: if target.is_empty() {
            SampleRanges::of(0..what.spp)
        } else {
            target.clone()
        },
    };
    if let Some((path, p)) = &plan.resumed {
        if let Some(d) = p.record.difference(&record) {
            bail!(
                "{} does not match its scene as it loads now ({d}); it was rendered by \
                 another version of wavetrace or with other options",
                path.display()
            );
        }
    }
    Ok(record)
}

/// Says what the render renders (`capacity`: its paths per batch on one device) and
/// warns of a scene without emitters.
fn announce(plan: &Plan, what: &Rendered, capacity: Option<u32>, ranges: &SampleRanges) {
    let todo = ranges.count();
    eprintln!(
        "rendering {}x{} at {} spp with '{}', sampler '{}', {}{}{}",
        what.geometry.crop.width,
        what.geometry.crop.height,
        what.spp,
        what.integrator.name(),
        what.sampler.kind.name(),
        describe_film(&plan.scene),
        capacity
            .map(|c| format!(" ({c} paths per batch)"))
            .unwrap_or_default(),
        if todo == u64::from(what.spp) {
            String::new()
        } else {
            format!(": samples {ranges} ({todo} per pixel)")
        }
    );
    if what.integrator.needs_emitters() && plan.scene.emitters.is_empty() {
        eprintln!(
            "warning: {} has no emitters: '{}' will render a black image",
            plan.scene_path.display(),
            what.integrator.name()
        );
    }
}

/// What [`run_job`] renders and where its partials go.
struct Job<'a> {
    plan: &'a Plan,
    options: &'a wavetrace::render::RenderOptions,
    devices: &'a [String],
    count: &'a wavetrace::scene::sampler::SampleCount,
    ranges: &'a SampleRanges,
    /// The samples a resumed partial holds.
    start_done: &'a SampleRanges,
    record: &'a RenderRecord,
    partial_path: &'a Path,
    output: &'a Path,
    /// Checkpoint interval.
    every: Option<Duration>,
    /// The film's sampled pixels.
    pixels: u64,
    /// No progress bar (`-q`); where to stream the images (`--tev`); print the
    /// kernels' times (`--profile`).
    quiet: bool,
    tev: Option<&'a str>,
    profile: bool,
}

/// Renders `job`'s samples on `single` (else on the job's devices, one thread each)
/// from `start` (a resumed partial's sums), with progress, checkpoints and tev, and
/// reports its statistics.
fn run_job(job: &Job, single: Option<&mut Renderer>, start: Option<FilmSums>) -> Result<JobResult> {
    let todo = job.ranges.count();
    let (w, h) = (job.record.crop.width, job.record.crop.height);
    // Progress: a bar on a terminal, else (logs, batch jobs, -q) a line at the first
    // sample boundary and at most every 10 s after it.
    let draw_bar = !job.quiet && std::io::stderr().is_terminal();
    let bar = progress_bar(draw_bar, job.pixels * todo);
    let last_line: Mutex<Option<Instant>> = Mutex::new(None);
    let progress = |done: u64, _total: u64| {
        bar.set_position(done);
        bar.set_message(format!("{}/{todo} spp", done / job.pixels.max(1)));
    };
    let boundary = |done: u64, total: u64| {
        if draw_bar || done >= total {
            return;
        }
        let mut last = last_line.lock().unwrap_or_else(|e| e.into_inner());
        if last.is_none_or(|t| t.elapsed() >= Duration::from_secs(10)) {
            eprintln!("progress: {done}/{total} samples per pixel done");
            *last = Some(Instant::now());
        }
    };
    let checkpoint = |sums: &FilmSums, done: &SampleRanges| -> wavetrace::render::Result<()> {
        let p = Partial {
            record: RenderRecord {
                samples: done.clone(),
                ..job.record.clone()
            },
            sums: sums.clone(),
        };
        p.write(
            job.partial_path,
            Some(&job.partial_path.with_extension("png")),
        )?;
        bar.suspend(|| {
            eprintln!(
                "checkpoint: wrote {} ({})",
                job.partial_path.display(),
                p.record.samples_in_words()
            )
        });
        Ok(())
    };
    // tev: the image at sample boundaries, every TEV_INTERVAL, and at the end.
    let tev = job
        .tev
        .and_then(|address| open_tev(address, job.output, &job.plan.scene, w, h));
    let pixel_format = job.plan.scene.film.pixel_format;
    let show = |sums: &FilmSums| {
        if let Some(t) = &tev {
            send_to_tev(
                &mut t.lock().unwrap_or_else(|e| e.into_inner()),
                sums,
                pixel_format,
            );
        }
    };
    let control = JobControl {
        stop: &STOP,
        checkpoint_every: job.every,
        checkpoint: &checkpoint,
        boundary: &boundary,
        progress: &progress,
        preview: tev
            .is_some()
            .then_some((TEV_INTERVAL, &show as &job::Preview<'_>)),
    };
    let mut single = single;
    let result: JobResult = match single.as_deref_mut() {
        Some(renderer) => {
            renderer.set_sample_count(job.count.clone())?;
            job::render_on_one(renderer, job.ranges, start, job.start_done, &control)?
        }
        None => job::render_on_many(
            &job.plan.scene,
            job.options,
            job.devices,
            job.count.clone(),
            job.ranges,
            start,
            job.start_done,
            &control,
            &mut |name| bar.suspend(|| eprintln!("device: {name}")),
        )?,
    };
    bar.finish_and_clear();
    let stats = &result.stats;
    let rendered = result.done.count() - job.start_done.count();
    report_stats(stats, rendered * job.pixels, job.profile, single.as_deref());

    if let Some(sums) = &result.sums {
        show(sums);
    }
    Ok(result)
}

/// Time between the images a render sends to tev.
const TEV_INTERVAL: Duration = Duration::from_millis(500);

/// Sends the film to tev; a failure (tev closed) is a warning, once: later sends
/// are skipped.
fn send_to_tev(tev: &mut TevStream, film: &FilmSums, format: PixelFormat) {
    if tev.is_closed() {
        return;
    }
    let (_, data) = film.channels(format);
    if let Err(e) = tev.update(&data) {
        eprintln!("warning: {e}; no more updates go to tev");
        tev.close();
    }
}

/// Writes the image of a partial in its film's formats (with its record in an
/// EXR's header), atomically.
fn write_image(p: &Partial, output: &Path, png: &Path) -> Result<()> {
    let (pixel, component, file) = p.record.formats().map_err(anyhow::Error::msg)?;
    let extras = wavetrace::render::film::ExrExtras {
        text: p.record.text(),
        sums: false,
    };
    partial::write_atomically(output, Some(png), |exr, png| {
        p.sums.write_with(exr, pixel, component, file, png, &extras)
    })
    .with_context(|| format!("writing {}", output.display()))
}

fn report_stats(stats: &RenderStats, samples: u64, profile: bool, renderer: Option<&Renderer>) {
    eprintln!(
        "rendered in {:.3} s: {:.2} M samples/s, {:.2} M rays/s ({} rays, {} batches)",
        stats.seconds,
        samples as f64 / stats.seconds / 1e6,
        stats.rays as f64 / stats.seconds / 1e6,
        stats.rays,
        stats.batches
    );
    if let Some(p) = &stats.photons {
        eprintln!(
            "photons: {} paths emitted, {} photons stored in {} pass(es) of at most {} \
             ({:.2} M emitted/s, {:.2} M stored/s); tracing {:.3} s, grids {:.3} s, \
             gathers {:.3} s; {:.0} bytes per photon",
            p.emitted,
            p.stored,
            p.passes,
            p.capacity,
            p.emitted_per_second() / 1e6,
            p.stored_per_second() / 1e6,
            p.trace_seconds,
            p.grid_seconds,
            p.gather_seconds,
            p.bytes_per_photon
        );
    }
    if stats.discarded > 0 {
        eprintln!(
            "warning: {} samples were NaN or infinite and were discarded",
            stats.discarded
        );
    }
    if stats.cut_paths > 0 {
        eprintln!(
            "warning: {} paths were still going after {} bounces and were cut short \
             (the image misses their later light): give the integrator a max_depth, \
             or a smaller rr_depth",
            stats.cut_paths,
            renderer.map_or_else(
                || "the budget of".to_string(),
                |r| r.bounce_budget().to_string()
            )
        );
    }
    if profile {
        for (name, (secs, n)) in &stats.kernel_times.by_kernel {
            eprintln!("  {name:<15} {:>9.2} ms over {n} dispatches", secs * 1e3);
        }
        if stats.deferred > 0 {
            eprintln!(
                "  {} rays and shadow rays deferred to shade_deferred and shadow_deferred",
                stats.deferred
            );
        }
    }
}

/// `wavetrace merge PART.exr... -o OUT`.
pub fn merge(parts: &[PathBuf], output: &Path, allow_gaps: bool) -> Result<()> {
    let read: Vec<(PathBuf, Partial)> = parts
        .iter()
        .map(|p| Ok((p.clone(), Partial::read(p)?)))
        .collect::<Result<_>>()?;
    let merged = partial::merge(&read, allow_gaps)?;
    let rec = &merged.record;
    if rec.is_complete() {
        let (_, _, file) = rec.formats().map_err(anyhow::Error::msg)?;
        let out = output_path(output, file);
        let png = out.with_extension("png");
        write_image(&merged, &out, &png)?;
        eprintln!(
            "merged {} parts ({}): wrote {} and {}",
            parts.len(),
            rec.samples_in_words(),
            out.display(),
            png.display()
        );
    } else {
        let out = output_path(output, FileFormat::OpenExr);
        let png = out.with_extension("png");
        merged.write(&out, Some(&png))?;
        eprintln!(
            "merged {} parts: wrote {} and {}, a partial render of {} (samples {} are \
             missing; `wavetrace render --resume {}` renders them)",
            parts.len(),
            out.display(),
            png.display(),
            rec.samples_in_words(),
            rec.samples.missing(rec.spp),
            out.display()
        );
    }
    Ok(())
}
