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
//!
//! `eta` as a texture or an rgb value (tests/data/pplastic_eta/, `python3
//! tools/mitsuba_pplastic_eta.py`): each case's `<bsdf>`, loaded by wavetrace's loader,
//! evaluated on the GPU through bsdf_textured (shaders/tests/textured_bsdf.comp) at
//! Mitsuba's uv and direction pairs, in three parts: the eta looked up equals
//! Mitsuba's `eval_1` of the texture (the luminance weights differ from Mitsuba's by
//! at most 7.1e-5 each and both sum to 1, so by at most 1.42e-4 times the texel's
//! channel spread, plus 16 ε of the bilinear lookup); the model at Mitsuba's eta equals
//! Mitsuba's eval and pdf (the tolerance above); the textured evaluation equals the
//! model at the eta looked up (the same arithmetic: 4 ε). And a scene of four such
//! spheres (tests/data/pplastic_eta/scene.xml) against Mitsuba's render
//! (`python3 tools/mitsuba_ref.py tests/data/pplastic_eta/scene.xml -o
//! tests/data/pplastic_eta/scene_ref.exr --spp 4096 --variant scalar_rgb`) within noise.

mod common;

use common::mitsuba_values::{
    beckmann_exponent, compare_eval_pdf, num, read_cases, v3, Pair, Tolerance, EPS,
};
use common::stats::bsdf_probe;
use common::{assert_matches_reference_at, device, repo};
use glam::{Vec2, Vec3};
use wavetrace::accel::{prims_from_scene, Bvh};
use wavetrace::gpu::layout::BsdfRecord;
use wavetrace::gpu::{shaders, Kernel};
use wavetrace::image::Image;
use wavetrace::render::scene_buffers::SceneRecords;
use wavetrace::render::RenderOptions;
use wavetrace::scene::bsdf::{Bsdf, Distribution, PPlastic};
use wavetrace::scene::Scene;

#[test]
fn eval_and_pdf_match_mitsuba() {
    let cases = read_cases(
        "tests/data/pplastic_values.json",
        "python3 tools/mitsuba_bsdf_values.py",
    );
    let probe = bsdf_probe();
    let mut checked = 0;
    for case in &cases {
        let c = &case.params;
        let name = c["name"].as_str().expect("name");
        let b = PPlastic {
            distribution: match c["distribution"].as_str() {
                Some("ggx") => Distribution::Ggx,
                _ => Distribution::Beckmann,
            },
            alpha_u: num(&c["alpha_u"]),
            alpha_v: num(&c["alpha_v"]),
            diffuse_reflectance: v3(&c["diffuse_reflectance"]),
            specular_reflectance: v3(&c["specular_reflectance"]),
            eta: num(&c["eta"]),
        };
        let rec = BsdfRecord::from(&Bsdf::PPlastic(b));
        let scale = case.eval_scale();
        // Past x = 50, D < e⁻⁵⁰ / (π α² cos⁴θm): the absolute term covers it.
        let rel = |p: &Pair| {
            let x = beckmann_exponent(b.distribution, b.alpha_u, b.alpha_v, p.wo, p.wi);
            (64.0 + 4.0 * x.min(50.0)) * EPS
        };
        // Worst relative error (values above 1e-6 of the case's largest), and the
        // loosest relative tolerance applied.
        let a = compare_eval_pdf(&probe, &rec, &case.pairs, [1e-6 * scale, 1e-6], |p| {
            [
                Tolerance::new(rel(p), 1e-7 * scale),
                Tolerance::new(rel(p), 1e-7),
            ]
        });
        let loosest = case
            .pairs
            .iter()
            .filter(|p| p.eval.abs().max_element() as f64 > 1e-6 * scale)
            .map(rel)
            .fold(0.0f64, f64::max);
        println!(
            "{name}: {} pairs; worst |GPU - Mitsuba| / |Mitsuba|: eval {:.1} ε, \
             pdf {:.1} ε (ε = 2⁻²⁴; loosest tolerance {:.0} ε)",
            case.pairs.len(),
            a.worst_eval / EPS,
            a.worst_pdf / EPS,
            loosest / EPS
        );
        a.assert_agrees(name, case.pairs.len());
        // The power control: the tolerance stays far below what a wrong term makes (a
        // Fresnel factor or a lobe weight off by 1% is 1.7e5 ε).
        assert!(loosest < 2e-5, "{name}: tolerance {loosest}");
        checked += case.pairs.len();
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

/// The GPU's (f |cos θi|, pdf) and eta of `scene`'s BSDF record `id` with its textures
/// looked up by bsdf_textured at each point's uv (shaders/tests/textured_bsdf.comp).
fn textured_eval(scene: &Scene, id: u32, points: &[(Vec2, Vec3, Vec3)]) -> Vec<(Vec3, f32, f32)> {
    let device = device();
    let bvh = Bvh::build(prims_from_scene(scene));
    let records = SceneRecords::new(scene, &bvh);
    let (layout, buffers) = common::upload_scene(&device, &bvh, &records, 2, 12);
    let kernel = Kernel::new(
        &device,
        "textured_bsdf",
        shaders::TESTS_TEXTURED_BSDF,
        &layout,
        &[],
    )
    .expect("textured_bsdf kernel");
    let queries: Vec<[f32; 4]> = points
        .iter()
        .flat_map(|(uv, wo, wi)| {
            [
                [uv.x, uv.y, 0.0, 0.0],
                [wo.x, wo.y, wo.z, 0.0],
                [wi.x, wi.y, wi.z, 0.0],
            ]
        })
        .collect();
    let n = points.len();
    let raw = common::run_query_kernel(
        &device,
        &layout,
        &kernel,
        &buffers.set,
        &queries,
        &[n as u32, id, 0],
    );
    (0..n)
        .map(|i| {
            let r = raw[i];
            (Vec3::new(r[0], r[1], r[2]), r[3], raw[n + i][0])
        })
        .collect()
}

#[test]
fn textured_eta_evaluates_as_mitsuba() {
    let dir = repo("tests/data/pplastic_eta");
    let text = std::fs::read_to_string(dir.join("values.json"))
        .expect("tests/data/pplastic_eta/values.json (python3 tools/mitsuba_pplastic_eta.py)");
    let data: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    let probe = bsdf_probe();
    let mut checked = 0;
    for case in data["cases"].as_array().expect("cases") {
        let name = case["name"].as_str().expect("name");
        // The case's <bsdf> as written, its bitmap next to the scene.
        let xml = case["xml"].as_str().expect("xml").replace(
            "value=\"eta.exr\"",
            &format!("value=\"{}\"", dir.join("eta.exr").display()),
        );
        let path = common::temp_file(
            "pplastic_eta",
            "scene.xml",
            &format!(
                "<scene version=\"3.0.0\"><sensor type=\"perspective\"><film type=\"hdrfilm\"><integer name=\"width\" value=\"4\"/><integer name=\"height\" value=\"4\"/></film></sensor><shape type=\"sphere\">{xml}</shape></scene>"
            ),
        );
        let scene = common::load(&path);
        let id = scene
            .bsdfs
            .iter()
            .position(|b| match b {
                Bsdf::Textured { bsdf, .. } => matches!(**bsdf, Bsdf::PPlastic(_)),
                b => matches!(b, Bsdf::PPlastic(_)),
            })
            .expect("the case's pplastic");
        let model = match &scene.bsdfs[id] {
            Bsdf::Textured { bsdf, .. } => match **bsdf {
                Bsdf::PPlastic(p) => p,
                _ => unreachable!(),
            },
            Bsdf::PPlastic(p) => *p,
            _ => unreachable!(),
        };
        let values = case["values"].as_array().expect("values");
        let points: Vec<(Vec2, Vec3, Vec3)> = values
            .iter()
            .map(|v| {
                let uv = Vec2::new(num(&v["uv"][0]), num(&v["uv"][1]));
                (uv, v3(&v["wo"]), v3(&v["wi"]))
            })
            .collect();
        let gpu = textured_eval(&scene, id as u32, &points);
        let (mut worst_eta, mut worst_model, mut worst_path) = (0.0f64, 0.0f64, 0.0f64);
        for (v, (&(uv, wo, wi), &(eval, pdf, eta))) in values.iter().zip(points.iter().zip(&gpu)) {
            let at = format!("{name}: uv {uv}, wo {wo}, wi {wi}");
            // 1. The lookup: Mitsuba's eval_1 of the eta texture.
            let want_eta = num(&v["eta"]) as f64;
            let rgb = v3(&v["eta_rgb"]);
            let spread = (rgb.max_element() - rgb.min_element()) as f64;
            let tol = 1.42e-4 * spread + 16.0 * EPS * want_eta;
            let err = (eta as f64 - want_eta).abs();
            worst_eta = worst_eta.max(err / want_eta / EPS);
            assert!(
                err <= tol,
                "{at}: eta {eta}, Mitsuba {want_eta} (tolerance {tol:e})"
            );
            // 2. The model at Mitsuba's eta: Mitsuba's eval and pdf.
            let at_mitsuba = PPlastic {
                eta: want_eta as f32,
                ..model
            };
            let rec = BsdfRecord::from(&Bsdf::PPlastic(at_mitsuba));
            let (want_eval, want_pdf) = (v3(&v["eval"]), num(&v["pdf"]) as f64);
            let got = probe
                .eval(&rec, wo, &[[wi.x, wi.y, wi.z, 0.0]])
                .expect("bsdf kernel")[0];
            let x = beckmann_exponent(model.distribution, model.alpha_u, model.alpha_v, wo, wi);
            let rel = (64.0 + 4.0 * x.min(50.0)) * EPS;
            let scale = want_eval.max_element() as f64;
            for c in 0..3 {
                let (g, w) = (got.0[c] as f64, want_eval[c] as f64);
                if w.abs() > 1e-6 {
                    worst_model = worst_model.max((g - w).abs() / w.abs() / EPS);
                }
                assert!(
                    (g - w).abs() <= rel * w.abs() + 1e-7 * scale,
                    "{at}: eval[{c}] at Mitsuba's eta {g}, Mitsuba {w}"
                );
            }
            for (g, what) in [(got.1 as f64, "pdf"), (pdf as f64, "textured pdf")] {
                assert!(
                    (g - want_pdf).abs() <= rel * want_pdf + 1e-7,
                    "{at}: {what} {g}, Mitsuba {want_pdf}"
                );
            }
            // 3. The textured evaluation: the model at the eta looked up.
            let rec = BsdfRecord::from(&Bsdf::PPlastic(PPlastic { eta, ..model }));
            let same = probe
                .eval(&rec, wo, &[[wi.x, wi.y, wi.z, 0.0]])
                .expect("bsdf kernel")[0]
                .0;
            for c in 0..3 {
                let (g, w) = (eval[c] as f64, same[c] as f64);
                worst_path = worst_path.max((g - w).abs() / w.abs().max(1e-30) / EPS);
                assert!(
                    (g - w).abs() <= 4.0 * EPS * w.abs() + 1e-9,
                    "{at}: textured eval[{c}] {g}, the model at eta {eta}: {w}"
                );
            }
            checked += 1;
        }
        println!(
            "{name}: worst |GPU - Mitsuba| / |Mitsuba|: eta {worst_eta:.1} ε, eval at \
             Mitsuba's eta {worst_model:.1} ε; textured eval against the model {worst_path:.1} ε"
        );
    }
    assert!(checked >= 4 * 48, "{checked} points");
}

#[test]
fn textured_eta_renders_as_mitsuba() {
    let scene = common::load(&repo("tests/data/pplastic_eta/scene.xml"));
    let reference = Image::read_exr(repo("tests/data/pplastic_eta/scene_ref.exr"))
        .expect("tests/data/pplastic_eta/scene_ref.exr (tools/mitsuba_ref.py)");
    let img = common::render(&device(), &scene, &RenderOptions::default(), 256);
    assert_eq!(img.non_finite_count(), 0);
    assert_matches_reference_at(
        &img,
        &reference,
        "pplastic textured eta, path, 256 spp",
        0.01,
    );
}
