//! The `wavetrace` command line: parse arguments, call the library.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};

use wavetrace::bench;
use wavetrace::gpu::Device;
use wavetrace::render::{emitter_probe, RenderOptions};
use wavetrace::scene::film::{FileFormat, Filter, PixelFormat};
use wavetrace::scene::sampler::SamplerKind;
use wavetrace::scene::{self, Scene};
use wavetrace::warptest;

#[derive(Parser)]
#[command(
    name = "wavetrace",
    version,
    about = "A wavefront path tracer on Vulkan compute"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(clap::Args)]
struct SceneArgs {
    /// Scene file (Mitsuba 3 or Nori XML).
    scene: PathBuf,
    /// Override a scene default: -D spp=64 (Mitsuba `<default name= value=>`).
    #[arg(short = 'D', value_name = "NAME=VALUE")]
    define: Vec<String>,
}

/// How to run a render, shared by `render` and `bench`.
#[derive(clap::Args)]
struct RunArgs {
    /// Seed of the random numbers (added to the sampler's `seed`; default 0).
    #[arg(long)]
    seed: Option<u32>,
    /// Sampler, overriding the scene's type (its parameters carry over): independent,
    /// stratified, multijitter, orthogonal, ldsampler, zsobol.
    #[arg(long)]
    sampler: Option<String>,
    /// Integrator, overriding the scene's: normals, ao, simple, direct_ems,
    /// direct_mats, direct_mis (direct), path_mats, path_mis (path), vol_path_simple,
    /// vol_path_mis (volpath), single_scatter, photonmapper (Nori's photon mapper),
    /// sppm (stochastic progressive photon mapping: caustics, converging).
    #[arg(long)]
    integrator: Option<String>,
    /// Vulkan device: index or part of its name (see `wavetrace devices`); for
    /// `render`, also a comma-separated list or `all`: the samples are spread over
    /// those devices and merged (the same device may be named twice).
    #[arg(long)]
    device: Option<String>,
    /// Most paths in flight per batch.
    #[arg(long)]
    batch: Option<u32>,
    /// Most bounces a path may take before it is cut short, with a warning
    /// (default 65536; a max_depth ends paths sooner).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    max_bounces: Option<u32>,
    /// Photon mappers: most photons one photon-map pass holds (default: what the
    /// device's memory and binding limits allow); larger maps are gathered in passes.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    photons_per_pass: Option<u32>,
    /// Run the wavefront's kernels (a dispatch per stage and bounce) even on a CPU
    /// device, which otherwise runs each path's first bounce in one kernel,
    /// first_bounce (the whole path, for direct lighting). The same image either way
    /// up to float rounding.
    #[arg(long)]
    wavefront: bool,
    /// In scenes with null surfaces, let shade and shadow trace inside their crossing
    /// loops instead of leaving the rays that need it to kernels of their own (the
    /// same image either way up to float rounding; for comparisons).
    #[arg(long, conflicts_with = "deferral")]
    no_deferral: bool,
    /// Defer those rays even where the driver does not pay for it (by default only
    /// drivers other than Mesa 26's lavapipe defer; for comparisons).
    #[arg(long)]
    deferral: bool,
    /// AOVs to write beside the radiance, as named EXR channels (Mitsuba's `aov`
    /// integrator's): comma-separated types (depth, position, uv, geo_normal,
    /// sh_normal, albedo, prim_index, shape_index), each optionally `name:type`
    /// (default name: the type; `depth` gives channel `depth.T`).
    #[arg(long, value_name = "AOVS", value_parser = parse_aovs)]
    aov: Option<AovList>,
}

/// The AOVs `--aov` names.
#[derive(Clone, Debug)]
struct AovList(Vec<wavetrace::scene::integrator::aov::Aov>);

/// `--aov`: `type` or `name:type` entries.
fn parse_aovs(s: &str) -> Result<AovList, String> {
    wavetrace::scene::integrator::aov::parse_cli(s).map(AovList)
}

impl RunArgs {
    fn options(self, timestamps: bool) -> (RenderOptions, Option<String>) {
        let options = RenderOptions {
            integrator: self.integrator,
            seed: self.seed.unwrap_or(0),
            sampler: self.sampler,
            max_batch_paths: self.batch,
            timestamps,
            max_bounces: self.max_bounces,
            max_photons_per_pass: self.photons_per_pass,
            wavefront: self.wavefront,
            deferral: if self.no_deferral {
                Some(false)
            } else {
                self.deferral.then_some(true)
            },
            aovs: self.aov.map(|a| a.0).unwrap_or_default(),
            ..RenderOptions::default()
        };
        (options, self.device)
    }
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to a linear EXR (or the film's file format) and an sRGB PNG
    /// beside it; or some of its samples to a partial EXR (`--samples`), or the rest
    /// of an interrupted or partial render (`--resume`). A first Ctrl-C (SIGINT or
    /// SIGTERM) stops at the next sample boundary and writes a partial EXR to resume
    /// from; a second aborts at once.
    Render(cli::render::RenderArgs),
    /// Watch a scene converge in a window and move its camera (needs a display):
    /// WASDQE move, arrow keys turn, mouse drag orbits, scroll zooms, =/- move speed,
    /// [/] exposure, R resets the camera, P or F12 saves EXR + PNG, Esc quits.
    View {
        #[command(flatten)]
        scene: SceneArgs,
        /// Stop at this many samples per pixel (default: render until closed).
        #[arg(long)]
        spp: Option<u32>,
        /// Exposure of the display in stops (the saved EXR is not changed).
        #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
        exposure: f32,
        /// Render --spp samples (the scene's count without it), save what the window
        /// shows to this PNG, and exit.
        #[arg(long, value_name = "FILE.png")]
        screenshot: Option<PathBuf>,
        /// Sensor I of a scene with several (0: the first, the default), as `render
        /// --sensor` counts them.
        #[arg(long, value_name = "I")]
        sensor: Option<u32>,
        #[command(flatten)]
        run: RunArgs,
    },
    /// Merge partial EXRs of one render (`render --samples`) into the image of their
    /// samples, written in the film's formats as `render` writes it.
    Merge {
        /// The partial EXRs.
        #[arg(required = true)]
        parts: Vec<PathBuf>,
        /// Output file.
        #[arg(short, long)]
        output: PathBuf,
        /// Merge parts that do not hold every sample of the render: the image is
        /// then a partial EXR of the samples there are (its header says which).
        #[arg(long)]
        allow_gaps: bool,
    },
    /// Time against error: render at increasing sample counts and compare each image
    /// with a reference (RMSE, relMSE, rays/s, efficiency, GPU time per kernel).
    Bench {
        #[command(flatten)]
        scene: SceneArgs,
        /// Reference EXR of the scene's size (e.g. made by tools/mitsuba_ref.py).
        #[arg(long = "ref", value_name = "REF.exr")]
        reference: PathBuf,
        /// Sample counts, comma-separated; each is a render of samples 0..N.
        #[arg(long, value_name = "N,N,...", default_value = "1,4,16,64,256")]
        spp: String,
        /// Also write everything measured as JSON to this file.
        #[arg(long, value_name = "FILE")]
        json: Option<PathBuf>,
        /// Sensor I of a scene with several (0: the first, the default), as `render
        /// --sensor` counts them.
        #[arg(long, value_name = "I")]
        sensor: Option<u32>,
        #[command(flatten)]
        run: RunArgs,
        /// No progress bar.
        #[arg(short, long)]
        quiet: bool,
    },
    /// Print what a scene holds: shapes, triangles, BVH, emitters, integrator,
    /// sampler and the sample count it renders.
    Info {
        #[command(flatten)]
        scene: SceneArgs,
        /// Samples per pixel to round as the sampler would (default: the scene's).
        #[arg(long)]
        spp: Option<u32>,
        /// Sampler overriding the scene's type, as for `render`.
        #[arg(long)]
        sampler: Option<String>,
    },
    /// List the Vulkan devices wavetrace can use.
    Devices,
    /// Which CPU Vulkan driver and vector width runs here: with `--calibrate`, render a
    /// small Cornell box under the system's lavapipe and each newer one that
    /// `tools/lavapipe.sh --prebuilt` installed (at 256 and 512 bits), and record the
    /// fastest that renders the same image for every later run on this machine
    /// (`WAVETRACE_DRIVER=system` overrides it).
    Driver {
        /// Measure the candidates and record the fastest.
        #[arg(long)]
        calibrate: bool,
        /// The scene to measure with (default: the shipped Cornell box).
        #[arg(long)]
        scene: Option<PathBuf>,
        /// Renders per candidate (the best counts).
        #[arg(long, default_value_t = 2)]
        runs: u32,
    },
    /// Chi-square test of a GPU sampler against its own pdf (Nori's warptest): draw
    /// samples with the GLSL routine, histogram them, compare with the counts its pdf
    /// predicts, print X² and the p-value and draw the histograms. Exit status 0 when
    /// the test accepts the sampler, 1 when it rejects it (or on an error).
    #[command(allow_negative_numbers = true)]
    Warptest {
        // What to sample; the BSDFs named from the registry.
        #[arg(help = warptest::target::help())]
        target: String,
        /// Samples to draw.
        #[arg(long, default_value_t = 1_000_000, value_parser = clap::value_parser!(u32).range(1000..))]
        samples: u32,
        /// Seed of the sampler's random numbers.
        #[arg(long, default_value_t = 0)]
        seed: u32,
        /// Output PNG: observed counts, expected counts, residual (O - E) / sqrt(E)
        /// (default: warptest_TARGET.png).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Significance level of the test.
        #[arg(long, default_value_t = 0.01)]
        significance: f64,
        /// Roughness (microfacet distributions, rough BSDFs; default 0.2).
        #[arg(long)]
        alpha: Option<f32>,
        /// Anisotropic roughness along the tangent (with --alpha-v).
        #[arg(long)]
        alpha_u: Option<f32>,
        /// Anisotropic roughness along the bitangent (with --alpha-u).
        #[arg(long)]
        alpha_v: Option<f32>,
        /// Microfacet distribution of rough BSDFs: beckmann or ggx (default).
        #[arg(long)]
        distribution: Option<String>,
        /// Relative index of refraction (default 1.5).
        #[arg(long)]
        eta: Option<f32>,
        /// Incident angle from the normal in degrees (default 30; above 90: from
        /// below the surface).
        #[arg(long)]
        theta: Option<f32>,
        /// Incident azimuth in degrees (default 0).
        #[arg(long)]
        phi: Option<f32>,
        /// Henyey-Greenstein asymmetry (default 0.7).
        #[arg(long)]
        g: Option<f32>,
        /// Cosine of the cap's half angle (uniform_cap; default 0.5).
        #[arg(long)]
        cos_max: Option<f32>,
        /// Vulkan device: index or part of its name.
        #[arg(long)]
        device: Option<String>,
    },
}

fn parse_defines(defines: &[String]) -> Result<Vec<(String, String)>> {
    defines
        .iter()
        .map(|d| match d.split_once('=') {
            Some((k, v)) if !k.is_empty() => Ok((k.to_string(), v.to_string())),
            _ => bail!("-D expects NAME=VALUE, got {d:?}"),
        })
        .collect()
}

/// `wavetrace driver`: the recorded choice and the candidates, or (`--calibrate`) a
/// new measurement.
fn driver(calibrate: bool, scene: Option<PathBuf>, runs: u32) -> Result<()> {
    use wavetrace::gpu::driver_choice as dc;
    println!("machine: {}", dc::machine());
    if calibrate {
        let scene = match scene {
            Some(s) => s,
            None => std::env::current_exe()
                .ok()
                .and_then(|e| {
                    e.ancestors()
                        .map(|a| a.join("scenes/cbox/cbox_path.xml"))
                        .find(|p| p.is_file())
                })
                .context("no --scene given and the shipped scenes/cbox/cbox_path.xml not found above the executable")?,
        };
        let args: Vec<String> = ["-D", "res=256", "--spp", "32", "--seed", "1"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        println!(
            "measuring {} {} under each candidate ({runs} runs each):",
            scene.display(),
            args.join(" ")
        );
        for (c, result) in dc::calibrate(&scene, &args, runs)? {
            println!("  {}: {result}", c.describe());
        }
    } else {
        for c in dc::candidates() {
            println!("candidate: {}", c.describe());
        }
    }
    match dc::recorded() {
        Some(c) => println!("recorded for this machine: {}", c.describe()),
        None => println!("nothing recorded for this machine: the system's driver runs"),
    }
    Ok(())
}

fn load(args: &SceneArgs) -> Result<Scene> {
    let defines = parse_defines(&args.define)?;
    Ok(scene::load(&args.scene, &defines)?)
}

mod cli;

fn main() {
    // A recorded faster driver (`wavetrace driver --calibrate`) takes over here, before
    // Vulkan is opened; `driver` itself always runs as it was started.
    if std::env::args_os().nth(1).is_none_or(|a| a != "driver") {
        wavetrace::gpu::driver_choice::apply();
    }
    if let Err(e) = run(Cli::parse()) {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render(args) => cli::render::run(args),
        Command::Merge {
            parts,
            output,
            allow_gaps,
        } => crate::cli::render::merge(&parts, &output, allow_gaps),
        Command::View {
            scene,
            spp,
            exposure,
            screenshot,
            sensor,
            run,
        } => view(&scene, spp, exposure, screenshot, sensor, run),
        Command::Bench {
            scene,
            reference,
            spp,
            json,
            sensor,
            run,
            quiet,
        } => {
            let (render, device) = run.options(true);
            let options = bench::BenchOptions {
                spp: bench::parse_spp_list(&spp)?,
                render,
                sensor: sensor.map(|i| i as usize),
            };
            bench(
                &scene,
                &reference,
                json.as_deref(),
                options,
                device.as_deref(),
                quiet,
            )
        }
        Command::Info {
            scene,
            spp,
            sampler,
        } => {
            let t = Instant::now();
            let sc = load(&scene)?;
            print_info(&sc, t.elapsed().as_secs_f64(), spp, sampler.as_deref())?;
            Ok(())
        }
        Command::Driver {
            calibrate,
            scene,
            runs,
        } => driver(calibrate, scene, runs),
        Command::Devices => {
            for d in Device::list()? {
                println!("[{}] {} ({})", d.index, d.name, d.kind.name());
            }
            Ok(())
        }
        Command::Warptest {
            target,
            samples,
            seed,
            output,
            significance,
            alpha,
            alpha_u,
            alpha_v,
            distribution,
            eta,
            theta,
            phi,
            g,
            cos_max,
            device,
        } => {
            let params = warptest::target::Params {
                alpha,
                alpha_u,
                alpha_v,
                distribution,
                eta,
                theta,
                phi,
                g,
                cos_max,
            };
            if !(significance > 0.0 && significance < 1.0) {
                bail!("--significance must lie in (0, 1), found {significance}");
            }
            let (what, description) =
                warptest::target::parse(&target, &params).map_err(anyhow::Error::msg)?;
            let output = output.unwrap_or_else(|| PathBuf::from(format!("warptest_{target}.png")));
            let device = Device::new(device.as_deref())?;
            eprintln!("device: {}", device.info());
            let t = Instant::now();
            let outcome = match &what {
                warptest::Test::Kernel(target) => warptest::run(&device, target, samples, seed)?,
                warptest::Test::DirectionalArea(light) => {
                    emitter_probe::test_directional_area(&device, *light, samples, seed)?
                }
            };
            println!("{target}: {description}");
            println!(
                "{} samples in {:.2} s ({} left out: delta lobes or absorbed; {} off the domain), \
                 {} cells, integral of the pdf {:.4}",
                outcome.samples,
                t.elapsed().as_secs_f64(),
                outcome.excluded,
                outcome.outside,
                outcome.grid.cells(),
                outcome.pdf_integral
            );
            let pass = outcome.passes(significance);
            println!(
                "chi-square: X² = {:.1} with {} degrees of freedom, p-value = {:.4e}: {} at significance {significance}",
                outcome.chi2.statistic,
                outcome.chi2.dof,
                outcome.chi2.p_value,
                if pass { "passes" } else { "FAILS" }
            );
            // The error names the file and says why (no "writing" context: it would
            // name the file twice).
            warptest::image::write_png(&outcome, &output)?;
            println!(
                "wrote {} (left: observed counts, middle: expected counts, right: (O - E) / sqrt(E))",
                output.display()
            );
            if !pass {
                std::process::exit(1);
            }
            Ok(())
        }
    }
}

#[cfg(feature = "viewer")]
fn view(
    scene: &SceneArgs,
    spp: Option<u32>,
    exposure: f32,
    screenshot: Option<PathBuf>,
    sensor: Option<u32>,
    run: RunArgs,
) -> Result<()> {
    let started = Instant::now();
    if spp == Some(0) {
        bail!("--spp must be at least 1");
    }
    if !exposure.is_finite() {
        bail!("--exposure must be a finite number of stops");
    }
    // Say there is no display before loading a large scene.
    if let Some(reason) = wavetrace::viewer::window::missing_display() {
        return Err(wavetrace::viewer::Error::NoDisplay(reason).into());
    }
    let mut sc = load(scene)?;
    if let Some(i) = sensor {
        sc.select_sensor(i as usize)
            .map_err(|e| anyhow::anyhow!("--sensor: {}: {e}", scene.scene.display()))?;
    }
    let (render, device) = run.options(false);
    let options = wavetrace::viewer::ViewOptions {
        spp,
        exposure,
        screenshot,
        device,
        render,
        save_dir: PathBuf::from("."),
    };
    let report = wavetrace::viewer::run(&sc, &options, started, &mut |line| eprintln!("{line}"))?;
    eprintln!(
        "viewer: first frame {:.2} s after start; while rendering {:.1} frames/s, \
         {:.2} M samples/s ({} frames, {:.1} s); last image {} spp",
        report.first_frame_seconds,
        report.frames_per_second(),
        report.samples_per_second() / 1e6,
        report.render_frames,
        report.render_seconds,
        report.spp
    );
    Ok(())
}

#[cfg(not(feature = "viewer"))]
fn view(
    _scene: &SceneArgs,
    _spp: Option<u32>,
    _exposure: f32,
    _screenshot: Option<PathBuf>,
    _sensor: Option<u32>,
    _run: RunArgs,
) -> Result<()> {
    bail!(
        "this wavetrace was built without the viewer (cargo feature `viewer`); \
         render with `wavetrace render SCENE.xml`, or watch it in tev with --tev"
    )
}

fn bench(
    scene: &SceneArgs,
    reference: &Path,
    json: Option<&Path>,
    options: bench::BenchOptions,
    device: Option<&str>,
    quiet: bool,
) -> Result<()> {
    let defines = parse_defines(&scene.define)?;
    let device = Device::new(device)?;
    eprintln!("device: {}", device.info());
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::new(0);
        bar.set_style(
            ProgressStyle::with_template("{bar:40} {percent:>3}% {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        bar
    };
    let report = bench::run(
        &device,
        &scene.scene,
        &defines,
        reference,
        &options,
        &mut |spp, done, total| {
            bar.set_length(total);
            bar.set_position(done);
            bar.set_message(format!("{spp} spp"));
        },
    )?;
    bar.finish_and_clear();
    let s = &report.startup;
    eprintln!(
        "start-up: scene {:.0} ms, reference {:.0} ms, vulkan {:.0} ms, bvh {:.0} ms ({} nodes, SAH {:.1}), \
         upload {:.0} ms, pipelines {:.0} ms, first dispatch {:.0} ms, warm-up render (1 spp) {:.0} ms",
        s.scene_seconds * 1e3,
        s.reference_seconds * 1e3,
        s.vulkan_seconds * 1e3,
        s.bvh_seconds * 1e3,
        s.bvh_nodes,
        s.bvh_sah_cost,
        s.upload_seconds * 1e3,
        s.pipeline_seconds * 1e3,
        s.first_dispatch_seconds * 1e3,
        s.warmup_seconds * 1e3,
    );
    for r in report.rows.iter().filter(|r| r.spp != r.requested_spp) {
        eprintln!(
            "note: sampler '{}' rounds {} spp to {} (Mitsuba's rule)",
            report.sampler, r.requested_spp, r.spp
        );
    }
    println!(
        "{} ({}x{}, integrator {}, sampler {}, seed {}) against {}",
        report.scene.display(),
        report.width,
        report.height,
        report.integrator,
        report.sampler,
        report.seed,
        report.reference.display()
    );
    print!("{}", report.table());
    print!("{}", report.photon_table());
    print!("{}", report.kernel_table());
    for r in report.rows.iter().filter(|r| r.discarded > 0) {
        eprintln!(
            "warning: {} samples at {} spp were NaN or infinite and were discarded",
            r.discarded, r.spp
        );
    }
    for r in report.rows.iter().filter(|r| r.cut_paths > 0) {
        eprintln!(
            "warning: {} paths at {} spp were still going at the bounce budget and were cut short",
            r.cut_paths, r.spp
        );
    }
    if let Some(path) = json {
        let text = serde_json::to_string_pretty(&report.to_json())?;
        std::fs::write(path, text + "\n").with_context(|| format!("writing {}", path.display()))?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

/// `path` with the extension of `format` (Mitsuba replaces any other; `.hdr` is
/// kept for RGBE, its usual name).
fn output_path(path: &Path, format: FileFormat) -> PathBuf {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    match (format, ext.as_str()) {
        (FileFormat::OpenExr, "exr")
        | (FileFormat::Rgbe, "rgbe" | "hdr")
        | (FileFormat::Pfm, "pfm") => path.to_path_buf(),
        _ => path.with_extension(format.extension()),
    }
}

/// The film in words: filter, crop window, sampled border, pixel format.
fn describe_film(sc: &Scene) -> String {
    let f = &sc.film;
    let filter = match f.filter {
        Filter::Box => "box filter".to_string(),
        Filter::Tent { radius } => format!("tent filter (radius {radius})"),
        Filter::Gaussian { stddev, radius } => {
            format!("gaussian filter (stddev {stddev}, radius {radius})")
        }
        Filter::Mitchell { b, c, radius } => {
            format!("mitchell filter (B {b}, C {c}, radius {radius})")
        }
        Filter::Lanczos { lobes } => format!("lanczos filter ({lobes} lobes)"),
    };
    let mut parts = vec![filter];
    if let Some(c) = f.crop {
        parts.push(format!(
            "crop {}x{} at ({}, {}) of {}x{}",
            c.width, c.height, c.x, c.y, sc.camera.width, sc.camera.height
        ));
    }
    if f.sample_border {
        parts.push("sampled border".into());
    }
    if f.pixel_format != PixelFormat::Rgb {
        parts.push(f.pixel_format.name().to_string());
    }
    parts.join(", ")
}

fn default_output(scene: &Path) -> PathBuf {
    let stem = scene
        .file_stem()
        .map(|s| s.to_os_string())
        .unwrap_or_else(|| "render".into());
    PathBuf::from(stem).with_extension("exr")
}

fn print_info(
    sc: &Scene,
    load_seconds: f64,
    spp: Option<u32>,
    sampler: Option<&str>,
) -> Result<()> {
    use wavetrace::bench::memory::PeakMeter;
    println!(
        "scene:       {} (loaded in {:.1} ms)",
        sc.path.display(),
        load_seconds * 1e3
    );
    let c = &sc.camera;
    println!(
        "camera:      {}x{}, horizontal fov {:.2}°, clip [{}, {}]",
        c.width, c.height, c.fov_x_deg, c.near_clip, c.far_clip
    );
    println!("film:        {}", describe_film(sc));
    let s = wavetrace::render::choose_sampler(sc, sampler)?;
    let requested = spp.unwrap_or(sc.spp);
    let count = s
        .sample_count(requested, c.width, c.height)
        .map_err(anyhow::Error::msg)?;
    let mut params = format!("seed {}", s.seed);
    match s.kind {
        SamplerKind::Stratified | SamplerKind::Multijitter => {
            params += &format!(", jitter {}", s.jitter)
        }
        SamplerKind::Orthogonal => {
            params += &format!(", jitter {}, strength {}", s.jitter, s.strength)
        }
        SamplerKind::ZSobol => params += &format!(", randomization {}", s.randomization.name()),
        SamplerKind::Independent | SamplerKind::LdSampler => {}
    }
    println!("sampler:     {} ({params})", s.kind.name());
    if count.count == requested {
        println!("samples:     {} per pixel", count.count);
    } else {
        println!(
            "samples:     {} per pixel ({requested} asked for, rounded by the sampler)",
            count.count
        );
    }
    println!(
        "integrator:  {} {:?}",
        sc.integrator.name, sc.integrator.params
    );
    println!("meshes:      {}", sc.meshes.len());
    for m in &sc.meshes {
        // Curves (linearcurve): segments between control points.
        let (prims, points) = if m.is_ellipsoids() {
            ("ellipsoids", "centres")
        } else if m.is_curves() {
            ("segments", "control points")
        } else {
            ("triangles", "vertices")
        };
        println!(
            "  {:<40} {:>8} {prims} {:>8} {points}{}{}{}",
            m.name,
            m.indices.len(),
            m.positions.len(),
            if m.normals.is_empty() {
                ""
            } else {
                ", normals"
            },
            if m.uvs.is_empty() { "" } else { ", uvs" },
            if m.emitter.is_some() { ", emitter" } else { "" },
        );
    }
    println!("quadrics:    {}", sc.quadrics.len());
    for q in &sc.quadrics {
        println!(
            "  {:?}, area {}{}",
            q.kind,
            q.area(),
            if q.emitter.is_some() { ", emitter" } else { "" }
        );
    }
    println!("triangles:   {}", sc.triangle_count());
    if !sc.groups.is_empty() {
        // Unique: stored once (a group's once however often it is placed);
        // instanced: what rays may meet, each instance counting its group's.
        println!(
            "instancing:  {} groups, {} instances; triangles {} unique, {} instanced",
            sc.groups.len(),
            sc.instances.len(),
            sc.triangle_count(),
            sc.instanced_triangle_count()
        );
    }
    println!("features:    {}", sc.features().join(", "));
    println!("bsdfs:       {}", sc.bsdfs.len());
    println!("emitters:    {}", sc.emitters.len());
    for e in &sc.emitters {
        println!("  {e:?}");
    }
    let meter = PeakMeter::start();
    let bvh = wavetrace::accel::instance::scene_bvh(sc).map_err(anyhow::Error::msg)?;
    let s = &bvh.stats;
    // The build's peak above the loaded scene, where the OS tells it.
    let peak = meter
        .extra()
        .map(|b| {
            let prims = bvh.prims.len().max(1) as f64;
            format!(
                ", build peak {:.1} MiB ({:.0} bytes a primitive)",
                b as f64 / (1u64 << 20) as f64,
                b as f64 / prims
            )
        })
        .unwrap_or_default();
    println!(
        "bvh:         {} nodes, {} leaves, depth {}, largest leaf {}, SAH cost {:.2}, built in {:.1} ms{peak}",
        s.node_count,
        s.leaf_count,
        s.max_depth,
        s.max_leaf_size,
        s.sah_cost,
        s.build_seconds * 1e3
    );
    if let Some(t) = &bvh.two_level {
        println!(
            "two-level:   {} instances ({}-byte records); top level {} nodes, {} primitives; traversal stack {}",
            t.instances, t.record_bytes(), t.top_nodes, t.top_prims, t.stack_depth
        );
    }
    print_device_memory(sc, &bvh);
    Ok(())
}

/// The memory each scene buffer takes on the device, and how it is split over
/// bindings there (on the default device, or as on lavapipe without one).
fn print_device_memory(sc: &Scene, bvh: &wavetrace::accel::Bvh) {
    use wavetrace::render::scene_buffers::SceneRecords;
    use wavetrace::render::scene_parts::{
        array_sizes, scene_arrays, ScenePlan, DEFAULT_PART_SHIFT,
    };
    let records = SceneRecords::new(sc, bvh);
    let bytes = array_sizes(&scene_arrays(bvh, &records));
    let (plan, on) = match Device::new(None) {
        Ok(device) => (
            ScenePlan::for_device(device.info(), bytes, None),
            device.info().to_string(),
        ),
        Err(e) => (
            ScenePlan::new(bytes, DEFAULT_PART_SHIFT),
            format!("no Vulkan device ({e}); bindings as on lavapipe"),
        ),
    };
    println!("device memory of the scene buffers, on {on}:");
    match plan {
        Ok(plan) => {
            for line in plan.describe() {
                println!("  {line}");
            }
        }
        Err(e) => println!("  the scene does not fit: {e}"),
    }
}

/// How the kernels' modules were specialized, for the start-up line: "7 kernels
/// specialized, 7 from cache" (see `gpu::specialize`).
fn specialization_summary() -> String {
    let st = wavetrace::gpu::specialize::stats();
    let mut parts = vec![format!(
        "{} kernels specialized, {} from cache",
        st.cached + st.optimized,
        st.cached
    )];
    if st.driver > 0 {
        parts.push(format!("{} by the driver", st.driver));
    }
    parts.join(", ")
}
