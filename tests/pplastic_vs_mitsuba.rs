//! `pplastic` against Mitsuba 3 itself: the GPU's bsdf_eval and bsdf_pdf at the
//! (wo, wi) pairs and parameters of tests/data/pplastic_values.json, whose values
//! Mitsuba 3.9.1 computed (`scalar_rgb`, single precision;
//! `python3 tools/mitsuba_bsdf_values.py > tests/data/pplastic_values.json`).
//!
//! Tolerance from f32 precision: both sides evaluate the same formula in single
//! precision with different operation orders, a few dozen roundings of ε = 2⁻²⁴
//! each; GLSL allows `exp` an error of (3 + 2|x|) ulp, and Beckmann's
//! D = exp(-tan²θm / α²) / ... carries its argument's relative error times x =
//! tan²θm / α². So |GPU - Mitsuba| <= (64 + 4 min(x, 50)) ε |Mitsuba| + 1e-7 max(eval) (the last
//! for terms that cancel to nothing, e.g. the specular lobe far from the mirror).
//!
//! And a scene rendered by both: two pplastic spheres under a constant sky and an
//! area light (tests/data/pplastic_spheres.xml), against Mitsuba's render
//! (`python3 tools/mitsuba_ref.py tests/data/pplastic_spheres.xml -o
//! tests/data/pplastic_spheres_ref.exr --spp 16384 --variant scalar_rgb`) within noise.

mod common;

use common::mitsuba_values::{num, v3, EPS};
use common::stats::bsdf_probe;
use common::{assert_matches_reference_at, device, repo};
use glam::Vec3;
use serde_json::Value;
use wavetrace::gpu::layout::BsdfRecord;
use wavetrace::image::Image;
use wavetrace::render::RenderOptions;
use wavetrace::scene::bsdf::{Bsdf, Distribution, PPlastic};

/// The exponent of Beckmann's D at the half vector (0 for GGX, whose D is rational).
fn exponent(b: &PPlastic, wo: Vec3, wi: Vec3) -> f64 {
    let m = (wo + wi).normalize();
    if b.distribution != Distribution::Beckmann || m.z <= 0.0 {
        return 0.0;
    }
    let (x, y, z) = (m.x as f64, m.y as f64, m.z as f64);
    let (au, av) = (b.alpha_u as f64, b.alpha_v as f64);
    ((x / au).powi(2) + (y / av).powi(2)) / (z * z)
}

#[test]
fn eval_and_pdf_match_mitsuba() {
    let text = std::fs::read_to_string(repo("tests/data/pplastic_values.json"))
        .expect("tests/data/pplastic_values.json (python3 tools/mitsuba_bsdf_values.py)");
    let data: Value = serde_json::from_str(&text).expect("JSON");
    let probe = bsdf_probe();
    let mut checked = 0;
    for case in data["cases"].as_array().expect("cases") {
        let name = case["name"].as_str().expect("name");
        let b = PPlastic {
            distribution: match case["distribution"].as_str() {
                Some("ggx") => Distribution::Ggx,
                _ => Distribution::Beckmann,
            },
            alpha_u: num(&case["alpha_u"]),
            alpha_v: num(&case["alpha_v"]),
            diffuse_reflectance: v3(&case["diffuse_reflectance"]),
            specular_reflectance: v3(&case["specular_reflectance"]),
            eta: num(&case["eta"]),
        };
        let rec = BsdfRecord::from(&Bsdf::PPlastic(b));
        let values = case["values"].as_array().expect("values");
        let scale = values
            .iter()
            .map(|v| v3(&v["eval"]).max_element() as f64)
            .fold(0.0, f64::max);
        // Worst relative error in units of ε (values above 1e-6 of the case's largest),
        // and the loosest relative tolerance applied.
        let (mut worst_eval, mut worst_pdf, mut loosest) = (0.0f64, 0.0f64, 0.0f64);
        for v in values {
            let (wo, wi) = (v3(&v["wo"]), v3(&v["wi"]));
            let got = probe
                .eval(&rec, wo, &[[wi.x, wi.y, wi.z, 0.0]])
                .expect("bsdf kernel")[0];
            let (want_eval, want_pdf) = (v3(&v["eval"]), num(&v["pdf"]) as f64);
            // Past x = 50, D < e⁻⁵⁰ / (π α² cos⁴θm): the absolute term covers it.
            let rel = (64.0 + 4.0 * exponent(&b, wo, wi).min(50.0)) * EPS;
            for k in 0..3 {
                let (g, w) = (got.0[k] as f64, want_eval[k] as f64);
                let tol = rel * w.abs() + 1e-7 * scale;
                if w.abs() > 1e-6 * scale {
                    worst_eval = worst_eval.max((g - w).abs() / w.abs() / EPS);
                    loosest = loosest.max(rel);
                }
                assert!(
                    (g - w).abs() <= tol,
                    "{name}: wo {wo}, wi {wi}: eval[{k}] {g}, Mitsuba {w} (tolerance {tol:e})"
                );
            }
            let g = got.1 as f64;
            let tol = rel * want_pdf.abs() + 1e-7;
            if want_pdf > 1e-6 {
                worst_pdf = worst_pdf.max((g - want_pdf).abs() / want_pdf / EPS);
            }
            assert!(
                (g - want_pdf).abs() <= tol,
                "{name}: wo {wo}, wi {wi}: pdf {g}, Mitsuba {want_pdf} (tolerance {tol:e})"
            );
            checked += 1;
        }
        println!(
            "{name}: {} pairs; worst |GPU - Mitsuba| / |Mitsuba|: eval {worst_eval:.1} ε, \
             pdf {worst_pdf:.1} ε (ε = 2⁻²⁴; loosest tolerance {:.0} ε)",
            values.len(),
            loosest / EPS
        );
        // The power control: the tolerance stays far below what a wrong term makes (a
        // Fresnel factor or a lobe weight off by 1% is 1.7e5 ε).
        assert!(loosest < 2e-5, "{name}: tolerance {loosest}");
    }
    assert!(checked >= 250, "{checked} pairs");
}

#[test]
fn spheres_render_as_mitsuba() {
    let scene = common::load(&repo("tests/data/pplastic_spheres.xml"));
    let reference = Image::read_exr(repo("tests/data/pplastic_spheres_ref.exr"))
        .expect("tests/data/pplastic_spheres_ref.exr");
    let img = common::render(&device(), &scene, &RenderOptions::default(), 256);
    assert_eq!(img.non_finite_count(), 0);
    assert_matches_reference_at(&img, &reference, "pplastic spheres, path, 256 spp", 0.01);
}
