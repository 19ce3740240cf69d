//! Participating media: phase-function sampling against its density (chi-square, in
//! GLSL on the GPU, as tests/chi2.rs does for BSDFs).

mod common;

use common::stats::{chi2, sidak, SphereGrid};
use glam::Vec3;
use wavetrace::gpu::{
    shaders, BindingLayout, Buffer, CommandList, DescriptorSet, Device, Kernel, Location,
};

/// At least as many chi-square tests as this file runs (Šidák correction).
const TESTS_IN_FILE: usize = 12;
/// Family-wise significance of the file.
const ALPHA: f64 = 0.01;
/// Samples per chi-square test.
const N: u32 = 400_000;

fn assert_fit(name: &str, observed: &[f64], expected: &[f64]) {
    let r = chi2(observed, expected);
    let level = sidak(ALPHA, TESTS_IN_FILE);
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

/// GPU runner for `shaders/tests/phase.comp`.
struct PhaseProbe {
    device: Device,
    layout: BindingLayout,
    kernel: Kernel,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct PhasePush {
    wo: [f32; 4],
    g: f32,
    mode: u32,
    count: u32,
    seed: u32,
}

impl PhaseProbe {
    fn new() -> PhaseProbe {
        let device = common::device();
        let layout = BindingLayout::new(&device, &[2], 32).expect("layout");
        let kernel =
            Kernel::new(&device, "phase", shaders::TESTS_PHASE, &layout, &[]).expect("kernel");
        PhaseProbe {
            device,
            layout,
            kernel,
        }
    }

    fn run(&self, push: PhasePush, dirs: &[[f32; 4]], per_item: u64) -> Vec<[f32; 4]> {
        let d = &self.device;
        let dummy = [[0f32; 4]];
        let input = Buffer::from_slice(d, "dirs", if dirs.is_empty() { &dummy } else { dirs })
            .expect("buffer");
        let n = push.count as u64 * per_item;
        let out = Buffer::new(d, "out", (n * 16).max(16), Location::Gpu).expect("buffer");
        let set = DescriptorSet::new(&self.layout, 0, &[&input, &out]).expect("set");
        let mut cmd = CommandList::new(d).expect("commands");
        let groups = push.count.div_ceil(64);
        cmd.dispatch(
            &self.kernel,
            &[&set],
            bytemuck::bytes_of(&push),
            [groups.min(65535), groups.div_ceil(65535), 1],
        );
        cmd.barrier();
        cmd.submit_and_wait().expect("submit");
        let mut v: Vec<[f32; 4]> = out.read(d).expect("read");
        v.truncate(n as usize);
        v
    }

    /// (wi, pdf from sample, eval at wi, pdf at wi) for `count` samples.
    fn sample(&self, g: f32, wo: Vec3, count: u32, seed: u32) -> Vec<(Vec3, f32, f32, f32)> {
        let push = PhasePush {
            wo: [wo.x, wo.y, wo.z, 0.0],
            g,
            mode: 0,
            count,
            seed,
        };
        self.run(push, &[], 2)
            .chunks(2)
            .map(|c| {
                (
                    Vec3::new(c[0][0], c[0][1], c[0][2]),
                    c[0][3],
                    c[1][0],
                    c[1][1],
                )
            })
            .collect()
    }

    /// phase_pdf at each direction.
    fn pdf(&self, g: f32, wo: Vec3, dirs: &[[f32; 4]]) -> Vec<f64> {
        let push = PhasePush {
            wo: [wo.x, wo.y, wo.z, 0.0],
            g,
            mode: 1,
            count: dirs.len() as u32,
            seed: 0,
        };
        self.run(push, dirs, 1)
            .iter()
            .map(|v| v[0] as f64)
            .collect()
    }
}

/// Henyey-Greenstein sampling for several g, including ±0.9 (sharp lobes, forward
/// and backward): samples histogrammed on a sphere grid centred on the propagation
/// direction -wo (cells shrink at both poles, where the lobes peak), expected counts by
/// quadrature of phase_pdf; also ∫pdf = 1, sample's pdf = phase_pdf = phase_eval
/// (weights of exactly 1), and unit directions.
#[test]
fn henyey_greenstein_sampling_matches_its_pdf() {
    let probe = PhaseProbe::new();
    let wo = Vec3::new(0.3, -0.5, 0.8).normalize();
    for (k, g) in [-0.9f32, -0.5, 0.0, 0.3, 0.7, 0.9].into_iter().enumerate() {
        let name = format!("hg g = {g}");
        let samples = probe.sample(g, wo, N, 11 + k as u32);
        let grid = SphereGrid::new(-wo, 32, 24);
        let mut observed = vec![0.0; grid.cells()];
        for (wi, pdf, eval, pdf_at) in &samples {
            assert!(
                (wi.length() - 1.0).abs() < 1e-4,
                "{name}: wi {wi} is not unit"
            );
            let rel = |a: f32, b: f32| (a - b).abs() <= 1e-4 * a.abs().max(b.abs());
            assert!(
                *pdf > 0.0 && rel(*pdf, *pdf_at) && rel(*pdf, *eval),
                "{name}: sample pdf {pdf}, phase_pdf {pdf_at}, phase_eval {eval} at {wi}"
            );
            observed[grid.cell_of(*wi).expect("finite wi")] += 1.0;
        }
        let (dirs, w) = grid.quadrature(8);
        let pdf = probe.pdf(g, wo, &dirs);
        let mass = grid.integrate(8, &pdf, &w);
        let total: f64 = mass.iter().sum();
        // Midpoint rule with 256 x 192 points on lobes centred on the grid's axis.
        assert!(
            (total - 1.0).abs() < 5e-3,
            "{name}: pdf integrates to {total}"
        );
        let expected: Vec<f64> = mass.iter().map(|m| m * N as f64).collect();
        assert_fit(&name, &observed, &expected);
    }
}
