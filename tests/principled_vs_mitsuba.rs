//! `principled` and `principledthin` against Mitsuba 3 itself: the GPU's bsdf_eval and
//! bsdf_pdf at the (wo, wi) pairs and parameter sets of
//! tests/data/principled_values.json, which Mitsuba 3.9.1 computed (`scalar_rgb`,
//! single precision; `python3 tools/mitsuba_principled_values.py >
//! tests/data/principled_values.json`), on both sides of the surface. Each case's
//! Mitsuba dictionary is read back here as a scene, so the test covers wavetrace's
//! reading of the parameters (`specular` to `eta`, the sampling rates) too.
//!
//! Tolerance: both sides evaluate the same formulas in single precision in different
//! orders; GGX's D = 1 / (π α_u α_v t²) near a sharp peak (α = 0.0025) amplifies the
//! half vector's rounding by about 1 / α, and the refracted half vector's
//! normalization divides by |wo + η wi|, which nearly vanishes at grazing
//! refraction. So |GPU - Mitsuba| <= 2e-4 |Mitsuba| + 1e-6 max(eval): a term off by a
//! lobe weight or a Fresnel factor (≥ 1%) still fails by 50 times.
//!
//! And a scene with every model and a textured parameter rendered by both
//! (scenes/principled/principled.xml at 64 x 64), against Mitsuba's render
//! (`python3 tools/mitsuba_ref.py scenes/principled/principled.xml -o
//! tests/data/principled_scene_ref.exr --spp 16384 --variant llvm_ad_rgb -D res=64`)
//! within noise.

mod common;

use common::mitsuba_values::v3;
use common::stats::bsdf_probe;
use common::{assert_matches_reference_at, device, repo};
use serde_json::Value;
use wavetrace::gpu::layout::BsdfRecord;
use wavetrace::image::Image;
use wavetrace::render::RenderOptions;

#[test]
fn eval_and_pdf_match_mitsuba() {
    let text = std::fs::read_to_string(repo("tests/data/principled_values.json"))
        .expect("tests/data/principled_values.json (python3 tools/mitsuba_principled_values.py)");
    let data: Value = serde_json::from_str(&text).expect("JSON");
    let probe = bsdf_probe();
    let mut checked = 0;
    for (i, case) in data["cases"].as_array().expect("cases").iter().enumerate() {
        let name = case["mitsuba"].to_string();
        let rec = BsdfRecord::from(&common::bsdf_from_mitsuba_dict(
            &case["mitsuba"],
            &format!("principled_vs_mitsuba{i}"),
        ));
        let values = case["values"].as_array().expect("values");
        let scale = values
            .iter()
            .map(|v| v3(&v["eval"]).max_element() as f64)
            .fold(0.0, f64::max);
        let (mut worst_eval, mut worst_pdf) = (0.0f64, 0.0f64);
        let mut failures = Vec::new();
        for v in values {
            let (wo, wi) = (v3(&v["wo"]), v3(&v["wi"]));
            let got = probe
                .eval(&rec, wo, &[[wi.x, wi.y, wi.z, 0.0]])
                .expect("bsdf kernel")[0];
            let (want_eval, want_pdf) = (v3(&v["eval"]), v["pdf"].as_f64().expect("pdf"));
            for k in 0..3 {
                let (g, w) = (got.0[k] as f64, want_eval[k] as f64);
                if w.abs() > 1e-6 * scale {
                    worst_eval = worst_eval.max((g - w).abs() / w.abs());
                }
                if (g - w).abs() > 2e-4 * w.abs() + 1e-6 * scale {
                    failures.push(format!("wo {wo}, wi {wi}: eval[{k}] {g}, Mitsuba {w}"));
                }
            }
            let g = got.1 as f64;
            if want_pdf > 1e-6 {
                worst_pdf = worst_pdf.max((g - want_pdf).abs() / want_pdf);
            }
            if (g - want_pdf).abs() > 2e-4 * want_pdf.abs() + 1e-6 {
                failures.push(format!("wo {wo}, wi {wi}: pdf {g}, Mitsuba {want_pdf}"));
            }
            checked += 1;
        }
        println!(
            "{name}: {} pairs; worst relative |GPU - Mitsuba|: eval {worst_eval:.1e}, pdf {worst_pdf:.1e}",
            values.len()
        );
        assert!(
            failures.is_empty(),
            "{name}: {} of {} disagree:\n{}",
            failures.len(),
            values.len(),
            failures.join("\n")
        );
    }
    assert!(checked >= 1000, "{checked} pairs");
}

#[test]
fn scene_renders_as_mitsuba() {
    let scene = common::load_with(&repo("scenes/principled/principled.xml"), &[("res", "64")]);
    let reference = Image::read_exr(repo("tests/data/principled_scene_ref.exr"))
        .expect("tests/data/principled_scene_ref.exr");
    let img = common::render(&device(), &scene, &RenderOptions::default(), 512);
    assert_eq!(img.non_finite_count(), 0);
    assert_matches_reference_at(&img, &reference, "principled scene, path, 512 spp", 0.01);
}
