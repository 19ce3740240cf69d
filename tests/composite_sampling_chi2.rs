//! Sampling of blends and masks as the path tracers sample them (one-sample mixture,
//! `shaders/bsdf/mixture.glsl`, run by `shaders/tests/sample_bsdf.comp` on a blend
//! node and its two models): chi-square of the smooth samples against the mixture's
//! pdf, ∫ pdf against the share of delta samples, and every smooth sample's weight
//! against eval / pdf of the mixture (Mitsuba 3.9.1's blendbsdf). A delta child's
//! samples keep their own weight: the mask's pass-through weighs 1, as Mitsuba's.

mod common;

use common::stats::{bsdf_probe, dir, BsdfProbe, Sampled, FLAG_DELTA};
use glam::Vec3;
use wavetrace::scene::bsdf::composite::{self, Weight};
use wavetrace::scene::bsdf::{Bsdf, Conductor, Dielectric, Diffuse, Distribution, RoughConductor};
use wavetrace::warptest::Axis;

/// Chi-square tests in this file (Šidák correction).
const TESTS_IN_FILE: usize = 8;
/// Family-wise significance of the file.
const ALPHA: f64 = 0.01;
/// Samples per test, as tests/chi2.rs.
const N: u32 = 400_000;

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

/// A case of common::stats::bsdf_case (chi-square of the smooth samples against the
/// mixture's pdf, ∫ pdf against the share of delta samples, every smooth sample's
/// weight against eval / pdf of the mixture); returns the samples.
fn case(probe: &BsdfProbe, name: &str, bsdf: &Bsdf, wo: Vec3, axis: Axis) -> Vec<Sampled> {
    let recs = composite::records(std::slice::from_ref(bsdf));
    common::stats::bsdf_case(probe, name, &recs, wo, axis, (N, 5), ALPHA, TESTS_IN_FILE)
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
