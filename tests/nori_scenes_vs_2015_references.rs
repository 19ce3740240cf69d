//! Nori's course scenes (`../shared/scenes/nori`: veach_mi, odyssey, sphere, table)
//! against the reference images Nori's reference solution rendered in 2015 (`ref/`).
//!
//! The references are at full resolution with their own noise (their sample counts are
//! in their names) and Nori's Gaussian reconstruction filter (radius 2, stddev 0.5),
//! which the scene files ask for by naming no filter. Each scene is rendered here at a
//! quarter of its width and height with a box filter, and the reference is
//! box-averaged 4 x 4 to the same grid: a low-resolution pixel of ours estimates the
//! same integral over the same film area as the mean of those 16 reference pixels, and
//! at that scale the Gaussian filter's blur (half a reference pixel) no longer shows.
//! (Nori's Gaussian at the quarter resolution would blur four times wider than the
//! reference: its edges fail this test.) `full_resolution_windows_match_with_noris_filter`
//! compares windows at the references' own resolution, with the scenes' own filter.
//! Then a block t-test (per 16 x 16 block and channel, the mean of the per-pixel
//! differences over its standard error, which includes the reference's noise, as in
//! `image::metrics::block_t_test`; Bonferroni over blocks and scenes) must pass at 1%,
//! and the same render with its lower half darkened by 5% must fail (the lower half of
//! every scene here is lit, noisy geometry, not a constant emitter or background).
//! The standard error gets an allowance of 0.1% of the block's mean added in
//! quadrature, for noise that a few dozen samples per pixel do not show: on
//! sphere_ao_mats the far floor loses about 0.2% of its light to the sphere, one BSDF
//! sample in 500, which 32 samples per pixel mostly miss, so the block looks noise-free
//! at 0.6 while the reference has converged to 0.5989 (ours has too at 512 spp).
//!
//! Two rewrites make the files render what Nori rendered in 2015:
//! - Nori's `lookat` did not normalise its `left` and `up` axes until commit 981dfb2
//!   (2015-08-18, "fixed bug in lookat transform parsing/construction code"); both have
//!   length sin θ, θ the angle between `up` and the view direction, so a 2015 camera's
//!   field of view was narrower by that factor in tan(fov / 2): 4.4% for veach_mi and
//!   odyssey, 1% for sphere, nothing for table (its `up` is perpendicular). wavetrace
//!   reads `lookat` as Nori does since then; here each `<lookat>` becomes the 2015
//!   `<matrix>`. `current_lookat_misses_the_2015_references` shows that veach_mi
//!   fails without it: that zoom was the "4-5% brighter floor".
//! - sphere's files name `../../pa1/plane.obj`, which is `pa1/plane.obj` in our copy
//!   (its SOURCES.txt says so).
//!
//! The photon mapper's `table_pmap` is tested against its reference apart
//! (`photon_mapper_matches_noris_table_reference`), its noise being correlated over the
//! photon radius. Left out: sphere_side (`distantdisk` with `thetaA` = 10, Nori's
//! exercise, not implemented), cbox's `pmap` (no reference in the snapshot), and the
//! `direct_ems` / `direct_mats` variants of veach_mi: emitter sampling on its nearly
//! specular plates and BSDF sampling of its small lights have noise so skewed that
//! neither the 256-spp references nor a render of a few hundred samples have converged
//! in some blocks (their means differ from the `direct_mis` images by up to 8% there),
//! which a t-test cannot judge. cbox's references are not in the snapshot, and bunny
//! has none.
//!
//! What is left (measured at 4 x 512 spp against both table references, which agree
//! with each other there to 0.04%): on table, 40 x 40-pixel blocks along the wine
//! glass's left and right silhouettes are 1-1.7% darker than Nori's, everywhere else
//! within 0.5%. Nori's dielectric and path tracers were course exercises, absent from
//! its public source, so their convention at grazing angles (a shading normal facing
//! away from the ray, say) cannot be read; the difference is below what this test
//! resolves at 32 spp.

mod common;

use std::path::{Path, PathBuf};

use common::{device, downsample, repo};
use wavetrace::image::metrics::student_t_two_sided_p;
use wavetrace::image::Image;
use wavetrace::render::RenderOptions;
use wavetrace::scene::film::{Crop, Filter};

/// Film size divisor.
const K: u32 = 4;
/// Block side of the t-test, in low-resolution pixels.
const BLOCK: u32 = 16;
/// Relative allowance added to every block's standard error (see the module comment).
const ALLOWANCE: f64 = 1e-3;

struct Case {
    /// Scene file, relative to `../shared/scenes/nori`.
    xml: &'static str,
    /// Its reference image, likewise.
    reference: &'static str,
    /// Samples per (low-resolution) pixel of our render.
    spp: u32,
}

const CASES: &[Case] = &[
    Case {
        xml: "veach_mi/veach_mis.xml",
        reference: "veach_mi/ref/veach_mis_128spp.exr",
        spp: 128,
    },
    Case {
        xml: "odyssey/odyssey_ems.xml",
        reference: "odyssey/ref/odyssey_ems_64spp.exr",
        spp: 32,
    },
    Case {
        xml: "odyssey/odyssey_mats.xml",
        reference: "odyssey/ref/odyssey_mats_64spp.exr",
        spp: 32,
    },
    Case {
        xml: "odyssey/odyssey_mis.xml",
        reference: "odyssey/ref/odyssey_mis_32spp.exr",
        spp: 32,
    },
    Case {
        xml: "sphere/sphere_ao_ems.xml",
        reference: "sphere/ref/sphere_ao_ems_256spp.exr",
        spp: 128,
    },
    Case {
        xml: "sphere/sphere_ao_mats.xml",
        reference: "sphere/ref/sphere_ao_mats_256spp.exr",
        spp: 64,
    },
    Case {
        xml: "sphere/sphere_ao_mis.xml",
        reference: "sphere/ref/sphere_ao_mis_128spp.exr",
        spp: 64,
    },
    Case {
        xml: "table/table_path_mis.xml",
        reference: "table/ref/table_path_mis_512spp.exr",
        spp: 32,
    },
];

fn nori_dir() -> PathBuf {
    repo("../shared/scenes/nori")
}

/// Parses "x, y, z" (commas and/or spaces).
fn vec3(s: &str) -> glam::DVec3 {
    let v: Vec<f64> = s
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().expect("a number"))
        .collect();
    assert_eq!(v.len(), 3, "three numbers in {s:?}");
    glam::DVec3::new(v[0], v[1], v[2])
}

/// Nori's `lookat` before commit 981dfb2 (2015-08-18), as a row-major `<matrix>`: the
/// columns are left = normalize(up) x dir and up' = dir x left, neither normalised, so
/// both have length sin θ (θ between `up` and `dir`), then dir and the origin.
fn lookat_2015(origin: &str, target: &str, up: &str) -> String {
    let (o, t, u) = (vec3(origin), vec3(target), vec3(up));
    let dir = (t - o).normalize();
    let left = u.normalize().cross(dir);
    let new_up = dir.cross(left);
    let m = glam::DMat4::from_cols(
        left.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        o.extend(1.0),
    );
    let rows: Vec<String> = (0..4)
        .flat_map(|r| (0..4).map(move |c| (r, c)))
        .map(|(r, c)| format!("{:.9}", m.col(c)[r]))
        .collect();
    format!("<matrix value=\"{}\"/>", rows.join(", "))
}

/// The scene file rewritten for the test: the film divided by [`K`], file names made
/// absolute (`../../pa1/` read as `pa1/`, see the module comment) and, with
/// `era_2015`, every `<lookat>` replaced by the 2015 matrix.
fn rewrite(file: &Path, era_2015: bool) -> String {
    rewrite_scaled(file, era_2015, K)
}

/// [`rewrite`] with the film divided by `k`.
fn rewrite_scaled(file: &Path, era_2015: bool, k: u32) -> String {
    let text =
        std::fs::read_to_string(file).unwrap_or_else(|e| panic!("reading {}: {e}", file.display()));
    let doc = roxmltree::Document::parse(&text).expect("parse the scene");
    let dir = file.parent().expect("scene folder");
    // (byte range, replacement), applied back to front.
    let mut edits: Vec<(std::ops::Range<usize>, String)> = Vec::new();
    for n in doc.descendants().filter(|n| n.is_element()) {
        let name = n.attribute("name");
        let value = n.attribute_node("value");
        match (n.tag_name().name(), name, value) {
            ("lookat", _, _) if era_2015 => edits.push((
                n.range(),
                lookat_2015(
                    n.attribute("origin").expect("origin"),
                    n.attribute("target").expect("target"),
                    n.attribute("up").expect("up"),
                ),
            )),
            ("integer", Some("width" | "height"), Some(v)) => {
                let px: u32 = v.value().parse().expect("film size");
                assert!(px.is_multiple_of(k), "{} divides by {k}", v.value());
                edits.push((v.range_value(), (px / k).to_string()));
            }
            ("string", Some("filename"), Some(v)) => {
                let rel = v.value().replace("../../pa1/", "pa1/");
                edits.push((v.range_value(), dir.join(rel).display().to_string()));
            }
            _ => {}
        }
    }
    edits.sort_by_key(|(r, _)| std::cmp::Reverse(r.start));
    let mut out = text.clone();
    for (range, with) in edits {
        out.replace_range(range, &with);
    }
    out
}

/// The block that disagrees most with the reference: (block column, row, channel, t,
/// Bonferroni-corrected two-sided p over the blocks and channels tested).
struct Worst {
    block: (u32, u32, usize),
    t: f64,
    p_bonferroni: f64,
}

impl std::fmt::Display for Worst {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (x, y, c) = self.block;
        write!(
            f,
            "worst block ({x}, {y}) channel {c}: t = {:.2}, Bonferroni p = {:.2e}",
            self.t, self.p_bonferroni
        )
    }
}

/// Per [`BLOCK`]-sided block and channel, t = mean(d) / sqrt(s² / n + (ALLOWANCE ·
/// mean(reference))²) over the pixel differences d = image - reference, under
/// Student's t with n - 1 degrees of freedom.
fn block_test(img: &Image, reference: &Image) -> Worst {
    block_test_correlated(img, reference, 1.0)
}

/// [`block_test`] with the variance of a block's mean widened by `factor` for
/// correlated pixels (`Filter::block_variance_factor`).
fn block_test_correlated(img: &Image, reference: &Image, factor: f64) -> Worst {
    assert_eq!((img.width, img.height), (reference.width, reference.height));
    let mut worst = Worst {
        block: (0, 0, 0),
        t: 0.0,
        p_bonferroni: 1.0,
    };
    let (mut tests, mut worst_p) = (0usize, 1.0f64);
    for by in 0..img.height.div_ceil(BLOCK) {
        for bx in 0..img.width.div_ceil(BLOCK) {
            let xs = bx * BLOCK..((bx + 1) * BLOCK).min(img.width);
            let ys = by * BLOCK..((by + 1) * BLOCK).min(img.height);
            for c in 0..3 {
                let (mut d, mut r) = (Vec::new(), 0.0);
                for y in ys.clone() {
                    for x in xs.clone() {
                        d.push(img.pixel(x, y)[c] as f64 - reference.pixel(x, y)[c] as f64);
                        r += reference.pixel(x, y)[c] as f64;
                    }
                }
                let n = d.len() as f64;
                if n < 2.0 {
                    continue;
                }
                let mean = d.iter().sum::<f64>() / n;
                let var = d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
                let se = (factor * var / n + (ALLOWANCE * r / n).powi(2))
                    .sqrt()
                    .max(1e-9);
                let t = if mean.is_finite() {
                    mean / se
                } else {
                    f64::INFINITY
                };
                let p = student_t_two_sided_p(t, n - 1.0);
                tests += 1;
                if p < worst_p || tests == 1 {
                    worst_p = p;
                    worst.block = (bx, by, c);
                    worst.t = t;
                }
            }
        }
    }
    worst.p_bonferroni = (worst_p * tests as f64).min(1.0);
    worst
}

/// Renders `case` (its scene rewritten by [`rewrite`]) and reads its reference at the
/// same low resolution.
fn render_case(device: &wavetrace::gpu::Device, case: &Case, era_2015: bool) -> (Image, Image) {
    let file = nori_dir().join(case.xml);
    let xml = rewrite(&file, era_2015);
    let name = case.xml.replace('/', "-");
    let path = common::temp_file("nori_scenes", &name, &xml);
    let mut scene = common::load(&path);
    assert_eq!(scene.film.filter, Filter::DEFAULT, "Nori's default filter");
    scene.film.filter = Filter::Box;
    let img = common::render(device, &scene, &RenderOptions::default(), case.spp);
    let reference = Image::read_exr(nori_dir().join(case.reference))
        .unwrap_or_else(|e| panic!("reading {}: {e}", case.reference));
    (img, downsample(&reference, K))
}

/// At the references' own resolution, windows of veach_mi and odyssey rendered with
/// the scenes' own filter (none named: Nori's Gaussian, radius 2, stddev 0.5) agree
/// with the same windows of Nori's references by the block t-test (16 x 16 blocks,
/// the standard error widened for the filter's correlated pixels, and the allowance
/// above), and have a lower MSE against them than the same windows rendered with a
/// box filter. At these sample counts part of that is the Gaussian's lower noise;
/// measured at 1024 spp, where the MSE is mostly the references' own noise, the box
/// still adds 2.6e-5 to veach_mi's 1.18e-4 and 0.45e-5 to odyssey's 4.56e-5: the
/// blur at every edge that it lacks and Nori's images have.
#[test]
fn full_resolution_windows_match_with_noris_filter() {
    let device = device();
    for (case, window) in [
        (
            &CASES[0],
            Crop {
                x: 320,
                y: 160,
                width: 128,
                height: 96,
            },
        ),
        (
            &CASES[3],
            Crop {
                x: 320,
                y: 176,
                width: 128,
                height: 96,
            },
        ),
    ] {
        let file = nori_dir().join(case.xml);
        let xml = rewrite_scaled(&file, true, 1);
        let name = format!("full-{}", case.xml.replace('/', "-"));
        let mut scene = common::load(&common::temp_file("nori_scenes", &name, &xml));
        assert_eq!(scene.film.filter, Filter::DEFAULT);
        scene.film.crop = Some(window);
        let full = Image::read_exr(nori_dir().join(case.reference)).expect("reference");
        let mut reference = Image::new(window.width, window.height);
        for y in 0..window.height {
            for x in 0..window.width {
                reference.set_pixel(x, y, full.pixel(window.x + x, window.y + y));
            }
        }
        let gaussian = common::render(&device, &scene, &RenderOptions::default(), case.spp);
        scene.film.filter = Filter::Box;
        let boxed = common::render(&device, &scene, &RenderOptions::default(), case.spp);
        let mse = |img: &Image| wavetrace::image::metrics::mse(img, &reference).expect("mse");
        let test = block_test_correlated(
            &gaussian,
            &reference,
            Filter::DEFAULT.block_variance_factor(BLOCK),
        );
        println!(
            "{} window {}x{} at ({}, {}), {} spp: MSE against Nori's reference: Gaussian {:.4e}, box {:.4e}; {test}",
            case.xml, window.width, window.height, window.x, window.y, case.spp, mse(&gaussian), mse(&boxed)
        );
        assert!(test.p_bonferroni >= 0.01, "{}: {test}", case.xml);
        assert!(
            mse(&gaussian) < mse(&boxed),
            "{}: the box filter fits Nori's reference better",
            case.xml
        );
    }
}

/// `img` with its lower half (rows from height / 2 down) scaled by `f`.
fn lower_half_scaled(img: &Image, f: f32) -> Image {
    let mut out = img.clone();
    let start = 3 * (img.height / 2 * img.width) as usize;
    out.rgb[start..].iter_mut().for_each(|v| *v *= f);
    out
}

#[test]
fn nori_scenes_match_noris_references() {
    let device = device();
    let level = 0.01 / CASES.len() as f64;
    let mut failures = Vec::new();
    for case in CASES {
        let start = std::time::Instant::now();
        let (img, reference) = render_case(&device, case, true);
        let test = block_test(&img, &reference);
        let ratio = common::mean(&img) / common::mean(&reference);
        let biased = block_test(&lower_half_scaled(&img, 0.95), &reference);
        println!(
            "{} ({}x{}, {} spp, {:.1} s): mean ratio {ratio:.4}; {test}; lower half x0.95: t = {:.1}",
            case.xml,
            img.width,
            img.height,
            case.spp,
            start.elapsed().as_secs_f64(),
            biased.t
        );
        if test.p_bonferroni < level {
            failures.push(format!("{}: {test}", case.xml));
        }
        if biased.p_bonferroni >= level {
            failures.push(format!("{}: cannot see a 5% bias: {biased}", case.xml));
        }
    }
    assert!(failures.is_empty(), "failed: {failures:#?}");
}

/// The cause of the "brighter floor" on veach_mi: read with today's `lookat`, the
/// scene is seen 4.4% wider than the 2015 references, and the test above fails.
#[test]
fn current_lookat_misses_the_2015_references() {
    let device = device();
    let case = &CASES[0];
    let (img, reference) = render_case(&device, case, false);
    let test = block_test(&img, &reference);
    println!("{} with today's lookat: {test}", case.xml);
    assert!(test.p_bonferroni < 0.01 / CASES.len() as f64, "{test}");
}

#[test]
fn lookat_2015_narrows_the_view_by_sin_theta() {
    // veach_mi: up = y, dir = (0, -7.5, -25) / |.|, so sin θ = 25 / sqrt(7.5² + 25²).
    let m = lookat_2015("0, 6, 27.5", "0, -1.5, 2.5", "0, 1, 0");
    let v: Vec<f64> = m
        .trim_start_matches("<matrix value=\"")
        .trim_end_matches("\"/>")
        .split(", ")
        .map(|s| s.parse().expect("a number"))
        .collect();
    let left_len = (v[0] * v[0] + v[4] * v[4] + v[8] * v[8]).sqrt();
    let up_len = (v[1] * v[1] + v[5] * v[5] + v[9] * v[9]).sqrt();
    let sin = 25.0 / (7.5f64 * 7.5 + 25.0 * 25.0).sqrt();
    assert!((left_len - sin).abs() < 1e-8 && (up_len - sin).abs() < 1e-8);
    assert!(
        (1.0 / sin - 1.0440).abs() < 1e-3,
        "a {:.4}x zoom",
        1.0 / sin
    );
    assert_eq!((v[3], v[7], v[11]), (0.0, 6.0, 27.5));
}

/// Independent renders of the photon mapper test (see
/// `photon_mapper_matches_noris_table_reference`).
const PMAP_REPLICAS: u32 = 24;
/// Photons each of them stores.
const PMAP_PHOTONS: u32 = 40_000;
/// Samples per low-resolution pixel of each.
const PMAP_SPP: u32 = 2;
/// Photons Nori's reference stored (`table_pmap_256spp_5Mp.exr`).
const PMAP_REFERENCE_PHOTONS: f64 = 5e6;
/// Block side of the photon mapper's test, in low-resolution pixels.
const PMAP_BLOCK: u32 = 40;

/// Nori's photon mapper on `table/table_pmap.xml` (radius 1, 5 M photons, 256 spp)
/// against Nori's reference, by the block test of this suite at a quarter of the
/// resolution, with the changes the photon map's noise asks for.
///
/// The radius stays the scene's: the density estimate's expectation is the irradiance
/// blurred over the gather disk, which depends on the radius (a world-space length,
/// the same at any film size) and not on the photon count. The photon count drops to
/// 24 independent renders (seeds 0-23) of 40,000 photons at 2 spp each, whose mean
/// estimates the same image as one of 960,000 photons. A photon map's error is not
/// independent from pixel to pixel: every pixel within the radius of a photon shares
/// it, so a block's standard error is not its pixels' spread over √n (blocks of 16 x 16
/// low-resolution pixels hold a few dozen disks of the radius, not 256 independent
/// values). Each block's standard error is instead taken from the spread of its mean
/// over the 24 renders (23 degrees of freedom, Student's t), plus the reference's own
/// photon noise, the same estimator's with 5 M photons: that spread times 40,000 / 5 M.
/// Blocks are 40 x 40 low-resolution pixels (the film's 200 columns hold five; 5 x 5
/// disks of the radius and more on the table), and the upper half, the lower half and
/// the whole image are tested too (Bonferroni over all): a block's standard error is a
/// few % of its mean, too much for any block alone to see the 5%-darkened lower half,
/// which the half's mean sees. The darkened half must fail, and the 0.1% allowance of
/// the suite applies.
///
/// Why these numbers (measured over 72 renders, seeds 0-71, as 3 disjoint sets of 24
/// and 150 random ones): the lower half's mean varies by 3.1% (relative standard
/// deviation) from render to render, so with 12 renders the darkened half's expected
/// t was about 5.6 against a bound of 6.0 (11 degrees of freedom, 114 tests), and 3 of
/// 6 disjoint sets of 12 missed it; with 24 its t is 6.4-7.0 against a bound of 4.5
/// and no set missed it. A block's mean over 40,000 photons is skewed (a few renders
/// put a bright cluster of photons in it), which makes its t too large on the side of
/// the many dim renders: blocks of 32 left strips 8 pixels wide at the right edge,
/// whose worst t reached -4.9 (over the bound at 24 renders, and -6.1 for one set of
/// 12); blocks of 40 pixels (69 tests) keep the worst unbiased t at 2.5 (median of
/// the random sets), 3.7 (99th percentile). Two samples per pixel instead of four
/// change none of these numbers by more than 0.6 (the photons' noise dominates every
/// region) and keep the test at about 30 s.
#[test]
fn photon_mapper_matches_noris_table_reference() {
    let device = device();
    let file = nori_dir().join("table/table_pmap.xml");
    let xml = rewrite(&file, true).replace(
        "name=\"photonCount\" value=\"5000000\"",
        &format!("name=\"photonCount\" value=\"{PMAP_PHOTONS}\""),
    );
    assert!(
        xml.contains(&format!("value=\"{PMAP_PHOTONS}\"")),
        "photonCount rewritten"
    );
    let path = common::temp_file("nori_scenes", "table-pmap.xml", &xml);
    let scene = common::load(&path);
    let reference = downsample(
        &Image::read_exr(nori_dir().join("table/ref/table_pmap_256spp_5Mp.exr"))
            .expect("table_pmap reference"),
        K,
    );
    let start = std::time::Instant::now();
    let mut r = wavetrace::render::Renderer::new(&device, &scene, &RenderOptions::default())
        .expect("photon mapper");
    let replicas: Vec<Image> = (0..PMAP_REPLICAS)
        .map(|seed| {
            r.set_seed(seed).expect("seed");
            r.render(PMAP_SPP, &mut |_, _| {}).expect("render").0
        })
        .collect();
    let mut mean = Image::new(reference.width, reference.height);
    for (k, v) in mean.rgb.iter_mut().enumerate() {
        *v = replicas.iter().map(|img| img.rgb[k]).sum::<f32>() / PMAP_REPLICAS as f32;
    }
    let test = |scale: f32| replica_block_test(&replicas, &reference, scale);
    let (worst, tests) = test(1.0);
    let (biased, _) = test(0.95);
    let ratio = common::mean(&mean) / common::mean(&reference);
    println!(
        "table_pmap ({}x{}, {PMAP_REPLICAS} x {PMAP_PHOTONS} photons at {PMAP_SPP} spp, {:.1} s): \
         mean ratio {ratio:.4}; {tests} block tests; worst block {:?} t = {:.2}, Bonferroni p = {:.2e}; \
         lower half x0.95: worst t = {:.2}, p = {:.2e}",
        mean.width,
        mean.height,
        start.elapsed().as_secs_f64(),
        worst.block,
        worst.t,
        worst.p_bonferroni,
        biased.t,
        biased.p_bonferroni
    );
    assert!(
        worst.p_bonferroni >= 0.01,
        "disagrees with Nori's reference: {worst}"
    );
    assert!(biased.p_bonferroni < 0.01, "cannot see a 5% bias: {biased}");
}

/// The block test of [`block_test`] for the mean of independent `replicas`, each
/// region's standard error taken from the spread of the replicas' region means (see
/// `photon_mapper_matches_noris_table_reference`); `lower_scale` scales the lower half
/// of every replica (1: as rendered). The regions are the blocks of [`PMAP_BLOCK`]
/// pixels, the upper and the lower half, and the whole image, each per channel.
/// Returns the worst region (block (7, 7) is the upper half, (8, 8) the lower one,
/// (9, 9) the whole image) and the number of tests.
fn replica_block_test(replicas: &[Image], reference: &Image, lower_scale: f32) -> (Worst, usize) {
    let (w, h) = (reference.width, reference.height);
    let n = replicas.len() as f64;
    let value = |img: &Image, x: u32, y: u32, c: usize| {
        let f = if y >= h / 2 { lower_scale } else { 1.0 };
        (img.pixel(x, y)[c] * f) as f64
    };
    // (id, columns, rows)
    type Region = ((u32, u32), std::ops::Range<u32>, std::ops::Range<u32>);
    let mut regions: Vec<Region> = Vec::new();
    for by in 0..h.div_ceil(PMAP_BLOCK) {
        for bx in 0..w.div_ceil(PMAP_BLOCK) {
            let xs = bx * PMAP_BLOCK..((bx + 1) * PMAP_BLOCK).min(w);
            let ys = by * PMAP_BLOCK..((by + 1) * PMAP_BLOCK).min(h);
            regions.push(((bx, by), xs, ys));
        }
    }
    regions.push(((7, 7), 0..w, 0..h / 2));
    regions.push(((8, 8), 0..w, h / 2..h));
    regions.push(((9, 9), 0..w, 0..h));
    let mut worst = Worst {
        block: (0, 0, 0),
        t: 0.0,
        p_bonferroni: 1.0,
    };
    let (mut tests, mut worst_p) = (0usize, 1.0f64);
    for (id, xs, ys) in &regions {
        let pixels = (xs.len() * ys.len()) as f64;
        for c in 0..3 {
            let region_mean = |img: &Image, f: &dyn Fn(&Image, u32, u32, usize) -> f64| {
                let mut s = 0.0;
                for y in ys.clone() {
                    for x in xs.clone() {
                        s += f(img, x, y, c);
                    }
                }
                s / pixels
            };
            let means: Vec<f64> = replicas
                .iter()
                .map(|img| region_mean(img, &value))
                .collect();
            let m = means.iter().sum::<f64>() / n;
            let var = means.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0);
            let r = region_mean(reference, &|img, x, y, c| img.pixel(x, y)[c] as f64);
            if var == 0.0 && r == 0.0 {
                continue; // nothing there (background)
            }
            let reference_var = var * PMAP_PHOTONS as f64 / PMAP_REFERENCE_PHOTONS;
            let se = (var / n + reference_var + (ALLOWANCE * r).powi(2))
                .sqrt()
                .max(1e-9);
            let t = (m - r) / se;
            let p = student_t_two_sided_p(t, n - 1.0);
            tests += 1;
            if p < worst_p || tests == 1 {
                worst_p = p;
                worst.block = (id.0, id.1, c);
                worst.t = t;
            }
        }
    }
    worst.p_bonferroni = (worst_p * tests as f64).min(1.0);
    (worst, tests)
}
