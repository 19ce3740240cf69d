//! Participating media's sampling routines against their own densities (chi-square, in
//! GLSL on the GPU, as tests/chi2.rs does for BSDFs): Henyey-Greenstein phase
//! sampling and equiangular distance sampling. The media's renders are in
//! media_vs_mitsuba.rs, media_closed_forms.rs, media_grids.rs and media_stress.rs.

mod common;

use glam::Vec3;
use wavetrace::gpu::{
    shaders, BindingLayout, Buffer, CommandList, DescriptorSet, Kernel, Location,
};

/// At least as many chi-square tests as this file runs (10 now: 6 Henyey-Greenstein g
/// values and 4 equiangular light positions; Šidák correction).
const TESTS_IN_FILE: usize = 12;
/// Family-wise significance of the file.
const ALPHA: f64 = 0.01;
/// Samples per chi-square test.
const N: u32 = 400_000;

fn assert_fit(name: &str, observed: &[f64], expected: &[f64]) {
    common::stats::assert_fit(name, observed, expected, ALPHA, TESTS_IN_FILE);
}

/// Henyey-Greenstein sampling for several g, including ±0.9 (sharp lobes, forward
/// and backward): samples histogrammed on a sphere grid centred on the propagation
/// direction -wo (cells shrink at both poles, where the lobes peak), expected counts by
/// quadrature of phase_pdf; also ∫pdf = 1, sample's pdf = phase_pdf = phase_eval
/// (weights of exactly 1), and unit directions.
#[test]
fn henyey_greenstein_sampling_matches_its_pdf() {
    let probe = common::stats::phase_probe();
    let wo = Vec3::new(0.3, -0.5, 0.8).normalize();
    for (k, g) in [-0.9f32, -0.5, 0.0, 0.3, 0.7, 0.9].into_iter().enumerate() {
        let name = format!("hg g = {g}");
        let (outcome, samples) =
            wavetrace::warptest::test_phase(&probe, g, wo, N, 11 + k as u32).expect("phase kernel");
        for s in &samples {
            let (wi, pdf, eval, pdf_at) = (s.wi, s.pdf, s.eval, s.pdf_eval);
            assert!(
                (wi.length() - 1.0).abs() < 1e-4,
                "{name}: wi {wi} is not unit"
            );
            let rel = |a: f32, b: f32| (a - b).abs() <= 1e-4 * a.abs().max(b.abs());
            assert!(
                pdf > 0.0 && rel(pdf, pdf_at) && rel(pdf, eval),
                "{name}: sample pdf {pdf}, phase_pdf {pdf_at}, phase_eval {eval} at {wi}"
            );
        }
        // Midpoint rule with 256 x 192 points on lobes centred on the grid's axis.
        let total = outcome.pdf_integral;
        assert!(
            (total - 1.0).abs() < 5e-3,
            "{name}: pdf integrates to {total}"
        );
        common::stats::assert_outcome(&name, &outcome, ALPHA, TESTS_IN_FILE);
    }
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct EquiangularPush {
    o: [f32; 4],
    d: [f32; 4],
    c: [f32; 4],
    mode: u32,
    count: u32,
    seed: u32,
    pad: u32,
}

/// Runs `shaders/tests/equiangular.comp`: `count` outputs for `input` (one vec4 each).
fn run_equiangular(push: EquiangularPush, input: &[[f32; 4]]) -> Vec<[f32; 4]> {
    let device = common::device();
    let layout = BindingLayout::new(&device, &[2], 64).expect("layout");
    let kernel = Kernel::new(
        &device,
        "equiangular",
        shaders::TESTS_EQUIANGULAR,
        &layout,
        &[],
    )
    .expect("kernel");
    let dummy = [[0f32; 4]];
    let inb = Buffer::from_slice(&device, "in", if input.is_empty() { &dummy } else { input })
        .expect("buffer");
    let out = Buffer::new(&device, "out", push.count as u64 * 16, Location::Gpu).expect("buffer");
    let set = DescriptorSet::new(&layout, 0, &[&inb, &out]).expect("set");
    let mut cmd = CommandList::new(&device).expect("commands");
    let groups = push.count.div_ceil(64);
    cmd.dispatch(
        &kernel,
        &[&set],
        bytemuck::bytes_of(&push),
        [groups.min(65535), groups.div_ceil(65535), 1],
    );
    cmd.barrier();
    cmd.submit_and_wait().expect("submit");
    let mut v: Vec<[f32; 4]> = out.read(&device).expect("read");
    v.truncate(push.count as usize);
    v
}

/// Equiangular sampling (Kulla and Fajardo 2012) against its pdf: a chi-square test
/// of 400k distances histogrammed in 64 bins of [a, b], expected counts by a 16-point
/// midpoint rule of the kernel's pdf per bin; the pdf integrates to 1 and matches the
/// pdf returned with each sample. Lights beside the segment, far beyond its end,
/// behind its origin, and very close to the ray (a sharp peak).
#[test]
fn equiangular_sampling_matches_its_pdf() {
    let o = Vec3::new(0.1, -0.2, 0.3);
    let d = Vec3::new(1.0, 0.5, -0.3).normalize();
    let (a, b) = (0.5f32, 4.0f32);
    let side = d.any_orthonormal_vector();
    let cases = [
        ("beside the middle", o + 2.0 * d + 0.7 * side),
        ("beyond the end", o + 9.0 * d + 1.5 * side),
        ("behind the origin", o - 2.0 * d + 0.4 * side),
        ("close to the ray", o + 1.3 * d + 0.03 * side),
    ];
    for (k, (name, c)) in cases.into_iter().enumerate() {
        let name = format!("equiangular, light {name}");
        let push = |mode, count| EquiangularPush {
            o: [o.x, o.y, o.z, a],
            d: [d.x, d.y, d.z, b],
            c: [c.x, c.y, c.z, 0.0],
            mode,
            count,
            seed: 100 + k as u32,
            pad: 0,
        };
        let bins = 64usize;
        let mut observed = vec![0.0; bins];
        for s in run_equiangular(push(0, N), &[]) {
            let t = s[0];
            assert!(
                t >= a && t <= b && s[1] > 0.0,
                "{name}: sample {t} with pdf {}",
                s[1]
            );
            let i = (((t - a) / (b - a)) * bins as f32) as usize;
            observed[i.min(bins - 1)] += 1.0;
        }
        let q = 16usize;
        let h = (b - a) as f64 / (bins * q) as f64;
        let points: Vec<[f32; 4]> = (0..bins * q)
            .map(|j| [(a as f64 + (j as f64 + 0.5) * h) as f32, 0.0, 0.0, 0.0])
            .collect();
        let pdf = run_equiangular(push(1, points.len() as u32), &points);
        let mass: Vec<f64> = (0..bins)
            .map(|i| (0..q).map(|j| pdf[i * q + j][0] as f64 * h).sum())
            .collect();
        let total: f64 = mass.iter().sum();
        assert!(
            (total - 1.0).abs() < 2e-3,
            "{name}: pdf integrates to {total}"
        );
        let expected: Vec<f64> = mass.iter().map(|m| m * N as f64).collect();
        assert_fit(&name, &observed, &expected);
    }
}
