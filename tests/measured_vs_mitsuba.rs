//! `measured` (RGL `.bsdf` files) against Mitsuba 3 itself, on the two test files
//! tests/data/measured_{iso,aniso}.bsdf (`tools/make_measured_bsdf.py`: GGX conductors
//! tabulated in the paper's parameterization; no RGL measurement ships with wavetrace):
//!
//! - the GPU's bsdf_eval and bsdf_pdf at the (wo, wi) pairs of
//!   tests/data/measured_values.json, which Mitsuba 3.9.1 computed (`scalar_rgb`;
//!   `python3 tools/mitsuba_measured_values.py > tests/data/measured_values.json`);
//! - bsdf_sample against bsdf_pdf by chi-square (`wavetrace warptest measured`), and
//!   a deliberately wrong pdf (the luminance warp's factor left out) rejected;
//! - a scene with both files (scenes/measured/measured.xml) against Mitsuba's render;
//! - energy: the mean sample weight against the integral of eval;
//! - bad files: errors naming the scene file, line, parameter and the fault.

mod common;

use common::mitsuba_values::{compare_eval_pdf, read_cases, Tolerance};
use common::stats::{bsdf_probe, dir};
use common::{assert_matches_reference_at, device, repo};
use wavetrace::image::Image;
use wavetrace::render::RenderOptions;
use wavetrace::scene::bsdf::measured::record_with_tables;
use wavetrace::scene::bsdf::Bsdf;
use wavetrace::warptest::{chi2, expected_counts, test_bsdf, Axis, Grid, SphereGrid};

/// The scene of one `measured` BSDF naming `file` (relative to the repository).
fn measured(file: &str, test: &str) -> Bsdf {
    let xml = format!(
        "<scene version=\"3.0.0\"><sensor type=\"perspective\"/><bsdf type=\"measured\" id=\"m\">\
         <string name=\"filename\" value=\"{}\"/></bsdf></scene>",
        repo(file).display()
    );
    let scene = common::load(&common::temp_file(test, "bsdf.xml", &xml));
    scene.bsdfs[0].clone()
}

/// Tolerance: both sides interpolate the same single-precision tables along the
/// same steps (the VNDF warp's inversion, bilinear and linear interpolation), the
/// angles by atan2 to a few ulps (measured.glsl's own: lavapipe's atan and asin are
/// off by ~1e-4 rad, which σ's slope near the horizon turned into 0.6% errors). The
/// values agree to 1e-5; |GPU - Mitsuba| <= 1e-4 |Mitsuba| + 1e-6 max leaves room for
/// other drivers' rounding while a table read one cell off or a mirrored azimuth
/// (differences of percents) fails by a hundred times.
#[test]
fn eval_and_pdf_match_mitsuba() {
    let cases = read_cases(
        "tests/data/measured_values.json",
        "python3 tools/mitsuba_measured_values.py",
    );
    let mut probe = bsdf_probe();
    let mut checked = 0;
    for (i, case) in cases.iter().enumerate() {
        let file = case.params["mitsuba"]["filename"]
            .as_str()
            .expect("filename");
        let (rec, tables) = record_with_tables(&measured(file, &format!("measured_values{i}")));
        probe.set_tables(&tables);
        let (scale, pdf_scale) = (case.eval_scale(), case.pdf_scale());
        let a = compare_eval_pdf(
            &probe,
            &rec,
            &case.pairs,
            [1e-3 * scale, 1e-3 * pdf_scale],
            |_| {
                [
                    Tolerance::new(1e-4, 1e-6 * scale),
                    Tolerance::new(1e-4, 1e-6 * pdf_scale),
                ]
            },
        );
        a.print_and_assert(file, case.pairs.len());
        checked += case.pairs.len();
    }
    assert!(checked >= 400, "{checked} pairs");
}

/// Chi-square tests in this file (Šidák correction).
const TESTS_IN_FILE: usize = 8;
const N: u32 = 400_000;

/// `wavetrace warptest measured`'s test for several incident directions of both
/// files: the samples against bsdf_pdf, sample's pdf and weight against eval / pdf.
#[test]
fn sampling_matches_the_pdf() {
    let mut probe = bsdf_probe();
    let cases = [
        ("tests/data/measured_iso.bsdf", dir(30.0, 20.0)),
        ("tests/data/measured_iso.bsdf", dir(70.0, -130.0)),
        ("tests/data/measured_aniso.bsdf", dir(10.0, 45.0)),
        ("tests/data/measured_aniso.bsdf", dir(45.0, 100.0)),
        ("tests/data/measured_aniso.bsdf", dir(65.0, -60.0)),
        ("tests/data/measured_aniso.bsdf", dir(50.0, 200.0)),
    ];
    for (i, (file, wo)) in cases.into_iter().enumerate() {
        let bsdf = measured(file, &format!("measured_chi2_{i}"));
        let (rec, tables) = record_with_tables(&bsdf);
        probe.set_tables(&tables);
        let name = format!("{file}, wo = {wo:.2}");
        let (outcome, samples) =
            test_bsdf(&probe, &rec, wo, Axis::for_bsdf(&bsdf), N, 7 + i as u32)
                .expect("bsdf kernel");
        let mut bad = 0;
        for s in samples.iter().filter(|s| s.flags != 0) {
            let w = s.eval / s.pdf_eval;
            let rel = |a: f32, b: f32| (a - b).abs() <= 2e-3 * a.abs().max(b.abs()) + 1e-6;
            if !(rel(s.pdf, s.pdf_eval) && rel(s.weight.x, w.x) && rel(s.weight.y, w.y)) {
                bad += 1;
            }
        }
        let absorbed = samples.iter().filter(|s| s.flags == 0).count();
        println!(
            "{name}: ∫pdf = {:.4}, absorbed {absorbed}, {bad} samples off eval/pdf, p = {:.3}",
            outcome.pdf_integral, outcome.chi2.p_value
        );
        // The inversion of the VNDF warp (eval, pdf) and the warp itself (sample) agree
        // to f32 rounding except where a sample lands on a cell edge of the tables.
        assert!(
            bad * 200 <= samples.len(),
            "{name}: {bad} samples off eval/pdf"
        );
        assert!(
            (outcome.pdf_integral + absorbed as f64 / N as f64 - 1.0).abs() < 0.02,
            "{name}: ∫pdf = {}",
            outcome.pdf_integral
        );
        common::stats::assert_outcome(&name, &outcome, 0.01, TESTS_IN_FILE);
    }
}

/// The control: the samples of the anisotropic file against a pdf that forgets the
/// luminance warp's factor (its density set to 1) must be rejected.
#[test]
fn a_wrong_pdf_is_rejected() {
    let mut probe = bsdf_probe();
    let bsdf = measured("tests/data/measured_aniso.bsdf", "measured_wrong_pdf");
    let (rec, tables) = record_with_tables(&bsdf);
    probe.set_tables(&tables);
    let wo = dir(45.0, 100.0);
    let samples = probe.sample(&rec, wo, N, 3).expect("bsdf kernel");
    let Bsdf::Measured(m) = &bsdf else {
        panic!("{bsdf:?}")
    };
    let mut wrong = tables.clone();
    let lum = m.data.words()[19].to_bits() as usize;
    let n = m.data.luminance.density.data.len();
    wrong[lum..lum + n].iter_mut().for_each(|v| *v = 1.0);
    probe.set_tables(&wrong);
    let grid = Grid::Sphere(SphereGrid::new(Axis::for_bsdf(&bsdf).direction(wo), 32, 24));
    let (expected, _) = expected_counts(&grid, N as usize, |dirs| {
        Ok(probe
            .eval(&rec, wo, dirs)?
            .iter()
            .map(|e| e.1 as f64)
            .collect())
    })
    .expect("bsdf kernel");
    let (observed, _) = grid.histogram(samples.iter().filter(|s| s.flags != 0).map(|s| s.wi));
    let p = chi2(&observed, &expected).p_value;
    assert!(
        p < 1e-12,
        "a pdf without the luminance factor passed: p = {p}"
    );
}

#[test]
fn scene_renders_as_mitsuba() {
    let scene = common::load_with(&repo("scenes/measured/measured.xml"), &[("res", "48")]);
    let reference = Image::read_exr(repo("tests/data/measured_scene_ref.exr"))
        .expect("tests/data/measured_scene_ref.exr");
    let img = common::render(&device(), &scene, &RenderOptions::default(), 512);
    assert_eq!(img.non_finite_count(), 0);
    assert_matches_reference_at(&img, &reference, "measured scene, path, 512 spp", 0.01);
}

/// Bad files and parameters: each error names the scene file, the line, the
/// parameter and what is wrong with the file.
#[test]
fn bad_files_are_clear_errors() {
    let dir = std::env::temp_dir().join("wavetrace_measured_bad_files");
    std::fs::create_dir_all(&dir).expect("temp dir");
    let good = std::fs::read(repo("tests/data/measured_iso.bsdf")).expect("iso");
    let write = |name: &str, bytes: &[u8]| {
        std::fs::write(dir.join(name), bytes).expect("write");
        name.to_string()
    };
    let cases = [
        (
            write("cut.bsdf", &good[..good.len() / 2]),
            "truncated tensor file",
        ),
        (
            write("png.bsdf", b"\x89PNG\r\n\x1a\n not at all a tensor"),
            "not a tensor file",
        ),
        (write("empty.bsdf", b""), "not a tensor file"),
        ("missing.bsdf".to_string(), "not found"),
    ];
    for (file, want) in cases {
        let scene = dir.join("scene.xml");
        std::fs::write(
            &scene,
            format!(
                "<scene version=\"3.0.0\">\n<bsdf type=\"measured\">\n<string name=\"filename\" value=\"{file}\"/>\n</bsdf>\n</scene>"
            ),
        )
        .expect("write");
        let err = wavetrace::scene::load(&scene, &[])
            .expect_err("a bad file")
            .to_string();
        assert!(
            err.contains("scene.xml:3") && err.contains("filename") && err.contains(&file),
            "{file}: {err}"
        );
        assert!(err.contains(want), "{file}: {err}");
    }
}

/// Energy: the mean sample weight (bsdf_sample) equals ∫ bsdf_eval dω over the
/// hemisphere (a 256 x 512 midpoint rule in (cos θ, φ)), the albedo Mitsuba's eval
/// gives (it matches Mitsuba's to 1e-5), and it stays below 1 (a conductor).
#[test]
fn sampled_albedo_matches_the_integral_of_eval() {
    let mut probe = bsdf_probe();
    for (file, wo) in [
        ("tests/data/measured_iso.bsdf", dir(40.0, 30.0)),
        ("tests/data/measured_aniso.bsdf", dir(60.0, 150.0)),
    ] {
        let bsdf = measured(file, "measured_albedo");
        let (rec, tables) = record_with_tables(&bsdf);
        probe.set_tables(&tables);
        let (nt, np) = (256, 512);
        let dirs: Vec<[f32; 4]> = (0..nt * np)
            .map(|k| {
                let mu = ((k / np) as f32 + 0.5) / nt as f32;
                let phi = ((k % np) as f32 + 0.5) / np as f32 * std::f32::consts::TAU;
                let s = (1.0 - mu * mu).sqrt();
                [s * phi.cos(), s * phi.sin(), mu, 0.0]
            })
            .collect();
        let cell = std::f64::consts::TAU / (nt * np) as f64;
        let integral = probe
            .eval(&rec, wo, &dirs)
            .expect("bsdf kernel")
            .iter()
            .fold(glam::DVec3::ZERO, |a, e| a + e.0.as_dvec3() * cell);
        let samples = probe.sample(&rec, wo, N, 11).expect("bsdf kernel");
        let n = samples.len() as f64;
        let mean = samples
            .iter()
            .fold(glam::DVec3::ZERO, |a, s| a + s.weight.as_dvec3() / n);
        let var = samples
            .iter()
            .fold(0.0, |a, s| a + (s.weight.x as f64 - mean.x).powi(2) / n);
        let sigma = (var / n).sqrt();
        println!("{file}, wo = {wo:.2}: sampled {mean:.4}, ∫ eval {integral:.4}, σ {sigma:.1e}");
        assert!(integral.max_element() < 1.0, "{file}: albedo {integral}");
        // 5 σ of the estimate, and 0.5% for the quadrature of a lobe of α 0.15.
        assert!(
            (mean.x - integral.x).abs() < 5.0 * sigma + 5e-3 * integral.x,
            "{file}, wo = {wo}: sampled albedo {mean}, ∫ eval {integral}"
        );
    }
}
