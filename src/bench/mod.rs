//! Benchmarks: render time against error at increasing sample counts.
//!
//! [`run`] prepares a scene once, renders one warm-up sample (llvmpipe compiles a
//! kernel at its first real dispatch; that must not count), then renders samples
//! `0..spp` for each requested `spp` and compares each image with a reference:
//!
//! - `seconds`: wall time of [`Renderer::render`] (record, submit, wait, read the film
//!   back), without scene loading, BVH build, pipeline creation or kernel compilation,
//!   which [`Report::startup`] lists apart;
//! - `rmse`, `rel_mse`: [`metrics::rmse`] and [`metrics::rel_mse`] against the
//!   reference;
//! - `efficiency` = 1 / (seconds × relMSE), the usual figure of merit of Monte Carlo
//!   rendering (larger is better; for an unbiased estimator it is roughly constant in
//!   spp, so two renderers or integrators compare by it at any sample count);
//! - GPU time per kernel from timestamp queries;
//! - for the photon mappers (`photonmapper`, `sppm`): photon paths emitted and photons
//!   stored per second of photon tracing, the wall time of grid builds and of gathers,
//!   passes, and GPU memory per photon slot ([`PhotonStats`]).
//!
//! Timestamps stay on for every render. Measured on lavapipe (ao scene, 256 spp, 16
//! batches, three alternating runs each way): 7.03, 7.02, 6.95 s without, 9.44,
//! 5.82, 6.24 s with; at 64 spp 1.34, 1.39 s without and 1.41, 1.36 s with. The
//! difference is inside the run-to-run noise of this machine: a timestamp is written
//! once per dispatch, and a batch has a few dozen dispatches against millions of rays.
//! So one render per spp gives both the wall time and the per-kernel split, and the
//! table and the kernel times describe the same run.
//!
//! [`Report::to_json`] gives everything as JSON (the format is documented there) and
//! [`Report::table`] as text.

pub mod memory;

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde_json::{json, Value};

use crate::gpu::{Device, KernelTimes};
use crate::image::{self, metrics, Image};
use crate::render::photon::PhotonStats;
use crate::render::{self, RenderOptions, Renderer};
use crate::scene;

/// Why a benchmark could not run.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error(transparent)]
    Scene(#[from] scene::Error),
    #[error(transparent)]
    Render(#[from] render::Error),
    /// The reference could not be read (the message names the file).
    #[error("reference {0}")]
    Reference(image::Error),
    /// The reference does not have the scene's film size.
    #[error(
        "reference {} is {ref_width}x{ref_height} pixels but {} renders {width}x{height}; \
         render the reference at the scene's resolution (or pass -D for the scene's size)",
        reference.display(), scene.display()
    )]
    ReferenceSize {
        reference: PathBuf,
        scene: PathBuf,
        width: u32,
        height: u32,
        ref_width: u32,
        ref_height: u32,
    },
    /// Comparing a render with the reference failed.
    #[error("comparing with the reference: {0}")]
    Metrics(image::Error),
    /// Benchmark options that cannot work (no sample counts, zero spp).
    #[error("{0}")]
    Options(String),
}

pub type Result<T> = std::result::Result<T, Error>;

/// What to benchmark.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    /// Sample counts to render, each from sample 0 (default 1, 4, 16, 64, 256).
    pub spp: Vec<u32>,
    /// Integrator, seed, batch size, as for a render. `timestamps` is ignored: the
    /// timed renders record none, and one more render of the largest sample count
    /// records them for the per-kernel times (see [`run`]).
    pub render: RenderOptions,
    /// The scene's sensor to render (`--sensor`; `None`: the first).
    pub sensor: Option<usize>,
}

impl Default for BenchOptions {
    fn default() -> Self {
        BenchOptions {
            spp: DEFAULT_SPP.to_vec(),
            render: RenderOptions::default(),
            sensor: None,
        }
    }
}

/// The sample counts `wavetrace bench` renders unless told otherwise.
pub const DEFAULT_SPP: &[u32] = &[1, 4, 16, 64, 256];

/// One render of the benchmark.
#[derive(Debug, Clone)]
pub struct Row {
    /// Samples per pixel rendered: the requested count as the sampler rounds it.
    pub spp: u32,
    /// Samples per pixel asked for.
    pub requested_spp: u32,
    /// Wall time of the render, seconds.
    pub seconds: f64,
    /// Rays traced (camera, extension and shadow rays).
    pub rays: u64,
    /// Samples discarded as NaN or infinite.
    pub discarded: u64,
    /// Paths cut at the bounce budget ([`RenderStats::cut_paths`](crate::render::RenderStats)).
    pub cut_paths: u64,
    /// Mean squared error over pixels and channels (the issue tables' MSE).
    pub mse: f64,
    pub rmse: f64,
    pub rel_mse: f64,
    /// GPU time per kernel: for the largest sample count only, from a render of its
    /// own (see [`run`]); empty otherwise and where the device has no timestamps.
    pub kernel_times: KernelTimes,
    /// Photon mappers: photons, passes and where their time went.
    pub photons: Option<PhotonStats>,
}

impl Row {
    /// Millions of rays per second of wall time.
    pub fn mrays_per_second(&self) -> f64 {
        self.rays as f64 / self.seconds / 1e6
    }

    /// 1 / (seconds × relMSE): larger is better; infinite for an exact image.
    pub fn efficiency(&self) -> f64 {
        1.0 / (self.seconds * self.rel_mse)
    }
}

/// Time spent before the first measured sample, seconds.
#[derive(Debug, Clone, Default)]
pub struct Startup {
    /// Reading and parsing the scene and its meshes.
    pub scene_seconds: f64,
    /// Reading the reference EXR.
    pub reference_seconds: f64,
    /// Loading Vulkan, creating the instance and the device.
    pub vulkan_seconds: f64,
    pub bvh_seconds: f64,
    pub bvh_nodes: usize,
    pub bvh_sah_cost: f64,
    pub upload_seconds: f64,
    pub pipeline_seconds: f64,
    /// Every kernel dispatched once with no work (where llvmpipe compiles).
    pub first_dispatch_seconds: f64,
    /// The 1-spp warm-up render that precedes the measurements.
    pub warmup_seconds: f64,
}

/// Everything a benchmark measured.
#[derive(Debug, Clone)]
pub struct Report {
    pub scene: PathBuf,
    pub reference: PathBuf,
    /// `-D` defines the scene was loaded with.
    pub defines: Vec<(String, String)>,
    pub device: String,
    pub device_kind: String,
    pub driver: String,
    pub integrator: String,
    /// The sampler's type.
    pub sampler: String,
    pub width: u32,
    pub height: u32,
    pub seed: u32,
    /// Paths in flight per batch.
    pub batch_paths: u32,
    pub timestamps: bool,
    pub startup: Startup,
    pub rows: Vec<Row>,
}

/// Reads the scene (with `-D` defines) and the reference, checks that their sizes
/// agree, and runs the benchmark on `device`. `progress` is called after each batch
/// with (spp of the render under way, samples done, samples in all).
///
/// Each sample count is rendered and timed without GPU timestamps; the largest is
/// then rendered once more with them, for its row's per-kernel times. Timestamps
/// are not free: lavapipe flushes its context for each, which made renders with
/// volumetric paths of some 70 bounces (of 5 dispatches each, then) about 7% slower.
pub fn run(
    device: &Device,
    scene_path: &Path,
    defines: &[(String, String)],
    reference_path: &Path,
    options: &BenchOptions,
    progress: &mut dyn FnMut(u32, u64, u64),
) -> Result<Report> {
    if options.spp.is_empty() {
        return Err(Error::Options("no sample counts to render".into()));
    }
    if options.spp.contains(&0) {
        return Err(Error::Options("sample counts must be at least 1".into()));
    }

    let t = Instant::now();
    let mut scene = scene::load(scene_path, defines)?;
    if let Some(i) = options.sensor {
        scene
            .select_sensor(i)
            .map_err(|e| Error::Options(format!("--sensor: {}: {e}", scene_path.display())))?;
    }
    let scene_seconds = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let reference = Image::read_exr(reference_path).map_err(Error::Reference)?;
    let reference_seconds = t.elapsed().as_secs_f64();
    let (width, height) = (scene.camera.width, scene.camera.height);
    if (reference.width, reference.height) != (width, height) {
        return Err(Error::ReferenceSize {
            reference: reference_path.to_path_buf(),
            scene: scene_path.to_path_buf(),
            width,
            height,
            ref_width: reference.width,
            ref_height: reference.height,
        });
    }

    let render_options = RenderOptions {
        timestamps: false,
        // Batches sized for the largest render measured.
        expected_spp: options.spp.iter().max().copied(),
        ..options.render.clone()
    };
    let mut renderer = Renderer::new(device, &scene, &render_options)?;
    let (_, warmup) = renderer.render(1, &mut |_, _| {})?;

    let info = device.info();
    let s = &renderer.setup;
    let startup = Startup {
        scene_seconds,
        reference_seconds,
        vulkan_seconds: info.startup_seconds,
        bvh_seconds: s.bvh.build_seconds,
        bvh_nodes: s.bvh.node_count,
        bvh_sah_cost: s.bvh.sah_cost,
        upload_seconds: s.upload_seconds,
        pipeline_seconds: s.pipeline_seconds,
        first_dispatch_seconds: s.first_dispatch_seconds,
        warmup_seconds: warmup.seconds,
    };

    let mut rows = Vec::with_capacity(options.spp.len());
    for &spp in &options.spp {
        let (image, stats) = renderer.render(spp, &mut |done, total| progress(spp, done, total))?;
        rows.push(Row {
            spp: stats.spp,
            requested_spp: spp,
            seconds: stats.seconds,
            rays: stats.rays,
            discarded: stats.discarded,
            cut_paths: stats.cut_paths,
            mse: metrics::mse(&image, &reference).map_err(Error::Metrics)?,
            rmse: metrics::rmse(&image, &reference).map_err(Error::Metrics)?,
            rel_mse: metrics::rel_mse(&image, &reference).map_err(Error::Metrics)?,
            kernel_times: stats.kernel_times,
            photons: stats.photons,
        });
    }
    let has_timestamps = info.timestamp_period_ns.is_some();
    if let (true, Some(largest)) = (has_timestamps, rows.iter().map(|r| r.spp).max()) {
        renderer.set_timestamps(true);
        let (_, stats) =
            renderer.render(largest, &mut |done, total| progress(largest, done, total))?;
        if let Some(row) = rows.iter_mut().rev().find(|r| r.spp == stats.spp) {
            row.kernel_times = stats.kernel_times;
        }
    }

    Ok(Report {
        scene: scene_path.to_path_buf(),
        reference: reference_path.to_path_buf(),
        defines: defines.to_vec(),
        device: info.name.clone(),
        device_kind: info.kind.name().to_string(),
        driver: info.driver.clone(),
        integrator: renderer.integrator().name().to_string(),
        sampler: renderer.sampler().kind.name().to_string(),
        width,
        height,
        seed: options.render.seed,
        batch_paths: renderer.capacity(),
        timestamps: has_timestamps,
        startup,
        rows,
    })
}

impl Report {
    /// The row with the most samples (the last of them if several tie).
    pub fn largest(&self) -> Option<&Row> {
        self.rows.iter().max_by_key(|r| r.spp)
    }

    /// The table `wavetrace bench` prints: one line per sample count.
    pub fn table(&self) -> String {
        let mut s = format!(
            "{:>6} {:>10} {:>12} {:>12} {:>12} {:>9} {:>12}\n",
            "spp", "seconds", "MSE", "RMSE", "relMSE", "Mrays/s", "efficiency"
        );
        for r in &self.rows {
            s += &format!(
                "{:>6} {:>10.4} {:>12.4e} {:>12.4e} {:>12.4e} {:>9.3} {:>12.4e}\n",
                r.spp,
                r.seconds,
                r.mse,
                r.rmse,
                r.rel_mse,
                r.mrays_per_second(),
                r.efficiency()
            );
        }
        s
    }

    /// Photon statistics per row, as text (empty but for the photon mappers): photon
    /// paths emitted and photons stored per second of photon tracing, grid build and
    /// gather wall times, passes, memory per photon slot.
    pub fn photon_table(&self) -> String {
        if self.rows.iter().all(|r| r.photons.is_none()) {
            return String::new();
        }
        let mut s = format!(
            "{:>6} {:>12} {:>12} {:>11} {:>11} {:>11} {:>7} {:>10}\n",
            "spp", "emitted/s", "stored/s", "trace s", "grid s", "gather s", "passes", "B/photon"
        );
        for r in &self.rows {
            if let Some(p) = &r.photons {
                s += &format!(
                    "{:>6} {:>12.4e} {:>12.4e} {:>11.4} {:>11.4} {:>11.4} {:>7} {:>10.1}\n",
                    r.spp,
                    p.emitted_per_second(),
                    p.stored_per_second(),
                    p.trace_seconds,
                    p.grid_seconds,
                    p.gather_seconds,
                    p.passes,
                    p.bytes_per_photon
                );
            }
        }
        s
    }

    /// GPU time per kernel of the largest render, as text (empty without timestamps).
    pub fn kernel_table(&self) -> String {
        let Some(r) = self.largest() else {
            return String::new();
        };
        let total = r.kernel_times.total_seconds();
        if r.kernel_times.by_kernel.is_empty() {
            return String::new();
        }
        let mut s = format!(
            "GPU time per kernel at {} spp ({:.3} s in all; a render of its own with \
             timestamps, the timed one recorded none):\n",
            r.spp, total
        );
        let mut kernels: Vec<_> = r.kernel_times.by_kernel.iter().collect();
        kernels.sort_by(|a, b| b.1 .0.total_cmp(&a.1 .0));
        for (name, (secs, n)) in kernels {
            s += &format!(
                "  {name:<12} {:>10.2} ms {:>5.1} % over {n} dispatches\n",
                secs * 1e3,
                100.0 * secs / total.max(f64::MIN_POSITIVE)
            );
        }
        s
    }

    /// The report as JSON:
    ///
    /// ```json
    /// { "scene": "...", "reference": "...", "defines": {"res": "128"},
    ///   "device": "llvmpipe (LLVM 15.0.6, 256 bits)", "device_kind": "cpu",
    ///   "driver": "...", "integrator": "ao", "sampler": "independent", "width": 128,
    ///   "height": 128, "seed": 0,
    ///   "batch_paths": 262144, "timestamps": true,
    ///   "startup": { "scene_seconds": ..., "reference_seconds": ...,
    ///                "vulkan_seconds": ..., "bvh_seconds": ..., "bvh_nodes": ...,
    ///                "bvh_sah_cost": ..., "upload_seconds": ...,
    ///                "pipeline_seconds": ..., "first_dispatch_seconds": ...,
    ///                "warmup_seconds": ... },
    ///   "rows": [ { "spp": 1, "requested_spp": 1, "seconds": ..., "rays": ...,
    ///               "mrays_per_second": ..., "mse": ..., "rmse": ..., "rel_mse": ..., "efficiency": ..., "discarded": 0, "cut_paths": 0,
    ///               "kernels": { "intersect": { "seconds": ..., "dispatches": 4 }, ... } },
    ///             ... ] }
    /// ```
    ///
    /// `kernels` is empty but in the row of the largest sample count. `photons` is
    /// `null` but for the photon mappers: `{ "emitted", "stored", "retraced", "passes",
    /// "trace_seconds", "grid_seconds", "gather_seconds", "emitted_per_second",
    /// "stored_per_second", "capacity", "bytes_per_photon" }` (see [`PhotonStats`]).
    ///
    /// Times are seconds. A non-finite number (efficiency of an exact image) is `null`.
    pub fn to_json(&self) -> Value {
        let s = &self.startup;
        let rows: Vec<Value> = self
            .rows
            .iter()
            .map(|r| {
                let kernels: serde_json::Map<String, Value> = r
                    .kernel_times
                    .by_kernel
                    .iter()
                    .map(|(k, (secs, n))| (k.clone(), json!({"seconds": secs, "dispatches": n})))
                    .collect();
                json!({
                    "spp": r.spp,
                    "requested_spp": r.requested_spp,
                    "seconds": r.seconds,
                    "rays": r.rays,
                    "mrays_per_second": finite(r.mrays_per_second()),
                    "mse": r.mse,
                    "rmse": r.rmse,
                    "rel_mse": r.rel_mse,
                    "efficiency": finite(r.efficiency()),
                    "discarded": r.discarded,
                    "cut_paths": r.cut_paths,
                    "kernels": kernels,
                    "photons": r.photons.as_ref().map(photon_json),
                })
            })
            .collect();
        let defines: serde_json::Map<String, Value> = self
            .defines
            .iter()
            .map(|(k, v)| (k.clone(), Value::from(v.as_str())))
            .collect();
        json!({
            "scene": self.scene.display().to_string(),
            "reference": self.reference.display().to_string(),
            "defines": defines,
            "device": self.device,
            "device_kind": self.device_kind,
            "driver": self.driver,
            "integrator": self.integrator,
            "sampler": self.sampler,
            "width": self.width,
            "height": self.height,
            "seed": self.seed,
            "batch_paths": self.batch_paths,
            "timestamps": self.timestamps,
            "startup": {
                "scene_seconds": s.scene_seconds,
                "reference_seconds": s.reference_seconds,
                "vulkan_seconds": s.vulkan_seconds,
                "bvh_seconds": s.bvh_seconds,
                "bvh_nodes": s.bvh_nodes,
                "bvh_sah_cost": finite(s.bvh_sah_cost),
                "upload_seconds": s.upload_seconds,
                "pipeline_seconds": s.pipeline_seconds,
                "first_dispatch_seconds": s.first_dispatch_seconds,
                "warmup_seconds": s.warmup_seconds,
            },
            "rows": rows,
        })
    }
}

/// A row's photon statistics as JSON (see [`Report::to_json`]).
fn photon_json(p: &PhotonStats) -> Value {
    json!({
        "emitted": p.emitted,
        "stored": p.stored,
        "retraced": p.retraced,
        "passes": p.passes,
        "trace_seconds": p.trace_seconds,
        "grid_seconds": p.grid_seconds,
        "gather_seconds": p.gather_seconds,
        "emitted_per_second": finite(p.emitted_per_second()),
        "stored_per_second": finite(p.stored_per_second()),
        "capacity": p.capacity,
        "bytes_per_photon": finite(p.bytes_per_photon),
    })
}

/// `x` as a JSON number, or `null` when it is NaN or infinite (JSON has neither).
fn finite(x: f64) -> Value {
    if x.is_finite() {
        json!(x)
    } else {
        Value::Null
    }
}

/// Parses a comma-separated list of sample counts such as `1,4,16,64,256`.
pub fn parse_spp_list(text: &str) -> Result<Vec<u32>> {
    let counts = text
        .split(',')
        .map(|t| {
            let t = t.trim();
            match t.parse::<u32>() {
                Ok(n) if n > 0 => Ok(n),
                _ => Err(Error::Options(format!(
                    "--spp expects positive integers separated by commas, got {t:?} in {text:?}"
                ))),
            }
        })
        .collect::<Result<Vec<u32>>>()?;
    Ok(counts)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(spp: u32, seconds: f64, rel_mse: f64) -> Row {
        Row {
            spp,
            requested_spp: spp,
            seconds,
            rays: 2_000_000,
            discarded: 0,
            cut_paths: 0,
            mse: rel_mse,
            rmse: rel_mse.sqrt(),
            rel_mse,
            kernel_times: KernelTimes::default(),
            photons: None,
        }
    }

    fn report(rows: Vec<Row>) -> Report {
        Report {
            scene: "s.xml".into(),
            reference: "r.exr".into(),
            defines: vec![("res".into(), "128".into())],
            device: "dev".into(),
            device_kind: "cpu".into(),
            driver: "drv".into(),
            integrator: "ao".into(),
            sampler: "independent".into(),
            width: 8,
            height: 8,
            seed: 0,
            batch_paths: 64,
            timestamps: false,
            startup: Startup::default(),
            rows,
        }
    }

    #[test]
    fn parses_spp_lists() {
        assert_eq!(parse_spp_list("1,4, 16").unwrap(), vec![1, 4, 16]);
        assert!(parse_spp_list("1,,4").is_err());
        assert!(parse_spp_list("0").is_err());
        assert!(parse_spp_list("-1").is_err());
        assert!(parse_spp_list("four").is_err());
    }

    #[test]
    fn efficiency_and_ray_rate() {
        let r = row(4, 2.0, 0.25);
        assert_eq!(r.efficiency(), 2.0);
        assert_eq!(r.mrays_per_second(), 1.0);
    }

    #[test]
    fn json_has_every_row_and_null_for_infinite_efficiency() {
        let rep = report(vec![row(1, 1.0, 0.5), row(4, 2.0, 0.0)]);
        let v = rep.to_json();
        assert_eq!(v["rows"].as_array().unwrap().len(), 2);
        assert_eq!(v["rows"][0]["efficiency"], json!(2.0));
        assert!(v["rows"][1]["efficiency"].is_null());
        assert_eq!(v["defines"]["res"], json!("128"));
        // Round trip through text: valid JSON.
        let text = serde_json::to_string(&v).unwrap();
        assert_eq!(serde_json::from_str::<Value>(&text).unwrap(), v);
    }

    #[test]
    fn table_has_a_line_per_row() {
        let rep = report(vec![row(1, 1.0, 0.5), row(4, 2.0, 0.1)]);
        let t = rep.table();
        assert_eq!(t.lines().count(), 3);
        assert!(t.lines().next().unwrap().contains("relMSE"));
        assert_eq!(rep.largest().unwrap().spp, 4);
        assert_eq!(rep.kernel_table(), "");
        assert_eq!(rep.photon_table(), "");
    }

    #[test]
    fn photon_rows_print_rates_and_json() {
        let mut r = row(16, 2.0, 0.1);
        r.photons = Some(PhotonStats {
            emitted: 1000,
            stored: 500,
            trace_seconds: 0.5,
            passes: 2,
            bytes_per_photon: 80.0,
            ..Default::default()
        });
        let rep = report(vec![r]);
        let t = rep.photon_table();
        assert_eq!(t.lines().count(), 2);
        assert!(t.contains("2.0000e3") && t.contains("1.0000e3"), "{t}");
        let v = rep.to_json();
        assert_eq!(v["rows"][0]["photons"]["emitted_per_second"], json!(2000.0));
        assert_eq!(v["rows"][0]["photons"]["passes"], json!(2));
    }
}
