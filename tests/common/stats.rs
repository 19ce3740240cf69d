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
