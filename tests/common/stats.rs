//! Statistical helpers shared by the GPU tests. The chi-square machinery itself (sphere
//! grids, quadrature, Pearson's test, the GPU runners of the sampling kernels) lives
//! in the library, `wavetrace::warptest`, which `wavetrace warptest` also runs; this
//! file adds what only tests need: the file-wide significance of many tests and a
//! deterministic generator for test inputs.
//!
//! A file of m tests rejects each at the Šidák-corrected level 1 - (1 - 0.01)^(1/m),
//! so the whole file has a 1% false-alarm rate.

// Each test binary compiles this module and uses a part of it.
#![allow(dead_code, unused_imports)]

pub use wavetrace::warptest::probe::{FLAG_DELTA, FLAG_NULL, FLAG_REFLECTION, FLAG_TRANSMISSION};
pub use wavetrace::warptest::{
    chi2, sidak, BsdfProbe, Outcome, PhaseProbe, Sampled, SphereGrid, Warp, WarpProbe,
};

use glam::Vec3;
use wavetrace::gpu::layout::BsdfRecord;
use wavetrace::warptest::{test_bsdf_records, Axis};

/// SplitMix64 (Steele, Lea, Flood 2014): a small deterministic generator for test
/// inputs and CPU random walks, so failures reproduce.
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1) with 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [0, 1) with 24 random bits.
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// Chi-square test of sampled `observed` counts against the pdf's `expected` counts,
/// failing at the Šidák level for `alpha` over `tests` tests (the number of such tests
/// in the calling file, or more).
pub fn assert_fit(name: &str, observed: &[f64], expected: &[f64], alpha: f64, tests: usize) {
    let r = chi2(observed, expected);
    let level = sidak(alpha, tests);
    println!(
        "{name}: X² = {:.1}, dof = {}, p = {:.4}",
        r.statistic, r.dof, r.p_value
    );
    assert!(
        r.p_value > level,
        "{name}: sampling does not match the pdf: X² = {:.1} with {} dof, p = {:.3e} < {:.3e}",
        r.statistic,
        r.dof,
        r.p_value,
        level
    );
}

/// [`assert_fit`] on a finished [`Outcome`], which must also have every sample on the
/// domain.
pub fn assert_outcome(name: &str, outcome: &Outcome, alpha: f64, tests: usize) {
    assert_eq!(
        outcome.outside, 0,
        "{name}: {} samples fell outside the domain",
        outcome.outside
    );
    assert_fit(name, &outcome.observed, &outcome.expected, alpha, tests);
}

/// A warp probe on the test device.
pub fn warp_probe() -> WarpProbe {
    WarpProbe::new(&super::device()).expect("warp kernel")
}

/// A BSDF probe on the test device.
pub fn bsdf_probe() -> BsdfProbe {
    BsdfProbe::new(&super::device()).expect("bsdf kernel")
}

/// A phase-function probe on the test device.
pub fn phase_probe() -> PhaseProbe {
    PhaseProbe::new(&super::device()).expect("phase kernel")
}

/// The unit direction at polar angle `theta_deg` from +z and azimuth `phi_deg`.
pub fn dir(theta_deg: f32, phi_deg: f32) -> Vec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

/// eval/pdf consistency of the non-delta samples of bsdf_sample (failed samples
/// weigh nothing, weights are finite and non-negative, wi is unit, each sample is a
/// reflection or a transmission, delta samples have no pdf, and the others' pdf and
/// weight are bsdf_pdf's and bsdf_eval / bsdf_pdf); returns the fraction of delta
/// samples.
pub fn check_bsdf_samples(name: &str, samples: &[Sampled]) -> f64 {
    let mut delta = 0usize;
    let mut bad = 0usize;
    let mut worst = String::new();
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
            "{name}: bad weight {:?}",
            s
        );
        assert!(
            (s.wi.length() - 1.0).abs() < 1e-3,
            "{name}: wi not unit: {:?}",
            s
        );
        let refl = s.flags & FLAG_REFLECTION != 0;
        let trans = s.flags & FLAG_TRANSMISSION != 0;
        assert!(refl != trans, "{name}: flags {}", s.flags);
        if s.flags & FLAG_DELTA != 0 {
            delta += 1;
            assert_eq!(s.pdf, 0.0, "{name}: delta sample with a pdf");
            continue;
        }
        // Relative 1e-3 (f32 evaluations of the same terms along different paths).
        let rel = |a: f32, b: f32| (a - b).abs() <= 1e-3 * a.abs().max(b.abs()) + 1e-7;
        let w = s.eval / s.pdf_eval;
        let ok = s.pdf > 0.0
            && rel(s.pdf, s.pdf_eval)
            && rel(s.weight.x, w.x)
            && rel(s.weight.y, w.y)
            && rel(s.weight.z, w.z);
        if !ok {
            bad += 1;
            if worst.is_empty() {
                worst = format!("{s:?} (eval/pdf = {w})");
            }
        }
    }
    // At most 1 in 10^4 samples may miss the 1e-3 agreement through f32 cancellation
    // (normalize(wo + wi) at near-grazing configurations).
    assert!(
        bad * 10_000 <= samples.len(),
        "{name}: {bad} of {} samples disagree with eval/pdf, e.g. {worst}",
        samples.len()
    );
    delta as f64 / samples.len() as f64
}

/// One BSDF case of `n` samples of the BSDF whose records are `recs` (a model's, or
/// a composite's nodes and models): chi-square of the non-delta samples against
/// bsdf_pdf (wavetrace::warptest::test_bsdf_records) at the Šidák level for `alpha`
/// over `tests` tests, pdf normalization, [`check_bsdf_samples`]; returns the samples.
#[allow(clippy::too_many_arguments)]
pub fn bsdf_case(
    probe: &BsdfProbe,
    name: &str,
    recs: &[BsdfRecord],
    wo: Vec3,
    axis: Axis,
    (n, seed): (u32, u32),
    alpha: f64,
    tests: usize,
) -> Vec<Sampled> {
    let name = format!("{name}, wo = {wo:.2}");
    let (outcome, samples) =
        test_bsdf_records(probe, recs, wo, axis, n, seed).expect("bsdf kernel");
    let delta = check_bsdf_samples(&name, &samples);
    let total = outcome.pdf_integral;
    // ∫ pdf = P(non-delta sample). Allowed gap: 5 binomial σ of the delta fraction plus
    // 1% for the quadrature (midpoint, 256 x 192 points, peaks centred on the grid axis)
    // and for samples lost below the horizon (pdf mass with no valid sample).
    let sigma = (delta * (1.0 - delta) / n as f64).sqrt();
    let failed = samples.iter().filter(|s| s.flags == 0).count() as f64 / n as f64;
    println!("{name}: ∫pdf = {total:.4}, delta {delta:.4}, absorbed {failed:.4}");
    assert!(
        (total + delta - 1.0).abs() < 5.0 * sigma + 0.01 + failed,
        "{name}: ∫pdf = {total} but {delta} of the samples are delta"
    );
    assert_outcome(&name, &outcome, alpha, tests);
    samples
}
