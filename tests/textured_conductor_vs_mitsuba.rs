//! Conductors whose `eta` and `k` are textures (`Slot::CondEta`, `Slot::CondK`: the
//! record's `tex_cond_eta`, `tex_cond_k`, looked up in shaders/bsdf/bsdf_textured.glsl)
//! against Mitsuba 3.9.1.
//!
//! Values: tests/data/textured_conductor/values.json (`python3
//! tools/mitsuba_textured_conductor.py`, `scalar_rgb`) holds Mitsuba's eval and pdf of
//! `roughconductor`s with bitmap (EXR) `eta` and `k` at random uv and direction pairs,
//! and its textures' values there. The test loads the same BSDFs with wavetrace's
//! loader, looks the textures up at each uv (the CPU lookup, which
//! tests/texture_lookups_gpu_vs_cpu.rs ties to the GPU's), and evaluates the GPU's
//! model with those indices. Tolerance as tests/pplastic_vs_mitsuba.rs says, widened to
//! 256 ε for the bilinear lookup's roundings, which the Fresnel term carries over.
//!
//! Render: tests/data/textured_conductor/scene.xml (a smooth and two rough conductors,
//! all with textured eta and k) against Mitsuba's render (`python3 tools/mitsuba_ref.py
//! tests/data/textured_conductor/scene.xml -o
//! tests/data/textured_conductor/scene_ref.exr --spp 4096 --variant scalar_rgb`), block
//! by block within noise; the same check rejects the render scaled by 0.95.

mod common;

use common::mitsuba_values::{num, v3, EPS};
use common::stats::bsdf_probe;
use common::{assert_matches_reference_at, device, repo};
use glam::{Vec2, Vec3};
use serde_json::Value;
use wavetrace::gpu::layout::BsdfRecord;
use wavetrace::image::Image;
use wavetrace::render::RenderOptions;
use wavetrace::scene::bsdf::{Bsdf, Distribution, RoughConductor};

const SCENE: &str = "tests/data/textured_conductor/scene.xml";

/// The textured rough conductors of the scene, with their eta and k texture indices.
fn textured_rough_conductors(scene: &wavetrace::scene::Scene) -> Vec<(RoughConductor, u32, u32)> {
    scene
        .bsdfs
        .iter()
        .filter_map(|b| match b {
            Bsdf::Textured { bsdf, maps } => match **bsdf {
                Bsdf::RoughConductor(rc) => Some((rc, maps.cond_eta?, maps.cond_k?)),
                _ => None,
            },
            _ => None,
        })
        .collect()
}

#[test]
fn textured_eta_and_k_eval_as_mitsuba() {
    let text = std::fs::read_to_string(repo("tests/data/textured_conductor/values.json"))
        .expect("values.json (python3 tools/mitsuba_textured_conductor.py)");
    let data: Value = serde_json::from_str(&text).expect("JSON");
    let scene = common::load(&repo(SCENE));
    let models = textured_rough_conductors(&scene);
    assert_eq!(models.len(), 2, "the scene's two textured rough conductors");
    let probe = bsdf_probe();
    let mut checked = 0;
    for case in data["cases"].as_array().expect("cases") {
        let name = case["name"].as_str().expect("name");
        let ggx = case["mitsuba"]["distribution"].as_str() == Some("ggx");
        let &(model, eta_tex, k_tex) = models
            .iter()
            .find(|m| (m.0.distribution == Distribution::Ggx) == ggx)
            .expect("the case's model in the scene");
        let (mut worst_tex, mut worst_eval) = (0.0f64, 0.0f64);
        for v in case["values"].as_array().expect("values") {
            let uv = Vec2::new(num(&v["uv"][0]), num(&v["uv"][1]));
            let eta = scene.textures[eta_tex as usize].eval(uv);
            let k = scene.textures[k_tex as usize].eval(uv);
            for (got, want, what) in [(eta, v3(&v["eta"]), "eta"), (k, v3(&v["k"]), "k")] {
                let err = ((got - want).abs() / want.abs()).max_element() as f64;
                worst_tex = worst_tex.max(err / EPS);
                assert!(
                    err < 16.0 * EPS,
                    "{name}: uv {uv}: {what} {got}, Mitsuba {want}"
                );
            }
            let rec = BsdfRecord::from(&Bsdf::RoughConductor(RoughConductor { eta, k, ..model }));
            let (wo, wi) = (v3(&v["wo"]), v3(&v["wi"]));
            let got = probe
                .eval(&rec, wo, &[[wi.x, wi.y, wi.z, 0.0]])
                .expect("bsdf kernel")[0];
            let (want_eval, want_pdf): (Vec3, f64) = (v3(&v["eval"]), num(&v["pdf"]) as f64);
            // Beckmann's exp carries its argument's error (tests/pplastic_vs_mitsuba.rs).
            let m = (wo + wi).normalize();
            let x = if ggx {
                0.0
            } else {
                let (au, av) = (model.alpha_u as f64, model.alpha_v as f64);
                ((m.x as f64 / au).powi(2) + (m.y as f64 / av).powi(2)) / (m.z as f64).powi(2)
            };
            let rel = (256.0 + 4.0 * x.min(50.0)) * EPS;
            for c in 0..3 {
                let (g, w) = (got.0[c] as f64, want_eval[c] as f64);
                if w.abs() > 1e-6 {
                    worst_eval = worst_eval.max((g - w).abs() / w.abs() / EPS);
                }
                assert!(
                    (g - w).abs() <= rel * w.abs() + 1e-7,
                    "{name}: uv {uv}, wo {wo}, wi {wi}: eval[{c}] {g}, Mitsuba {w}"
                );
            }
            let g = got.1 as f64;
            assert!(
                (g - want_pdf).abs() <= rel * want_pdf + 1e-7,
                "{name}: uv {uv}, wo {wo}, wi {wi}: pdf {g}, Mitsuba {want_pdf}"
            );
            checked += 1;
        }
        println!("{name}: worst relative error: textures {worst_tex:.1} ε, eval {worst_eval:.1} ε");
    }
    assert!(checked >= 96, "{checked} points");
}

#[test]
fn textured_eta_and_k_render_as_mitsuba() {
    let scene = common::load(&repo(SCENE));
    let reference = Image::read_exr(repo("tests/data/textured_conductor/scene_ref.exr"))
        .expect("tests/data/textured_conductor/scene_ref.exr (tools/mitsuba_ref.py)");
    let img = common::render(&device(), &scene, &RenderOptions::default(), 256);
    assert_eq!(img.non_finite_count(), 0);
    assert_matches_reference_at(&img, &reference, "textured eta and k, path, 256 spp", 0.01);
}
