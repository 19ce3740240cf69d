//! Sample ranges, partial EXRs, merging, interruption and resuming, several devices
//! (issue #15). The scene: `scenes/media/thin_textured.xml` (fog, a thin dielectric
//! with a checkerboard texture, an environment and an area light) at 20x20 pixels
//! with the stratified sampler at 9 spp, whose pattern depends on the whole render's
//! sample count, so parts that did not use the whole count would differ.
//!
//! What is exact (src/render/partial.rs): a pixel's sum is a float32 left fold over
//! its samples in order. Merging parts in range order is therefore bit for bit the
//! unsplit render when every part after the first holds one sample (the 2, 3 and 7
//! part splits below); other splits regroup the additions and agree to float32
//! rounding. Resuming continues the fold: bit for bit.

mod common;

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use common::{repo, temp_dir, wavetrace};
use wavetrace::image::exr;
use wavetrace::render::job::{self, JobControl};
use wavetrace::render::partial::{self, Partial, SampleRanges};
use wavetrace::render::{FilmSums, RenderOptions, Renderer};

const SCENE: &str = "scenes/media/thin_textured.xml";

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// Renders samples `range` of the test scene to `out` (a partial EXR), with `extra`
/// arguments; panics unless it succeeds.
fn render_part(scene: &Path, range: &str, out: &Path, extra: &[&str]) {
    let mut args = vec![
        "render",
        s(scene),
        "-D",
        "res=20",
        "--spp",
        "9",
        "--sampler",
        "stratified",
        "--samples",
        range,
        "-o",
        s(out),
        "-q",
    ];
    args.extend_from_slice(extra);
    let (code, _, err) = wavetrace(&args);
    assert_eq!(code, 0, "render --samples {range}: {err}");
}

fn read(path: &Path) -> Partial {
    Partial::read(path).unwrap_or_else(|e| panic!("{e}"))
}

/// Bits of every channel of an EXR: (name, values as bits).
fn channel_bits(path: &Path) -> Vec<(String, Vec<u32>)> {
    let (_, _, channels) = exr::read_channels(path).unwrap_or_else(|e| panic!("{e}"));
    channels
        .into_iter()
        .map(|c| (c.name, c.values.iter().map(|v| v.to_bits()).collect()))
        .collect()
}

fn bits(sums: &FilmSums) -> Vec<[u32; 4]> {
    sums.sums.iter().map(|p| p.map(f32::to_bits)).collect()
}

/// The largest difference between two films' sums relative to the larger value
/// (absolute below 1e-6).
fn max_relative_difference(a: &FilmSums, b: &FilmSums) -> f32 {
    a.sums
        .iter()
        .flatten()
        .zip(b.sums.iter().flatten())
        .map(|(x, y)| (x - y).abs() / x.abs().max(y.abs()).max(1e-6))
        .fold(0.0, f32::max)
}

/// Float32 regrouping of at most 9 additions of non-negative terms: each rounds by at
/// most 2^-24 relative, so the two folds differ by at most ~9 x 6e-8 of the sum.
const ROUNDING: f32 = 1e-6;

#[test]
fn parts_merge_into_the_unsplit_render_and_bad_merges_are_refused() {
    let d = temp_dir("merge");
    let scene = repo(SCENE);
    let whole = d.join("whole.exr");
    render_part(&scene, "0..9", &whole, &[]);
    let parts: Vec<PathBuf> = ["0..7", "7..8", "8..9"]
        .iter()
        .map(|r| {
            let p = d.join(format!("part{r}.exr"));
            render_part(&scene, r, &p, &[]);
            p
        })
        .collect();
    // The partial's header says what it holds; the PNG is beside it.
    let p0 = read(&parts[0]);
    assert_eq!(
        p0.record.samples_in_words(),
        "7 of 9 samples per pixel: 0..7"
    );
    assert!(parts[0].with_extension("png").exists());
    let (_, _, _, text) = exr::read_channels_with_text(&parts[0]).expect("read");
    assert!(text
        .iter()
        .any(|(k, v)| k == partial::SAMPLES_ATTRIBUTE && v.starts_with("7 of 9")));

    // Three parts, every one after the first one sample: the same fold as the unsplit
    // render, bit for bit, in whatever order the files are named.
    let named: Vec<(PathBuf, Partial)> = parts.iter().rev().map(|p| (p.clone(), read(p))).collect();
    let merged = partial::merge(&named, false).expect("merge");
    assert_eq!(bits(&merged.sums), bits(&read(&whole).sums));
    let merged_exr = d.join("merged.exr");
    let mut args = vec!["merge"];
    args.extend(parts.iter().map(|p| s(p)));
    args.extend(["-o", s(&merged_exr)]);
    let (code, _, err) = wavetrace(&args);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("9 of 9 samples per pixel"), "{err}");
    assert!(merged_exr.with_extension("png").exists());
    // The image in the film's formats (float16 RGB): that of the unsplit render.
    let whole_exr = d.join("whole_image.exr");
    let (code, _, err) = wavetrace(&["merge", s(&whole), "-o", s(&whole_exr)]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(channel_bits(&merged_exr), channel_bits(&whole_exr));
    assert_eq!(
        channel_bits(&merged_exr)
            .iter()
            .map(|(n, _)| n.as_str())
            .collect::<Vec<_>>(),
        ["B", "G", "R"]
    );

    // Refusals, each exit status 1 with its reason.
    let refuse = |args: &[&str], needle: &str| {
        let (code, _, err) = wavetrace(args);
        assert_eq!(code, 1, "{args:?} should fail: {err}");
        assert!(
            err.contains(needle),
            "{args:?}: expected '{needle}' in: {err}"
        );
    };
    // Another seed.
    let seeded = d.join("seed1.exr");
    render_part(&scene, "8..9", &seeded, &["--seed", "1"]);
    let out = d.join("bad.exr");
    refuse(
        &[
            "merge",
            s(&parts[0]),
            s(&parts[1]),
            s(&seeded),
            "-o",
            s(&out),
        ],
        "seeds 0 and 1",
    );
    // Another scene file (the same scene with one more comment: another hash).
    let text = std::fs::read_to_string(&scene).expect("scene");
    let other = d.join("other.xml");
    std::fs::write(&other, text.replace("<scene", "<!-- another -->\n<scene")).expect("write");
    let other_part = d.join("other.exr");
    render_part(&other, "8..9", &other_part, &[]);
    refuse(
        &[
            "merge",
            s(&parts[0]),
            s(&parts[1]),
            s(&other_part),
            "-o",
            s(&out),
        ],
        "different renders (scene files (sha256)",
    );
    // Overlapping ranges.
    refuse(
        &["merge", s(&whole), s(&parts[1]), "-o", s(&out)],
        "overlap in samples 7..8",
    );
    // A gap, unless allowed; then a partial that says what it holds.
    refuse(
        &["merge", s(&parts[0]), s(&parts[2]), "-o", s(&out)],
        "samples 7..8 are missing",
    );
    let (code, _, err) = wavetrace(&[
        "merge",
        s(&parts[0]),
        s(&parts[2]),
        "-o",
        s(&out),
        "--allow-gaps",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        read(&out).record.samples_in_words(),
        "8 of 9 samples per pixel: 0..7,8..9"
    );
    // Not a partial at all.
    refuse(
        &["merge", s(&merged_exr), s(&parts[0]), "-o", s(&out)],
        "a finished image, not a partial",
    );
    // A part past the render's samples.
    let (code, _, err) = wavetrace(&[
        "render",
        SCENE,
        "-D",
        "res=20",
        "--spp",
        "9",
        "--samples",
        "8..10",
        "-o",
        s(&out),
    ]);
    assert_eq!(code, 1);
    assert!(err.contains("reaches past the render's 9 samples"), "{err}");
    // --part I/N (what a Slurm array task renders: tools/slurm) needs 0 <= I < N and
    // at most one part per sample.
    for (part, needle) in [
        ("3/3", "0 <= I < N"),
        ("2/10", "cannot be cut into 10 parts"),
    ] {
        let (code, _, err) = wavetrace(&[
            "render",
            SCENE,
            "-D",
            "res=20",
            "--spp",
            "9",
            "--part",
            part,
            "-o",
            s(&out),
        ]);
        assert_eq!(code, 1, "{err}");
        assert!(err.contains(needle), "--part {part}: {err}");
    }

    std::fs::remove_dir_all(&d).ok();
}

/// A renderer of the test scene at 20x20, stratified, its pattern of 9 samples, two
/// samples of every pixel per batch.
fn renderer(device: &wavetrace::gpu::Device) -> (wavetrace::scene::Scene, RenderOptions, Renderer) {
    let scene = wavetrace::scene::load(
        &repo(SCENE),
        &[("res".into(), "20".into()), ("spp".into(), "9".into())],
    )
    .expect("scene");
    let options = RenderOptions {
        sampler: Some("stratified".into()),
        max_batch_paths: Some(800),
        ..RenderOptions::default()
    };
    let mut r = Renderer::new(device, &scene, &options).expect("renderer");
    let count = r.round_sample_count(9).expect("count");
    r.set_sample_count(count).expect("count");
    (scene, options, r)
}

fn fold(r: &mut Renderer, ranges: &[std::ops::Range<u32>]) -> FilmSums {
    let mut acc: Option<FilmSums> = None;
    for q in ranges {
        let (sums, _) = r
            .render_film(q.start, q.end - q.start, &mut |_, _| {})
            .expect("render");
        match &mut acc {
            Some(a) => a.merge(&sums).expect("merge"),
            None => acc = Some(sums),
        }
    }
    acc.expect("a range")
}

#[test]
fn range_sums_fold_resume_and_spread_over_devices_as_documented() {
    let device = common::device();
    let (scene, options, mut r) = renderer(&device);
    let unsplit = fold(&mut r, std::slice::from_ref(&(0..9)));
    // 2 and 7 parts, every one after the first a single sample: bit for bit.
    assert_eq!(bits(&fold(&mut r, &[0..8, 8..9])), bits(&unsplit));
    let seven = [0..3, 3..4, 4..5, 5..6, 6..7, 7..8, 8..9];
    assert_eq!(bits(&fold(&mut r, &seven)), bits(&unsplit));
    // Other splits regroup the float32 additions: equal to rounding.
    for split in [vec![0..4, 4..9], vec![0..2, 2..5, 5..9]] {
        let diff = max_relative_difference(&fold(&mut r, &split), &unsplit);
        assert!(diff <= ROUNDING, "{split:?}: {diff}");
    }
    // Continuing the sums of 0..3 (a resume; its batches are 3..5, 5..7, 7..9, not
    // the unsplit render's) is the unsplit fold, bit for bit.
    let first = fold(&mut r, std::slice::from_ref(&(0..3)));
    let (resumed, stats) = r
        .render_film_controlled(3, 6, Some(&first), &mut |_, _| {}, &mut |_, _| Ok(false))
        .expect("resume");
    assert_eq!(stats.spp, 6);
    assert_eq!(bits(&resumed), bits(&unsplit));
    // Stopping: at the end of the batch in flight (a sample boundary), the sums
    // holding exactly the samples done.
    let mut boundaries = Vec::new();
    let (stopped, stats) = r
        .render_film_controlled(0, 9, None, &mut |_, _| {}, &mut |_, done| {
            boundaries.push(done);
            Ok(done >= 3)
        })
        .expect("stop");
    assert_eq!(boundaries, [2, 4]);
    assert_eq!(stats.spp, 4);
    assert_eq!(
        bits(&stopped),
        bits(&fold(&mut r, std::slice::from_ref(&(0..4))))
    );

    // Two renderers on the same device, opened twice: chunks folded in sample order,
    // whichever device rendered them.
    let stop = std::sync::atomic::AtomicBool::new(false);
    let control = JobControl {
        stop: &stop,
        checkpoint_every: None,
        checkpoint: &|_, _| Ok(()),
        boundary: &|_, _| {},
        progress: &|_, _| {},
        preview: None,
    };
    let all = SampleRanges::of(0..9);
    let count = r.round_sample_count(9).expect("count");
    let result = job::render_on_many(
        &scene,
        &options,
        &["0".to_string(), "0".to_string()],
        count,
        &all,
        None,
        &SampleRanges::default(),
        &control,
        &mut |_| {},
    )
    .expect("two devices");
    assert!(!result.stopped);
    assert_eq!(result.done, all);
    let chunks = job::chunks(&all, 2);
    assert_eq!(chunks.len(), 5);
    let sums = result.sums.expect("sums");
    assert_eq!(bits(&sums), bits(&fold(&mut r, &chunks)));
    assert!(max_relative_difference(&sums, &unsplit) <= ROUNDING);
}

/// SIGINT after the first batch: a valid partial EXR saying how many samples it holds,
/// exit status non-zero with the resume command; `--resume` completes it to the image
/// of the uninterrupted render, bit for bit.
#[test]
fn interrupted_render_resumes_to_the_uninterrupted_image() {
    let d = temp_dir("resume");
    // 32x32 pixels, 1024 paths per batch: one sample per batch, 256 batches (about
    // 2 s on lavapipe), so the signal lands long before the end.
    let common_args = [
        "render", SCENE, "-D", "res=32", "--spp", "256", "--batch", "1024", "-q",
    ];
    let interrupted = d.join("int.exr");
    let mut child = Command::new(env!("CARGO_BIN_EXE_wavetrace"))
        .current_dir(repo(""))
        .args(common_args)
        .args(["-o", s(&interrupted)])
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    let mut stderr = BufReader::new(child.stderr.take().expect("stderr"));
    let mut log = String::new();
    // Wait for the line that says a batch (a sample of every pixel) is done.
    loop {
        let mut line = String::new();
        let n = stderr.read_line(&mut line).expect("read stderr");
        log += &line;
        assert!(n > 0, "the render ended without reporting progress: {log}");
        if line.starts_with("progress: ") {
            break;
        }
    }
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill");
    assert!(kill.success());
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut stderr, &mut rest).expect("read stderr");
    log += &rest;
    let status = child.wait().expect("wait");
    assert_eq!(status.code(), Some(130), "{log}");
    assert!(
        log.contains(&format!(
            "resume with: wavetrace render --resume {}",
            s(&interrupted)
        )),
        "{log}"
    );
    let p = read(&interrupted);
    let done = p.record.samples.count();
    assert!((1..256).contains(&done), "{done} samples done: {log}");
    assert_eq!(p.record.samples, SampleRanges::of(0..done as u32));
    let (_, _, _, text) = exr::read_channels_with_text(&interrupted).expect("read");
    let words = format!("{done} of 256 samples per pixel");
    assert!(
        text.iter()
            .any(|(k, v)| k == partial::SAMPLES_ATTRIBUTE && v.starts_with(&words)),
        "{text:?}"
    );
    assert!(interrupted.with_extension("png").exists());

    let resumed = d.join("resumed.exr");
    let (code, _, err) = wavetrace(&["render", "--resume", s(&interrupted), "-o", s(&resumed)]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains(&format!("samples {done}..256")), "{err}");
    let reference = d.join("reference.exr");
    let mut args = common_args.to_vec();
    args.extend(["-o", s(&reference)]);
    let (code, _, err) = wavetrace(&args);
    assert_eq!(code, 0, "{err}");
    assert_eq!(channel_bits(&resumed), channel_bits(&reference));
    // Options that the partial fixes are refused with --resume.
    let (code, _, err) = wavetrace(&["render", "--resume", s(&interrupted), "--seed", "3"]);
    assert_eq!(code, 1);
    assert!(err.contains("drop --seed"), "{err}");
    std::fs::remove_dir_all(&d).ok();
}
