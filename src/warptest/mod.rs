//! Statistical tests of the GPU samplers: draw samples with a GLSL sampling routine,
//! histogram them, and compare with the counts its own pdf predicts by Pearson's
//! chi-square test, as Nori's warptest and Mitsuba's `chi2` do. `wavetrace warptest`
//! runs one test and draws the histograms; tests/chi2.rs, tests/furnace.rs and
//! tests/media_sampling_chi2.rs run many.
//!
//! - [`grid`]: the cells (a sphere grid around an axis, or a chart of a planar domain)
//!   and the quadrature giving each cell's expected count;
//! - [`chi2`]: the test statistic and p-value;
//! - [`probe`]: the GPU runners of warps, BSDFs and phase functions;
//! - [`image`]: observed and expected histograms side by side, as a PNG;
//! - [`target`]: targets by name and parameters, as the command line gives them.

pub mod chi2;
pub mod grid;
pub mod image;
pub mod probe;
pub mod target;

use glam::Vec3;

use crate::gpu::layout::BsdfRecord;
use crate::gpu::{Device, Result};
use crate::scene::bsdf::{composite, LobeAxis};
use crate::scene::Bsdf;

pub use chi2::{chi2, gamma_q, sidak, Chi2};
pub use grid::{Chart, Grid, PlaneGrid, SphereGrid};
pub use probe::{BsdfProbe, PhaseProbe, Sampled, Warp, WarpProbe};

/// Quadrature points per cell side for expected counts (k x k per cell): with 32 x 24
/// cells, 256 x 192 midpoints over the sphere.
pub const QUADRATURE: usize = 8;

/// What to test.
#[derive(Debug, Clone)]
pub enum Target {
    /// A warp of warp.glsl or a microfacet normal sampler.
    Warp(Warp),
    /// `bsdf_sample` of a BSDF against `bsdf_pdf`, for the incident direction `wo`
    /// (local frame, z the normal), histogrammed around `axis`.
    Bsdf { bsdf: Bsdf, wo: Vec3, axis: Axis },
    /// Henyey-Greenstein `phase_sample` against `phase_pdf` (g = 0: isotropic), for
    /// the direction `wo` towards the previous vertex.
    Phase { g: f32, wo: Vec3 },
}

/// What `wavetrace warptest` runs ([`target::parse`]): a [`Target`] of this module's
/// own kernels ([`run`]), or a test that needs a scene's buffers, which the layer
/// above uploads (`render::emitter_probe`; `warptest` sits below `render`).
#[derive(Debug, Clone)]
pub enum Test {
    Kernel(Target),
    /// A directionalarea emitter's light rays on a shape of its own
    /// (`shaders/emitter/directionalarea.glsl`): the points against their density.
    DirectionalArea(AreaLight),
}

/// The shape a [`Test::DirectionalArea`] emitter sits on, placed so that its area
/// in world space differs from its local one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AreaShape {
    /// A mesh of four triangles of areas 0.5, 0.7, 1.5 and 1.3 tiling the square
    /// [-1, 1]² (a fan from (0.3, -0.5)), scaled unevenly, rotated and moved.
    Fan,
    /// A disk, scaled, rotated and moved.
    Disk,
    /// A sphere (its points as directions from the centre).
    Sphere,
}

/// What [`Test::DirectionalArea`] tests: the emitter's shape, and whether to pair
/// its points with a deliberately wrong density (the fan's triangles chosen uniformly
/// instead of by area), for testing the test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AreaLight {
    pub shape: AreaShape,
    pub mismatched: bool,
}

/// Where to centre a sphere grid for a BSDF: cells shrink near the axis and its
/// opposite, where narrow lobes peak.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Axis {
    /// The normal.
    Normal,
    /// The mirror direction of wo.
    Reflect,
    /// The refracted direction of wo through a smooth interface of relative index eta.
    Refract(f32),
}

impl Axis {
    /// The axis direction for incident direction `wo` (local frame).
    pub fn direction(self, wo: Vec3) -> Vec3 {
        match self {
            Axis::Normal => Vec3::Z,
            Axis::Reflect => Vec3::new(-wo.x, -wo.y, wo.z),
            Axis::Refract(eta) => {
                let eta_ti = if wo.z > 0.0 { 1.0 / eta } else { eta };
                let s2 = eta_ti * eta_ti * (1.0 - wo.z * wo.z);
                if s2 >= 1.0 {
                    Vec3::new(-wo.x, -wo.y, wo.z)
                } else {
                    let ct = (1.0 - s2).sqrt() * -wo.z.signum();
                    Vec3::new(-eta_ti * wo.x, -eta_ti * wo.y, ct).normalize()
                }
            }
        }
    }

    /// The axis that resolves `bsdf`'s lobe best: the mirror (or refracted) direction
    /// for roughness below 0.2, else the normal.
    pub fn for_bsdf(bsdf: &Bsdf) -> Axis {
        match bsdf.model().lobe_axis() {
            LobeAxis::Normal => Axis::Normal,
            LobeAxis::Reflect => Axis::Reflect,
            LobeAxis::Refract(eta) => Axis::Refract(eta),
        }
    }
}

/// A finished test: counts per cell, the pdf's integral, the verdict.
#[derive(Debug, Clone)]
pub struct Outcome {
    pub grid: Grid,
    pub observed: Vec<f64>,
    pub expected: Vec<f64>,
    /// Samples drawn.
    pub samples: usize,
    /// Samples left out of the histogram: delta lobes (a BSDF's smooth part) and
    /// failed samples (absorbed, zero weight).
    pub excluded: usize,
    /// Samples that fell in no cell (off the domain): part of the observed misfit.
    pub outside: usize,
    /// ∫ pdf over the domain by the quadrature (1 for a normalized sampler without
    /// delta lobes).
    pub pdf_integral: f64,
    pub chi2: Chi2,
}

impl Outcome {
    /// Whether the test accepts the sampler at significance `alpha` (the p-value is at
    /// least `alpha` and no sample fell off the domain).
    pub fn passes(&self, alpha: f64) -> bool {
        self.outside == 0 && self.chi2.p_value >= alpha
    }
}

/// Expected counts of `samples` samples in each cell of `grid` for `pdf` (evaluated
/// at the quadrature points); also ∫ pdf.
pub fn expected_counts(
    grid: &Grid,
    samples: usize,
    pdf: impl FnOnce(&[[f32; 4]]) -> Result<Vec<f64>>,
) -> Result<(Vec<f64>, f64)> {
    let (points, w) = grid.quadrature(QUADRATURE);
    let density = pdf(&points)?;
    let mass = grid.integrate(QUADRATURE, &density, &w);
    let total = mass.iter().sum();
    Ok((mass.iter().map(|m| m * samples as f64).collect(), total))
}

/// The outcome of a test from its grid, the sampled points (in the grid's domain),
/// the samples drawn and left out, and [`expected_counts`].
pub fn finish(
    grid: Grid,
    points: Vec<Vec3>,
    samples: usize,
    excluded: usize,
    expected: (Vec<f64>, f64),
) -> Outcome {
    let (observed, outside) = grid.histogram(points);
    let (expected, pdf_integral) = expected;
    let mut test = chi2(&observed, &expected);
    if outside > 0 {
        test.p_value = 0.0;
    }
    Outcome {
        grid,
        observed,
        expected,
        samples,
        excluded,
        outside,
        pdf_integral,
        chi2: test,
    }
}

/// The grid a warp is histogrammed on: 32 x 32 chart cells for planar domains, 32 x 24
/// sphere cells around +z for directions.
pub fn warp_grid(warp: Warp) -> Grid {
    match warp {
        Warp::Disk | Warp::ThinLensAperture => Grid::Plane(PlaneGrid {
            chart: Chart::Disk,
            res: 32,
        }),
        Warp::Projector { tan_x, tan_y } => Grid::Plane(PlaneGrid {
            chart: Chart::Frustum { tan_x, tan_y },
            res: 32,
        }),
        Warp::Triangle => Grid::Plane(PlaneGrid {
            chart: Chart::Triangle,
            res: 32,
        }),
        _ => Grid::Sphere(SphereGrid::new(Vec3::Z, 32, 24)),
    }
}

/// Tests a warp with `n` samples.
pub fn test_warp(probe: &WarpProbe, warp: Warp, n: u32, seed: u32) -> Result<Outcome> {
    let grid = warp_grid(warp);
    let samples = probe.sample(warp, n, seed)?;
    let points = samples
        .iter()
        .map(|s| Vec3::new(s[0], s[1], s[2]))
        .collect();
    let expected = expected_counts(&grid, n as usize, |p| probe.pdf(warp, p))?;
    Ok(finish(grid, points, n as usize, 0, expected))
}

/// Tests `bsdf_sample` of `rec` for incident direction `wo` with `n` samples: the
/// non-delta samples against `bsdf_pdf`. Also returns the samples.
pub fn test_bsdf(
    probe: &BsdfProbe,
    rec: &BsdfRecord,
    wo: Vec3,
    axis: Axis,
    n: u32,
    seed: u32,
) -> Result<(Outcome, Vec<Sampled>)> {
    test_bsdf_records(probe, std::slice::from_ref(rec), wo, axis, n, seed)
}

/// [`test_bsdf`] of the records of one BSDF ([`BsdfProbe::sample_records`]: a model,
/// or a blend of two).
pub fn test_bsdf_records(
    probe: &BsdfProbe,
    recs: &[BsdfRecord],
    wo: Vec3,
    axis: Axis,
    n: u32,
    seed: u32,
) -> Result<(Outcome, Vec<Sampled>)> {
    let grid = Grid::Sphere(SphereGrid::new(axis.direction(wo), 32, 24));
    let samples = probe.sample_records(recs, wo, n, seed)?;
    let kept: Vec<Vec3> = samples
        .iter()
        .filter(|s| s.flags != 0 && s.flags & probe::FLAG_DELTA == 0)
        .map(|s| s.wi)
        .collect();
    let excluded = samples.len() - kept.len();
    let expected = expected_counts(&grid, n as usize, |dirs| {
        Ok(probe
            .eval_records(recs, wo, dirs)?
            .iter()
            .map(|e| e.1 as f64)
            .collect())
    })?;
    Ok((finish(grid, kept, n as usize, excluded, expected), samples))
}

/// Tests Henyey-Greenstein sampling with asymmetry `g` for `wo`, histogrammed around
/// the propagation direction -wo. Also returns the samples.
pub fn test_phase(
    probe: &PhaseProbe,
    g: f32,
    wo: Vec3,
    n: u32,
    seed: u32,
) -> Result<(Outcome, Vec<probe::PhaseSampled>)> {
    let grid = Grid::Sphere(SphereGrid::new(-wo, 32, 24));
    let samples = probe.sample(g, wo, n, seed)?;
    let points = samples.iter().map(|s| s.wi).collect();
    let expected = expected_counts(&grid, n as usize, |dirs| probe.pdf(g, wo, dirs))?;
    Ok((finish(grid, points, n as usize, 0, expected), samples))
}

/// Runs the test of `target` with `n` samples on `device`.
pub fn run(device: &Device, target: &Target, n: u32, seed: u32) -> Result<Outcome> {
    match target {
        Target::Warp(w) => test_warp(&WarpProbe::new(device)?, *w, n, seed),
        Target::Bsdf { bsdf, wo, axis } => {
            let mut probe = BsdfProbe::new(device)?;
            let (rec, tables) = crate::scene::bsdf::measured::record_with_tables(bsdf);
            let mut recs = composite::records(std::slice::from_ref(bsdf));
            if !tables.is_empty() {
                probe.set_tables(&tables);
                recs[0] = rec;
            }
            Ok(test_bsdf_records(&probe, &recs, *wo, *axis, n, seed)?.0)
        }
        Target::Phase { g, wo } => Ok(test_phase(&PhaseProbe::new(device)?, *g, *wo, n, seed)?.0),
    }
}
