//! Shared helpers of the GPU tests. They run on whatever Vulkan device is best (on CI:
//! lavapipe); a missing device fails the test with the reason.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use glam::Vec3;
use wavetrace::accel::{prims_from_scene, Bvh, FlatPrims};
use wavetrace::gpu::{
    shaders, BindingKind, BindingLayout, Buffer, CommandList, DescriptorSet, Device, Kernel,
    Location,
};
use wavetrace::image::metrics::{block_t_test, block_t_test_correlated, rel_mse, BlockTest};
use wavetrace::image::Image;
use wavetrace::render::scene_buffers::{scene_binding_kinds, SceneBuffers, SceneRecords};
use wavetrace::render::{RenderOptions, Renderer};
use wavetrace::scene::Scene;

pub fn device() -> Device {
    Device::new(std::env::var("WAVETRACE_DEVICE").ok().as_deref())
        .expect("a Vulkan device (run tools/setup.sh)")
}

/// The scene uploaded for a test kernel: its binding layout (set 0 the scene's
/// bindings, set 1 `storage_buffers` storage buffers, `push_bytes` of push constants)
/// and the scene's buffers in set 0.
pub fn upload_scene(
    device: &Device,
    bvh: &Bvh,
    records: &SceneRecords,
    storage_buffers: usize,
    push_bytes: u32,
) -> (BindingLayout, SceneBuffers) {
    let layout = BindingLayout::with_kinds(
        device,
        &[
            scene_binding_kinds(),
            vec![BindingKind::Storage; storage_buffers],
        ],
        push_bytes,
    )
    .unwrap();
    let buffers = SceneBuffers::upload(device, &layout, bvh, records).unwrap();
    (layout, buffers)
}

/// Runs a test kernel that reads the scene (set 0, `scene_set`) and, in set 1, the
/// `queries` (binding 0) and writes one vec4 per query (binding 1), in workgroups of
/// 64 with push constants `push`; returns the results.
pub fn run_query_kernel(
    device: &Device,
    layout: &BindingLayout,
    kernel: &Kernel,
    scene_set: &DescriptorSet,
    queries: &[[f32; 4]],
    push: &[u32],
) -> Vec<[f32; 4]> {
    let input = Buffer::from_slice(device, "queries", queries).expect("queries buffer");
    let out = Buffer::new(device, "results", queries.len() as u64 * 16, Location::Gpu)
        .expect("results buffer");
    let set = DescriptorSet::new(layout, 1, &[&input, &out]).expect("query set");
    let mut cmd = CommandList::new(device).expect("command list");
    cmd.dispatch(
        kernel,
        &[scene_set, &set],
        bytemuck::cast_slice(push),
        [(queries.len() as u32).div_ceil(64), 1, 1],
    );
    cmd.submit_and_wait().expect("query kernel");
    let mut raw: Vec<[f32; 4]> = out.read(device).expect("read results");
    raw.truncate(queries.len());
    raw
}

/// What tests/surface_query.comp found along a ray: the closest hit's point `p` at
/// distance `t`, geometric and shading normals, shading tangent (sh_frame.s) and uv.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceHit {
    pub p: Vec3,
    pub t: f32,
    pub ng: Vec3,
    pub ns: Vec3,
    pub ss: Vec3,
    pub uv: [f32; 2],
}

/// Pairs what [`surface_query`] found along a Mitsuba hit/miss case's rays (its
/// `hits`, then its `misses`, as `found`) with Mitsuba's records: pushes to `failures`
/// each of Mitsuba's misses that ours hits and each of its hits that ours misses, and
/// returns the hits both found, each with Mitsuba's record and the ray as a label.
pub fn hits_both_found<'a>(
    case: &'a serde_json::Value,
    found: &[Option<SurfaceHit>],
    failures: &mut Vec<String>,
) -> Vec<(&'a serde_json::Value, SurfaceHit, String)> {
    let name = case["name"].as_str().unwrap();
    let hits = case["hits"].as_array().unwrap();
    let misses = case["misses"].as_array().unwrap();
    for (m, f) in misses.iter().zip(&found[hits.len()..]) {
        if let Some(SurfaceHit { p, t, .. }) = f {
            failures.push(format!(
                "{name}: ours a hit at {p} (t {t}), Mitsuba's a miss (ray {} {})",
                m["o"], m["d"]
            ));
        }
    }
    let mut both = Vec::new();
    for (h, f) in hits.iter().zip(found) {
        let ray = format!("ray {} {}", h["o"], h["d"]);
        match f {
            Some(hit) => both.push((h, *hit, ray)),
            None => failures.push(format!(
                "{name}: ours a miss, Mitsuba's t = {} ({ray})",
                h["t"]
            )),
        }
    }
    both
}

/// Loads the scene at `scene_path`, builds and uploads its tree and traces `rays`
/// (origin, direction) with the `surface_query` test kernel: the surface at each
/// closest hit, or None on a miss.
pub fn surface_query(scene_path: &Path, rays: &[(Vec3, Vec3)]) -> Vec<Option<SurfaceHit>> {
    let scene = load(scene_path);
    let device = device();
    let bvh = Bvh::build(prims_from_scene(&scene));
    let records = SceneRecords::new(&scene, &bvh);
    let (layout, buffers) = upload_scene(&device, &bvh, &records, 2, 4);
    let kernel = Kernel::new(
        &device,
        "surface_query",
        shaders::TESTS_SURFACE_QUERY,
        &layout,
        &FlatPrims::of(&bvh, 0).constants(),
    )
    .unwrap();
    let queries: Vec<[f32; 4]> = rays
        .iter()
        .flat_map(|(o, d)| {
            [
                o.extend(0.0).into(),
                d.extend(0.0).into(),
                [0.0; 4],
                [0.0; 4],
            ]
        })
        .collect();
    let raw = run_query_kernel(
        &device,
        &layout,
        &kernel,
        &buffers.set,
        &queries,
        &[queries.len() as u32],
    );
    raw.chunks_exact(4)
        .map(|r| {
            (r[1][3] >= 0.0).then(|| {
                let v = |k: usize| Vec3::new(r[k][0], r[k][1], r[k][2]);
                SurfaceHit {
                    p: v(0),
                    t: r[0][3],
                    ng: v(1),
                    ns: v(2),
                    ss: v(3),
                    uv: [r[2][3], r[3][3]],
                }
            })
        })
        .collect()
}

/// A scene file `name`.xml in the temporary folder of `test`: a perspective sensor and
/// `shape` (a Mitsuba snippet whose files are looked up in `dir`).
pub fn shape_scene(test: &str, name: &str, dir: &Path, shape: &str) -> PathBuf {
    let xml = format!(
        "<scene version=\"3.0.0\">\n<path value=\"{}\"/>\n<sensor type=\"perspective\"/>\n{shape}\n</scene>\n",
        dir.display()
    );
    temp_file(test, &format!("{name}.xml"), &xml)
}

/// Runs the `wavetrace` binary in the repository root: (exit status, stdout, stderr).
pub fn wavetrace(args: &[&str]) -> (i32, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_wavetrace"))
        .current_dir(repo(""))
        .args(args)
        .output()
        .expect("run wavetrace");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Renders `scene` at `spp` to `out` with the `wavetrace` binary, quietly: (exit
/// status, stdout, stderr).
pub fn render_to(scene: &Path, out: &Path, spp: &str) -> (i32, String, String) {
    wavetrace(&[
        "render",
        scene.to_str().unwrap(),
        "--spp",
        spp,
        "-o",
        out.to_str().unwrap(),
        "-q",
    ])
}

/// The window `letterbox` (src/gpu/letterbox.rs) draws on the device for `push` from
/// the picture `pixels` (4 bytes a pixel, R in the lowest, top row first): 4 bytes a
/// window pixel in the order `push` says, top row first.
pub fn letterbox_window(push: &wavetrace::gpu::layout::LetterboxPush, pixels: &[u32]) -> Vec<u32> {
    use wavetrace::gpu::letterbox::{self, Letterbox};
    let device = device();
    let kernel = Letterbox::new(&device).expect("letterbox kernel");
    let picture = Buffer::from_slice(&device, "picture", pixels).unwrap();
    let bytes = u64::from(push.window_width) * u64::from(push.window_height) * 4;
    let window = Buffer::new(&device, "window", bytes, Location::Gpu).unwrap();
    let set = kernel.bind(&picture, &window).unwrap();
    let mut cmd = CommandList::new(&device).unwrap();
    cmd.dispatch(
        &kernel.kernel,
        &[&set],
        bytemuck::bytes_of(push),
        letterbox::groups(push),
    );
    cmd.barrier();
    cmd.submit_and_wait().unwrap();
    window.read(&device).unwrap()
}

/// Writes a driver record (`wavetrace driver --calibrate`'s
/// `driver-choice.json`) into `cache/wavetrace`, for a run with XDG_CACHE_HOME =
/// `cache`: measured on `machine`, choosing `driver` (a newer lavapipe's folder;
/// `None`: the system's driver) at `width` bits.
pub fn write_driver_record(cache: &Path, machine: &str, driver: Option<&Path>, width: u32) {
    let dir = cache.join("wavetrace");
    std::fs::create_dir_all(&dir).unwrap();
    let driver = driver.map_or("null".to_string(), |d| format!("\"{}\"", d.display()));
    std::fs::write(
        dir.join("driver-choice.json"),
        format!(
            r#"{{"machine": {}, "choice": {{"driver": {driver}, "width": {width}}}}}"#,
            serde_json::to_string(machine).unwrap()
        ),
    )
    .unwrap();
}

/// The newest newer lavapipe installed in the user's cache (`tools/lavapipe.sh
/// --prebuilt`), if any; without one, says the test skips, or fails it where
/// WAVETRACE_REQUIRE_PREBUILT is set (as `.ci/run` sets it once it installed one).
pub fn installed_prebuilt() -> Option<PathBuf> {
    let found = std::env::var_os("HOME").and_then(|home| {
        let cache = PathBuf::from(home).join(".cache/wavetrace");
        let mut found: Vec<PathBuf> = std::fs::read_dir(cache)
            .ok()?
            .flatten()
            .map(|e| e.path())
            .filter(|p| {
                p.file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with("lavapipe-deb-"))
                    && p.join(".complete").is_file()
            })
            .collect();
        found.sort();
        found.pop()
    });
    if found.is_none() {
        assert!(
            std::env::var_os("WAVETRACE_REQUIRE_PREBUILT").is_none(),
            "WAVETRACE_REQUIRE_PREBUILT is set but no newer lavapipe is installed in ~/.cache/wavetrace"
        );
        eprintln!("skipped: no newer lavapipe installed (tools/lavapipe.sh --prebuilt)");
    }
    found
}

/// Path of a file in the repository.
pub fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

/// A temporary folder of this test process for `test` (created if need be).
pub fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("wavetrace-test-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("create temp dir");
    dir
}

/// Writes `text` to a fresh file in a per-test temporary folder and returns its path.
pub fn temp_file(test: &str, name: &str, text: &str) -> PathBuf {
    let path = temp_dir(test).join(name);
    std::fs::write(&path, text).expect("write temp file");
    path
}

pub fn load(path: &Path) -> Scene {
    wavetrace::scene::load(path, &[]).unwrap_or_else(|e| panic!("loading {}: {e}", path.display()))
}

/// Loads the scene at `path` with `-D` `defines`.
pub fn load_with(path: &Path, defines: &[(&str, &str)]) -> Scene {
    let d: Vec<(String, String)> = defines
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
    wavetrace::scene::load(path, &d).unwrap_or_else(|e| panic!("loading {}: {e}", path.display()))
}

/// Block t-test of `img` against `reference` (image::metrics: per 8x8 block and channel
/// a one-sample t-test of the pixel differences, the worst p-value Bonferroni-corrected
/// over all blocks): prints `label` with the outcome and the relMSE, and panics unless
/// the render passes at 1% and the same test rejects the render scaled by 0.95 (it
/// must have the power to see a 5% bias).
pub fn assert_matches_reference(img: &Image, reference: &Image, label: &str) -> BlockTest {
    assert_matches_filtered_reference(img, reference, label, &wavetrace::scene::film::Filter::Box)
}

/// [`assert_matches_reference`] for an image made with a reconstruction filter wider
/// than a pixel (as its reference was): neighbouring pixels share samples, so their
/// noise correlates and a block mean varies more than for independent pixels; the
/// block t-test widens its standard error by the filter's factor
/// (`Filter::block_variance_factor`; 1 for the box).
pub fn assert_matches_filtered_reference(
    img: &Image,
    reference: &Image,
    label: &str,
    filter: &wavetrace::scene::film::Filter,
) -> BlockTest {
    let factor = filter.block_variance_factor(8);
    let test = block_t_test_correlated(img, reference, 8, factor).expect("t-test");
    println!(
        "{label}: {test} (variance x {factor:.2}); relMSE {:.3e}",
        rel_mse(img, reference).expect("relMSE")
    );
    assert!(
        test.passes(0.01),
        "{label}: render disagrees with the Mitsuba reference: {test}"
    );
    let mut biased = img.clone();
    biased.rgb.iter_mut().for_each(|v| *v *= 0.95);
    let b = block_t_test_correlated(&biased, reference, 8, factor).expect("t-test");
    assert!(
        !b.passes(0.01),
        "{label}: the check cannot see a 5% bias: {b}"
    );
    test
}

/// Outcome of [`compare_with_reference`]: the worst 8x8 block and the whole image.
pub struct Comparison {
    pub blocks: BlockTest,
    pub whole: BlockTest,
}

impl Comparison {
    /// Passes at family-wise level `alpha`: half of it for the blocks, half for the
    /// whole image (Bonferroni).
    pub fn passes(&self, alpha: f64) -> bool {
        self.blocks.passes(0.5 * alpha) && self.whole.passes(0.5 * alpha)
    }
}

/// Two t-tests of the per-pixel differences (image::metrics::block_t_test): per 8x8
/// block and channel (a local error), and over the whole image per channel (a small
/// global bias, which the whole image resolves far better than any one block). Both
/// take the noise from the spread of the differences, so a noisy reference's own
/// variance is part of it.
pub fn compare_with_reference(img: &Image, reference: &Image) -> Comparison {
    let whole_side = img.width.max(img.height);
    Comparison {
        blocks: block_t_test(img, reference, 8).expect("t-test"),
        whole: block_t_test(img, reference, whole_side).expect("t-test"),
    }
}

/// [`compare_with_reference`] at family-wise level `alpha`: prints `label` with both
/// outcomes and the relMSE, and panics unless the render passes and the same tests
/// reject the render scaled by 0.95 (they must have the power to see a 5% bias).
pub fn assert_matches_reference_at(
    img: &Image,
    reference: &Image,
    label: &str,
    alpha: f64,
) -> Comparison {
    let c = compare_with_reference(img, reference);
    println!(
        "{label}: blocks {}; whole image {}; relMSE {:.3e}",
        c.blocks,
        c.whole,
        rel_mse(img, reference).expect("relMSE")
    );
    assert!(
        c.passes(alpha),
        "{label}: render disagrees with the reference at level {alpha:.1e}: blocks {}; whole image {}",
        c.blocks,
        c.whole
    );
    let mut biased = img.clone();
    biased.rgb.iter_mut().for_each(|v| *v *= 0.95);
    let b = compare_with_reference(&biased, reference);
    println!(
        "{label} x 0.95: blocks p = {:.2e}, whole image p = {:.2e}",
        b.blocks.p_bonferroni, b.whole.p_bonferroni
    );
    assert!(
        !b.passes(alpha),
        "{label}: the check cannot see a 5% bias: blocks {}; whole image {}",
        b.blocks,
        b.whole
    );
    c
}

/// Renders `spp` samples (samples `0..spp`) of a scene.
pub fn render(device: &Device, scene: &Scene, options: &RenderOptions, spp: u32) -> Image {
    let mut r =
        Renderer::new(device, scene, options).unwrap_or_else(|e| panic!("setting up render: {e}"));
    r.render(spp, &mut |_, _| {}).expect("render").0
}

/// Mean of every channel of every pixel.
pub fn mean(img: &Image) -> f64 {
    img.rgb.iter().map(|&v| v as f64).sum::<f64>() / img.rgb.len() as f64
}

/// The largest difference between two images' values relative to the larger of the
/// two (values under 1e-3 count as 1e-3): for images equal up to float rounding.
pub fn largest_relative_difference(a: &Image, b: &Image) -> f32 {
    a.rgb
        .iter()
        .zip(&b.rgb)
        .map(|(x, y)| (x - y).abs() / x.abs().max(y.abs()).max(1e-3))
        .fold(0.0f32, f32::max)
}

/// The RGB value of pixel (x, y).
pub fn pixel(img: &Image, x: u32, y: u32) -> [f32; 3] {
    let i = 3 * (y * img.width + x) as usize;
    [img.rgb[i], img.rgb[i + 1], img.rgb[i + 2]]
}
/// `img` box-averaged over `k` x `k` pixels.
pub fn downsample(img: &Image, k: u32) -> Image {
    assert!(img.width.is_multiple_of(k) && img.height.is_multiple_of(k));
    let mut out = Image::new(img.width / k, img.height / k);
    let w = 1.0 / (k * k) as f64;
    for y in 0..out.height {
        for x in 0..out.width {
            let mut sum = [0.0f64; 3];
            for dy in 0..k {
                for dx in 0..k {
                    let p = img.pixel(k * x + dx, k * y + dy);
                    (0..3).for_each(|c| sum[c] += p[c] as f64);
                }
            }
            out.set_pixel(x, y, sum.map(|s| (s * w) as f32));
        }
    }
    out
}

pub mod albedo;
pub mod aov_channels;
pub mod media;
pub mod mitsuba_values;
pub mod stats;

/// The BSDF a Mitsuba dictionary of numbers and `{"type": "rgb", "value": [..]}`
/// colors describes (as the tools/ scripts pass them to `mi.load_dict`), read by
/// wavetrace's scene loader; `test` names the temporary file.
pub fn bsdf_from_mitsuba_dict(d: &serde_json::Value, test: &str) -> wavetrace::scene::bsdf::Bsdf {
    use serde_json::Value;
    let mut body = String::new();
    for (k, v) in d.as_object().expect("a dictionary") {
        match v {
            Value::Number(x) => body += &format!("<float name=\"{k}\" value=\"{x}\"/>"),
            Value::Object(o) => {
                let c: Vec<String> = o["value"]
                    .as_array()
                    .expect("rgb values")
                    .iter()
                    .map(|x| x.to_string())
                    .collect();
                body += &format!("<rgb name=\"{k}\" value=\"{}\"/>", c.join(", "))
            }
            Value::String(x) if k != "type" => {
                body += &format!("<string name=\"{k}\" value=\"{x}\"/>")
            }
            _ => {}
        }
    }
    let xml = format!(
        "<scene version=\"3.0.0\"><sensor type=\"perspective\"/><bsdf type=\"{}\" id=\"m\">{body}</bsdf></scene>",
        d["type"].as_str().expect("type")
    );
    let scene = load(&temp_file(test, "bsdf.xml", &xml));
    scene.bsdfs[0].clone()
}
