//! Sampling of blends and masks as the path tracers sample them (one-sample mixture,
//! `shaders/bsdf/mixture.glsl`, run by `shaders/tests/sample_bsdf.comp` on a blend
//! node and its two models): chi-square of the smooth samples against the mixture's
//! pdf, ∫ pdf against the share of delta samples, and every smooth sample's weight
//! against eval / pdf of the mixture (Mitsuba 3.9.1's blendbsdf). A delta child's
//! samples keep their own weight: the mask's pass-through weighs 1, as Mitsuba's.

mod common;

use common::stats::{bsdf_probe, BsdfProbe, Sampled, FLAG_DELTA};
use glam::Vec3;
use wavetrace::scene::bsdf::composite::{self, Weight};
use wavetrace::scene::bsdf::{Bsdf, Conductor, Dielectric, Diffuse, Distribution, RoughConductor};
use wavetrace::warptest::{test_bsdf_records, Axis};

/// Chi-square tests in this file (Šidák correction).
const TESTS_IN_FILE: usize = 8;
/// Family-wise significance of the file.
const ALPHA: f64 = 0.01;
/// Samples per test, as tests/chi2.rs.
const N: u32 = 400_000;

fn dir(theta_deg: f32, phi_deg: f32) -> Vec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

fn diffuse(r: f32) -> Bsdf {
    Bsdf::Diffuse(Diffuse {
        reflectance: Vec3::splat(r),
    })
}

fn rough_cu(alpha: f32) -> Bsdf {
    Bsdf::RoughConductor(RoughConductor {
        distribution: Distribution::Ggx,
        alpha_u: alpha,
        alpha_v: alpha,
        eta: Vec3::new(0.2, 0.92, 1.1),
        k: Vec3::new(3.9, 2.46, 2.14),
        specular_reflectance: Vec3::ONE,
    })
}

fn blend(w: f32, a: Bsdf, b: Bsdf) -> Bsdf {
    Bsdf::Blend {
        weight: Weight::constant(w),
        bsdfs: Box::new([a, b]),
    }
}

/// Weights of smooth samples against eval / pdf of the mixture (relative 1e-3);
/// returns the share of delta samples.
fn check_weights(name: &str, samples: &[Sampled]) -> f64 {
    let mut delta = 0usize;
    let mut bad = 0usize;
    for s in samples {
        if s.flags == 0 {
            assert_eq!(
                s.weight,
                Vec3::ZERO,
                "{name}: a failed sample carries weight"
            );
            continue;
        }
        assert!(
            s.weight.is_finite() && s.weight.min_element() >= 0.0,
            "{name}: bad weight {s:?}"
        );
        if s.flags & FLAG_DELTA != 0 {
            delta += 1;
            assert_eq!(s.pdf, 0.0, "{name}: delta sample with a pdf");
            continue;
        }
        let rel = |a: f32, b: f32| (a - b).abs() <= 1e-3 * a.abs().max(b.abs()) + 1e-7;
        let w = s.eval / s.pdf_eval;
        if !(s.pdf > 0.0
            && rel(s.pdf, s.pdf_eval)
            && rel(s.weight.x, w.x)
            && rel(s.weight.y, w.y)
            && rel(s.weight.z, w.z))
        {
            bad += 1;
        }
    }
    assert!(
        bad * 10_000 <= samples.len(),
        "{name}: {bad} of {} samples disagree with eval/pdf of the mixture",
        samples.len()
    );
    delta as f64 / samples.len() as f64
}

fn case(probe: &BsdfProbe, name: &str, bsdf: &Bsdf, wo: Vec3, axis: Axis) -> Vec<Sampled> {
    let recs = composite::records(std::slice::from_ref(bsdf));
    let name = format!("{name}, wo = {wo:.2}");
    let (outcome, samples) = test_bsdf_records(probe, &recs, wo, axis, N, 5).expect("bsdf kernel");
    let delta = check_weights(&name, &samples);
    let total = outcome.pdf_integral;
    let sigma = (delta * (1.0 - delta) / N as f64).sqrt();
    let failed = samples.iter().filter(|s| s.flags == 0).count() as f64 / N as f64;
    println!("{name}: ∫pdf = {total:.4}, delta {delta:.4}, absorbed {failed:.4}");
    // As tests/chi2.rs: ∫ pdf = P(smooth sample), within 5 σ and the quadrature's 1%.
    assert!(
        (total + delta - 1.0).abs() < 5.0 * sigma + 0.01 + failed,
        "{name}: ∫pdf = {total} but {delta} of the samples are delta"
    );
    common::stats::assert_outcome(&name, &outcome, ALPHA, TESTS_IN_FILE);
    samples
}

#[test]
fn smooth_blends_sample_their_mixture() {
    let probe = bsdf_probe();
    // Grids centred as tests/chi2.rs centres them: on the mirror direction for a
    // narrow lobe, on the normal for wide ones (a tilted grid's cells at the horizon
    // would expect nothing where samples land).
    for wo in [dir(20.0, 10.0), dir(65.0, 100.0)] {
        case(
            &probe,
            "0.7 diffuse + 0.3 GGX Cu α 0.1",
            &blend(0.3, diffuse(0.5), rough_cu(0.1)),
            wo,
            Axis::Reflect,
        );
        case(
            &probe,
            "0.4 GGX Cu α 0.3 + 0.6 diffuse",
            &blend(0.6, rough_cu(0.3), diffuse(0.8)),
            wo,
            Axis::Normal,
        );
    }
}

#[test]
fn delta_children_keep_their_own_weight() {
    let probe = bsdf_probe();
    let wo = dir(35.0, 0.0);
    // A smooth conductor (F = 1, no absorption): its samples weigh 1, not 1 mixed with
    // the diffuse child's density as Mitsuba 3.9.1's blendbsdf has it.
    let mirror = Bsdf::Conductor(Conductor {
        eta: Vec3::ZERO,
        k: Vec3::ONE,
        specular_reflectance: Vec3::ONE,
    });
    let samples = case(
        &probe,
        "0.6 diffuse + 0.4 mirror",
        &blend(0.4, diffuse(0.5), mirror),
        wo,
        Axis::Normal,
    );
    let mirrored: Vec<&Sampled> = samples
        .iter()
        .filter(|s| s.flags & FLAG_DELTA != 0)
        .collect();
    assert!(mirrored
        .iter()
        .all(|s| (s.weight - Vec3::ONE).abs().max_element() < 1e-5));
    let share = mirrored.len() as f64 / samples.len() as f64;
    assert!(
        (share - 0.4).abs() < 5.0 * (0.24 / N as f64).sqrt(),
        "mirror share {share}"
    );

    // A dielectric beside a diffuse child.
    let glass = Bsdf::Dielectric(Dielectric {
        eta: 1.5,
        specular_reflectance: Vec3::ONE,
        specular_transmittance: Vec3::ONE,
    });
    case(
        &probe,
        "0.5 diffuse + 0.5 glass",
        &blend(0.5, diffuse(0.8), glass),
        wo,
        Axis::Normal,
    );

    // A mask of opacity 0.3: the pass-through (probability 0.7, weight 1) and the
    // rough conductor's samples, whose pdf is 0.3 times the conductor's.
    let mask = Bsdf::Mask {
        opacity: Weight::constant(0.3),
        bsdf: Box::new(rough_cu(0.3)),
    };
    let samples = case(&probe, "mask 0.3 of GGX Cu α 0.3", &mask, wo, Axis::Reflect);
    let through: Vec<&Sampled> = samples
        .iter()
        .filter(|s| s.flags & FLAG_DELTA != 0)
        .collect();
    assert!(through
        .iter()
        .all(|s| s.weight == Vec3::ONE && (s.wi + wo).length() < 1e-5));
    let share = through.len() as f64 / samples.len() as f64;
    assert!(
        (share - 0.7).abs() < 5.0 * (0.21 / N as f64).sqrt(),
        "pass-through share {share}"
    );
}
