//! Nori's own statistical tests (`../shared/scenes/nori/tests`, `<test type="ttest">`
//! files: scenes with known answers, each rendered by one of the direct-lighting or
//! path-tracing integrators): mesh lights seen by `direct_ems`, `direct_mats` and
//! `direct_mis`, the same under `path_mats` and `path_mis`, and furnaces whose answer
//! is the geometric series 1 / (1 - albedo).
//!
//! Every scene looks along one direction (a 1 x 1 film with a field of view of 1e-6
//! degrees, or a furnace where every direction sees the same radiance). The film is
//! widened here to 32 x 32 pixels that all see that direction, with a box filter, so
//! one render gives 1024 independent estimates (Nori's default Gaussian would share
//! each sample among 25 pixels and make them correlated); a one-sample t-test of their mean against Nori's
//! reference runs for every scene, Bonferroni-corrected over all of them at 1%.
//! `test-distant.xml` is left out: its `distantdisk` light is Nori's exercise, not a
//! Mitsuba or Nori plugin wavetrace implements.

mod common;

use std::path::Path;

use common::{device, repo};
use wavetrace::image::metrics::ln_gamma;
use wavetrace::render::RenderOptions;

const FILES: &[&str] = &[
    "../shared/scenes/nori/tests/pa3_tests/test-mesh.xml",
    "../shared/scenes/nori/tests/pa3_tests/test-mesh-furnace.xml",
    "../shared/scenes/nori/tests/pa4_tests/test-direct.xml",
    "../shared/scenes/nori/tests/pa4_tests/test-furnace.xml",
];
/// Scenes in FILES, for the Bonferroni correction.
const SCENES: usize = 15 + 6 + 10 + 4;
const SPP: u32 = 64;
const SIDE: u32 = 32;

/// Two-sided p-value of Student's t with `dof` degrees of freedom: the regularized
/// incomplete beta I_{dof/(dof+t²)}(dof/2, 1/2), by its continued fraction (Press et
/// al., "Numerical Recipes", 3rd ed., sec. 6.4).
fn t_p_value(t: f64, dof: f64) -> f64 {
    let x = dof / (dof + t * t);
    let (a, b) = (0.5 * dof, 0.5);
    let front =
        (ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln()).exp();
    // Lentz's continued fraction for I_x(a, b), valid for x < (a + 1) / (a + b + 2).
    let cf = |a: f64, b: f64, x: f64| {
        let tiny = 1e-300;
        let (mut c, mut d) = (1.0, 1.0 - (a + b) * x / (a + 1.0));
        d = if d.abs() < tiny { tiny } else { d };
        d = 1.0 / d;
        let mut h = d;
        for m in 1..300 {
            let m = m as f64;
            for k in 0..2 {
                let num = if k == 0 {
                    m * (b - m) * x / ((a + 2.0 * m - 1.0) * (a + 2.0 * m))
                } else {
                    -(a + m) * (a + b + m) * x / ((a + 2.0 * m) * (a + 2.0 * m + 1.0))
                };
                d = 1.0 + num * d;
                d = if d.abs() < tiny { tiny } else { d };
                c = 1.0 + num / c;
                c = if c.abs() < tiny { tiny } else { c };
                d = 1.0 / d;
                h *= d * c;
            }
        }
        h
    };
    if x < (a + 1.0) / (a + b + 2.0) {
        front * cf(a, b, x) / a
    } else {
        1.0 - front * cf(b, a, 1.0 - x) / b
    }
}

/// The `<scene>` elements of a Nori test file and its reference values.
fn scenes_of(file: &Path) -> (Vec<String>, Vec<f64>) {
    let text = std::fs::read_to_string(file).expect("read the test file");
    let doc = roxmltree::Document::parse(&text).expect("parse the test file");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "test");
    let references: Vec<f64> = root
        .children()
        .find(|n| n.attribute("name") == Some("references"))
        .and_then(|n| n.attribute("value"))
        .expect("references")
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().expect("a reference value"))
        .collect();
    let dir = file.parent().expect("test folder");
    let scenes = root
        .children()
        .filter(|n| n.has_tag_name("scene"))
        .map(|n| {
            let mut xml = text[n.range()].to_string();
            // Files named relative to the test file; a wider film of the same view.
            for (from, to) in [
                (
                    "<integer name=\"width\" value=\"1\"/>",
                    format!("<integer name=\"width\" value=\"{SIDE}\"/>"),
                ),
                (
                    "<integer name=\"height\" value=\"1\"/>",
                    format!("<integer name=\"height\" value=\"{SIDE}\"/>"),
                ),
            ] {
                xml = xml.replace(from, &to);
            }
            let key = "<string name=\"filename\" value=\"";
            let mut out = String::new();
            let mut rest = xml.as_str();
            while let Some(i) = rest.find(key) {
                let start = i + key.len();
                let end = start + rest[start..].find('"').expect("closing quote");
                out.push_str(&rest[..start]);
                out.push_str(&dir.join(&rest[start..end]).display().to_string());
                rest = &rest[end..];
            }
            out.push_str(rest);
            out
        })
        .collect();
    (scenes, references)
}

#[test]
fn noris_statistical_tests_pass() {
    let device = device();
    let level = 0.01 / SCENES as f64;
    let mut count = 0;
    let mut failures = Vec::new();
    for file in FILES {
        let (scenes, references) = scenes_of(&repo(file));
        assert_eq!(scenes.len(), references.len(), "{file}");
        for (i, (xml, &expected)) in scenes.iter().zip(&references).enumerate() {
            let name = format!("nori-{count}.xml");
            let path = common::temp_file("nori_tests", &name, xml);
            let mut scene = common::load(&path);
            assert!(scene.camera.width == SIDE || scene.camera.fov_x_deg > 1.0);
            scene.film.filter = wavetrace::scene::film::Filter::Box;
            let integrator = scene.integrator.name.clone();
            let img = common::render(&device, &scene, &RenderOptions::default(), SPP);
            // Channel means per pixel: the scenes are grey.
            let values: Vec<f64> = (0..img.height)
                .flat_map(|y| (0..img.width).map(move |x| (x, y)))
                .map(|(x, y)| {
                    let p = img.pixel(x, y);
                    (p[0] as f64 + p[1] as f64 + p[2] as f64) / 3.0
                })
                .collect();
            let n = values.len() as f64;
            let mean = values.iter().sum::<f64>() / n;
            let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
            let se = (var / n).sqrt();
            let t = if se > 0.0 {
                (mean - expected) / se
            } else if (mean - expected).abs() <= 1e-5 * expected.abs() {
                0.0
            } else {
                f64::INFINITY
            };
            let p = if t.is_finite() {
                t_p_value(t, n - 1.0)
            } else {
                0.0
            };
            println!(
                "{file} #{i} ({integrator}): {mean:.5} vs {expected:.5} (se {se:.2e}), t = {t:.2}, p = {p:.3e}"
            );
            if p < level {
                failures.push(format!(
                    "{file} #{i} ({integrator}): {mean} vs {expected}, p = {p:.2e}"
                ));
            }
            count += 1;
        }
    }
    assert_eq!(count, SCENES);
    assert!(failures.is_empty(), "failed: {failures:#?}");
}

#[test]
fn the_t_test_p_value_is_right() {
    // Two-sided p of Student's t: tables give t = 2.228 at p = 0.05 for 10 degrees of
    // freedom and t = 2.576 at p = 0.01 in the normal limit.
    assert!((t_p_value(2.228, 10.0) - 0.05).abs() < 2e-4);
    assert!((t_p_value(2.576, 1e6) - 0.01).abs() < 2e-4);
    assert!((t_p_value(0.0, 5.0) - 1.0).abs() < 1e-9);
}
