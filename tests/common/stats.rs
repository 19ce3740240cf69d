//! Statistical test machinery shared by tests/chi2.rs and tests/furnace.rs: Pearson's
//! chi-square goodness of fit as Nori's warptest (`src/warptest.cpp`, `chi2test.cpp`)
//! and Mitsuba's `mitsuba.chi2` do it, and runners for the GLSL test kernels
//! `shaders/tests/sample_bsdf.comp` and `shaders/tests/warp.comp`.
//!
//! A test histograms N samples over a grid of cells and compares with expected counts
//! N ∫_cell pdf, integrated numerically from the pdf evaluated on the GPU at k x k
//! midpoints per cell. Cells expecting fewer than 5 samples are pooled into one (as
//! Nori and Mitsuba do), the statistic X² = Σ (O - E)² / E has (cells - 1) degrees of
//! freedom, and its p-value is Q(dof/2, X²/2), the regularized upper incomplete gamma
//! function. A file of m tests rejects each at the Šidák-corrected level
//! 1 - (1 - 0.01)^(1/m), so the whole file has a 1% false-alarm rate.

#![allow(dead_code)]

use glam::Vec3;
use wavetrace::gpu::layout::BsdfRecord;
use wavetrace::gpu::{
    shaders, BindingLayout, Buffer, CommandList, DescriptorSet, Device, Kernel, Location,
};

pub use wavetrace::image::metrics::ln_gamma;

/// Regularized upper incomplete gamma Q(a, x) = Γ(a, x) / Γ(a): the series for
/// x < a + 1, else the continued fraction (Press et al., "Numerical Recipes", 3rd ed.,
/// sec. 6.2, `gser` / `gcf`).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let gln = ln_gamma(a);
    if x < a + 1.0 {
        let (mut ap, mut sum) = (a, 1.0 / a);
        let mut del = sum;
        for _ in 0..10_000 {
            ap += 1.0;
            del *= x / ap;
            sum += del;
            if del.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        1.0 - sum * (-x + a * x.ln() - gln).exp()
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-15 {
                break;
            }
        }
        (-x + a * x.ln() - gln).exp() * h
    }
}

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

/// Per-test significance for `m` tests at family-wise level `alpha` (Šidák).
pub fn sidak(alpha: f64, m: usize) -> f64 {
    1.0 - (1.0 - alpha).powf(1.0 / m as f64)
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

/// Outcome of a chi-square test.
#[derive(Debug, Clone, Copy)]
pub struct Chi2 {
    pub statistic: f64,
    pub dof: usize,
    pub p_value: f64,
}

/// Pearson's test of `observed` counts against `expected` counts per cell. Cells with
/// expected < 5 are pooled (sorted by expectation, merged until the pool reaches 5;
/// a final pool under 5 joins the smallest regular cell), so a cell that the
/// quadrature sees as empty but that an edge clips (disk boundary) is judged in the
/// pool. Samples when all pooled cells expect nothing make the p-value 0.
pub fn chi2(observed: &[f64], expected: &[f64]) -> Chi2 {
    let mut cells: Vec<(f64, f64)> = observed
        .iter()
        .copied()
        .zip(expected.iter().copied())
        .collect();
    // Samples where no pooled cell expects anything.
    let (o_small, e_small): (f64, f64) = cells
        .iter()
        .filter(|c| c.1 < 5.0)
        .fold((0.0, 0.0), |a, c| (a.0 + c.0, a.1 + c.1));
    if e_small == 0.0 && o_small > 0.0 {
        return Chi2 {
            statistic: f64::INFINITY,
            dof: 0,
            p_value: 0.0,
        };
    }
    cells.sort_by(|a, b| a.1.total_cmp(&b.1));
    let mut merged: Vec<(f64, f64)> = Vec::new();
    let (mut po, mut pe) = (0.0, 0.0);
    for (o, e) in cells {
        if e < 5.0 || pe > 0.0 && pe < 5.0 {
            po += o;
            pe += e;
            if pe >= 5.0 {
                merged.push((po, pe));
                (po, pe) = (0.0, 0.0);
            }
        } else {
            merged.push((o, e));
        }
    }
    if pe > 0.0 || po > 0.0 {
        match merged.first_mut() {
            Some(first) => {
                first.0 += po;
                first.1 += pe;
            }
            None => merged.push((po, pe)),
        }
    }
    let statistic: f64 = merged.iter().map(|&(o, e)| (o - e) * (o - e) / e).sum();
    let dof = merged.len().saturating_sub(1).max(1);
    Chi2 {
        statistic,
        dof,
        p_value: gamma_q(dof as f64 / 2.0, statistic / 2.0),
    }
}

/// A histogram over the sphere around an axis: cell (i, j) holds directions whose
/// coordinate t(θ') lies in [i, i+1) / nt and whose azimuth φ'/2π lies in [j, j+1) / np,
/// with θ' = (π/2) (2t)² for t <= 1/2 and θ' = π - (π/2) (2 - 2t)² above. Cells are
/// small near both poles, so that a narrow lobe centred on the axis (or its opposite)
/// spans several cells, and with nt even the plane orthogonal to the axis (the
/// horizon, when the axis is the normal) is a cell boundary: densities that jump
/// there (reflection vs. transmission) never straddle a cell.
pub struct SphereGrid {
    pub s: Vec3,
    pub t: Vec3,
    pub n: Vec3,
    pub nt: usize,
    pub np: usize,
}

impl SphereGrid {
    pub fn new(axis: Vec3, nt: usize, np: usize) -> SphereGrid {
        let n = axis.normalize();
        let (s, t) = n.any_orthonormal_pair();
        SphereGrid { s, t, n, nt, np }
    }

    pub fn cells(&self) -> usize {
        self.nt * self.np
    }

    /// θ'(t) and dθ'/dt.
    fn theta(tc: f64) -> (f64, f64) {
        let pi = std::f64::consts::PI;
        if tc <= 0.5 {
            (0.5 * pi * 4.0 * tc * tc, 4.0 * pi * tc)
        } else {
            let r = 1.0 - tc;
            (pi - 0.5 * pi * 4.0 * r * r, 4.0 * pi * r)
        }
    }

    fn t_of(theta: f64) -> f64 {
        let pi = std::f64::consts::PI;
        if theta <= 0.5 * pi {
            0.5 * (theta / (0.5 * pi)).sqrt()
        } else {
            1.0 - 0.5 * ((pi - theta) / (0.5 * pi)).max(0.0).sqrt()
        }
    }

    fn dir(&self, tc: f64, pc: f64) -> Vec3 {
        let theta = Self::theta(tc).0;
        let phi = 2.0 * std::f64::consts::PI * pc;
        let (st, ct) = theta.sin_cos();
        let l = Vec3::new((st * phi.cos()) as f32, (st * phi.sin()) as f32, ct as f32);
        (l.x * self.s + l.y * self.t + l.z * self.n).normalize()
    }

    pub fn cell_of(&self, d: Vec3) -> Option<usize> {
        if !d.is_finite() || d.length_squared() < 0.5 {
            return None;
        }
        let d = d.normalize();
        let z = d.dot(self.n).clamp(-1.0, 1.0) as f64;
        let tc = Self::t_of(z.acos());
        let phi = (d.dot(self.t) as f64).atan2(d.dot(self.s) as f64);
        let pc = (phi / (2.0 * std::f64::consts::PI)).rem_euclid(1.0);
        let i = ((tc * self.nt as f64) as usize).min(self.nt - 1);
        let j = ((pc * self.np as f64) as usize).min(self.np - 1);
        Some(i * self.np + j)
    }

    /// k x k midpoints per cell, and the solid angle each stands for:
    /// dω = sin θ' (dθ'/dt) dt dφ', φ' = 2π p.
    pub fn quadrature(&self, k: usize) -> (Vec<[f32; 4]>, Vec<f64>) {
        let cells: Vec<usize> = (0..self.cells()).collect();
        self.quadrature_of(&cells, k)
    }

    /// As [`SphereGrid::quadrature`], for the given cells only (in that order).
    pub fn quadrature_of(&self, cells: &[usize], k: usize) -> (Vec<[f32; 4]>, Vec<f64>) {
        let (nt, np) = (self.nt * k, self.np * k);
        let mut dirs = Vec::with_capacity(cells.len() * k * k);
        let mut w = Vec::with_capacity(cells.len() * k * k);
        let pi = std::f64::consts::PI;
        for &c in cells {
            let (i, j) = (c / self.np, c % self.np);
            for a in 0..k {
                for b in 0..k {
                    let tc = (i * k + a) as f64 / nt as f64 + 0.5 / nt as f64;
                    let pc = (j * k + b) as f64 / np as f64 + 0.5 / np as f64;
                    let d = self.dir(tc, pc);
                    dirs.push([d.x, d.y, d.z, 0.0]);
                    let (theta, dtheta) = Self::theta(tc);
                    w.push(theta.sin() * dtheta * 2.0 * pi / (nt * np) as f64);
                }
            }
        }
        (dirs, w)
    }

    /// Sums per-point values (pdf x weight) into per-cell integrals.
    pub fn integrate(&self, k: usize, pdf: &[f64], w: &[f64]) -> Vec<f64> {
        let per = k * k;
        (0..self.cells())
            .map(|c| (0..per).map(|q| pdf[c * per + q] * w[c * per + q]).sum())
            .collect()
    }
}

/// GPU runner for `shaders/tests/sample_bsdf.comp`.
pub struct BsdfProbe {
    pub device: Device,
    layout: BindingLayout,
    kernel: Kernel,
}

/// One `bsdf_sample` result with eval and pdf at its direction.
#[derive(Debug, Clone, Copy)]
pub struct Sampled {
    pub wi: Vec3,
    pub pdf: f32,
    pub weight: Vec3,
    pub flags: u32,
    pub eval: Vec3,
    pub pdf_eval: f32,
}

pub const FLAG_REFLECTION: u32 = 1;
pub const FLAG_TRANSMISSION: u32 = 2;
pub const FLAG_DELTA: u32 = 4;
/// Straight through without bending (thin dielectric).
pub const FLAG_NULL: u32 = 8;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct BsdfPush {
    wo: [f32; 4],
    mode: u32,
    count: u32,
    seed: u32,
    pad: u32,
}

impl BsdfProbe {
    pub fn new() -> BsdfProbe {
        let device = super::device();
        let layout = BindingLayout::new(&device, &[3], 32).expect("layout");
        let kernel = Kernel::new(
            &device,
            "sample_bsdf",
            shaders::TESTS_SAMPLE_BSDF,
            &layout,
            &[],
        )
        .expect("kernel");
        BsdfProbe {
            device,
            layout,
            kernel,
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn run(
        &self,
        rec: &BsdfRecord,
        wo: Vec3,
        mode: u32,
        count: u32,
        seed: u32,
        dirs: &[[f32; 4]],
        out_vec4s: usize,
    ) -> Vec<[f32; 4]> {
        let d = &self.device;
        let records = Buffer::from_slice(d, "record", std::slice::from_ref(rec)).expect("buffer");
        let dummy = [[0f32; 4]];
        let dir_buf = Buffer::from_slice(d, "dirs", if dirs.is_empty() { &dummy } else { dirs })
            .expect("buffer");
        let out =
            Buffer::new(d, "out", (out_vec4s * 16).max(16) as u64, Location::Gpu).expect("buffer");
        let set = DescriptorSet::new(&self.layout, 0, &[&records, &dir_buf, &out]).expect("set");
        let push = BsdfPush {
            wo: [wo.x, wo.y, wo.z, 0.0],
            mode,
            count,
            seed,
            pad: 0,
        };
        let mut cmd = CommandList::new(d).expect("commands");
        cmd.dispatch(
            &self.kernel,
            &[&set],
            bytemuck::bytes_of(&push),
            [count.div_ceil(64), 1, 1],
        );
        cmd.barrier();
        cmd.submit_and_wait().expect("submit");
        let mut v: Vec<[f32; 4]> = out.read(d).expect("read");
        v.truncate(out_vec4s);
        v
    }

    /// `count` samples of `bsdf_sample(rec, wo)` (u from a hash of the index and seed).
    pub fn sample(&self, rec: &BsdfRecord, wo: Vec3, count: u32, seed: u32) -> Vec<Sampled> {
        let raw = self.run(rec, wo, 0, count, seed, &[], 3 * count as usize);
        raw.chunks_exact(3)
            .map(|c| Sampled {
                wi: Vec3::new(c[0][0], c[0][1], c[0][2]),
                pdf: c[0][3],
                weight: Vec3::new(c[1][0], c[1][1], c[1][2]),
                flags: c[1][3].to_bits(),
                eval: Vec3::new(c[2][0], c[2][1], c[2][2]),
                pdf_eval: c[2][3],
            })
            .collect()
    }

    /// (bsdf_eval, bsdf_pdf) at each direction.
    pub fn eval(&self, rec: &BsdfRecord, wo: Vec3, dirs: &[[f32; 4]]) -> Vec<(Vec3, f32)> {
        let raw = self.run(rec, wo, 1, dirs.len() as u32, 0, dirs, dirs.len());
        raw.iter()
            .map(|v| (Vec3::new(v[0], v[1], v[2]), v[3]))
            .collect()
    }
}

/// GPU runner for `shaders/tests/warp.comp`.
pub struct WarpProbe {
    pub device: Device,
    layout: BindingLayout,
    kernel: Kernel,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct WarpPush {
    param: [f32; 4],
    mf: [f32; 4],
    warp: u32,
    mode: u32,
    count: u32,
    seed: u32,
}

/// Which warp to run, with its parameters.
#[derive(Debug, Clone, Copy)]
pub enum Warp {
    Disk,
    UniformHemisphere,
    CosineHemisphere,
    UniformSphere,
    Cap {
        cos_max: f32,
    },
    Triangle,
    /// Microfacet normals: type (0 Beckmann, 1 GGX), alpha_u, alpha_v, wo.
    Microfacet {
        ty: u32,
        alpha_u: f32,
        alpha_v: f32,
        wo: Vec3,
    },
}

impl Warp {
    fn push(&self, mode: u32, count: u32, seed: u32) -> WarpPush {
        let (warp, param, mf) = match *self {
            Warp::Disk => (0, [0.0; 4], [0.0; 4]),
            Warp::UniformHemisphere => (1, [0.0; 4], [0.0; 4]),
            Warp::CosineHemisphere => (2, [0.0; 4], [0.0; 4]),
            Warp::UniformSphere => (3, [0.0; 4], [0.0; 4]),
            Warp::Cap { cos_max } => (4, [cos_max, 0.0, 0.0, 0.0], [0.0; 4]),
            Warp::Triangle => (5, [0.0; 4], [0.0; 4]),
            Warp::Microfacet {
                ty,
                alpha_u,
                alpha_v,
                wo,
            } => (
                6,
                [wo.x, wo.y, wo.z, 0.0],
                [ty as f32, alpha_u, alpha_v, 0.0],
            ),
        };
        WarpPush {
            param,
            mf,
            warp,
            mode,
            count,
            seed,
        }
    }
}

impl WarpProbe {
    pub fn new() -> WarpProbe {
        let device = super::device();
        let layout = BindingLayout::new(&device, &[2], 48).expect("layout");
        let kernel =
            Kernel::new(&device, "warp", shaders::TESTS_WARP, &layout, &[]).expect("kernel");
        WarpProbe {
            device,
            layout,
            kernel,
        }
    }

    fn run(&self, push: WarpPush, points: &[[f32; 4]]) -> Vec<[f32; 4]> {
        let d = &self.device;
        let dummy = [[0f32; 4]];
        let pts = Buffer::from_slice(d, "points", if points.is_empty() { &dummy } else { points })
            .expect("buffer");
        let out =
            Buffer::new(d, "out", (push.count as u64 * 16).max(16), Location::Gpu).expect("buffer");
        let set = DescriptorSet::new(&self.layout, 0, &[&pts, &out]).expect("set");
        let mut cmd = CommandList::new(d).expect("commands");
        cmd.dispatch(
            &self.kernel,
            &[&set],
            bytemuck::bytes_of(&push),
            [push.count.div_ceil(64), 1, 1],
        );
        cmd.barrier();
        cmd.submit_and_wait().expect("submit");
        let mut v: Vec<[f32; 4]> = out.read(d).expect("read");
        v.truncate(push.count as usize);
        v
    }

    /// `count` warped points (xyz) with the pdf the kernel computes at each.
    pub fn sample(&self, warp: Warp, count: u32, seed: u32) -> Vec<[f32; 4]> {
        self.run(warp.push(0, count, seed), &[])
    }

    /// The warp's pdf at each point.
    pub fn pdf(&self, warp: Warp, points: &[[f32; 4]]) -> Vec<f64> {
        self.run(warp.push(1, points.len() as u32, 0), points)
            .iter()
            .map(|v| v[0] as f64)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gamma_q_known_values() {
        // Q(1, x) = e^-x; chi-square with 2 dof: P(X² > 5.991) = 0.05;
        // 10 dof: P(X² > 23.209) = 0.01.
        assert!((gamma_q(1.0, 2.0) - (-2.0f64).exp()).abs() < 1e-12);
        assert!((gamma_q(1.0, 5.991 / 2.0) - 0.05).abs() < 1e-4);
        assert!((gamma_q(5.0, 23.209 / 2.0) - 0.01).abs() < 1e-4);
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-12);
    }
}
