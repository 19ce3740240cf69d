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

use common::mitsuba_values::{
    beckmann_exponent, compare_eval_pdf, num, read_cases, v3, Pair, Tolerance, EPS,
};
use common::stats::bsdf_probe;
use common::{assert_matches_reference_at, device, repo};
use wavetrace::gpu::layout::BsdfRecord;
use wavetrace::image::Image;
use wavetrace::render::RenderOptions;
use wavetrace::scene::bsdf::{Bsdf, Distribution, PPlastic};

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
