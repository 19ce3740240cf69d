//! The rough coating's integrals exactly as Mitsuba 3 computes them for `roughplastic`
//! (`eval_transmittance` and `eval_reflectance` in include/mitsuba/render/microfacet.h):
//! over microfacet normals drawn from the visible-normal distribution of the incident
//! direction (its `sample` with `sample_visible`, by Mitsuba's own warps: the
//! concentric-disk construction for GGX, the erf-domain Newton inversion for
//! Beckmann), on a Gauss-Legendre grid of the unit square: 32² nodes when η > 1, 128²
//! otherwise.
//!
//! Integrand per normal m (wi the incident direction, F the dielectric Fresnel
//! reflectance at wi·m):
//! - transmittance: (1 - F) G1(t, m), t = wi refracted through m, counted where t is
//!   on the other side of the surface (light that enters and is not shadowed);
//! - reflectance: F G1(r, m), r = wi mirrored about m, counted where r is above.
//!
//! The transmittance is not 1 - reflectance: the light the reflected and refracted
//! rays lose to shadowing is lost (Smith's single scattering), so for rough coatings
//! T + R < 1. Before issue 39 wavetrace tabulated T = 1 - R, which gave the diffuse
//! base the shadowed energy back (+15% at α = 1).
//!
//! Mitsuba evaluates this in single precision; here in f64 (the tables agree to about
//! 1e-6).

use glam::DVec3;

use super::microfacet::{smith_g1, Distribution};

/// Mitsuba's `quad::gauss_legendre(n)`: nodes in [-1, 1] and weights summing to 2.
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            // Newton on P_n from the Chebyshev guess; P_n and P_n' by the recurrence.
            let mut x = -((2 * i + 1) as f64 / (2 * n) as f64 * std::f64::consts::PI).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    (p0, p1) = (p1, p2);
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let step = p1 / dp;
                x -= step;
                if step.abs() <= 4.0 * x.abs() * f64::EPSILON {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

use libm::erf;

/// Inverse of erf on (-1, 1) (±∞ at ±1): Giles' single-precision approximation
/// ("Approximating the erfinv function", GPU Computing Gems 2011), then two Newton
/// steps on libm's erf (to about 1e-15).
fn erfinv(y: f64) -> f64 {
    if y <= -1.0 {
        return f64::NEG_INFINITY;
    }
    if y >= 1.0 {
        return f64::INFINITY;
    }
    let mut w = -((1.0 - y) * (1.0 + y)).ln();
    let p = if w < 5.0 {
        w -= 2.5;
        [
            3.432_739_39e-7,
            -3.523_387_7e-6,
            -4.391_506_54e-6,
            2.185_808_7e-4,
            -1.253_725_03e-3,
            -4.177_681_64e-3,
            2.466_407_27e-1,
            1.501_409_41,
        ]
        .iter()
        .fold(2.810_226_36e-8, |p, c| c + p * w)
    } else {
        w = w.sqrt() - 3.0;
        [
            1.009_505_58e-4,
            1.349_343_22e-3,
            -3.673_428_44e-3,
            5.739_507_73e-3,
            -7.622_461_3e-3,
            9.438_870_47e-3,
            1.001_674_06,
            2.832_976_82,
        ]
        .iter()
        .fold(-2.002_142_57e-4, |p, c| c + p * w)
    };
    let mut x = p * y;
    for _ in 0..2 {
        let d = std::f64::consts::FRAC_2_SQRT_PI * (-x * x).exp();
        if d > 0.0 {
            x -= (erf(x) - y) / d;
        }
    }
    x
}

/// Mitsuba's `warp::square_to_uniform_disk_concentric` (Shirley and Chiu).
fn disk_concentric(sx: f64, sy: f64) -> (f64, f64) {
    let (x, y) = (2.0 * sx - 1.0, 2.0 * sy - 1.0);
    if x == 0.0 && y == 0.0 {
        return (0.0, 0.0);
    }
    let q = x.abs() < y.abs();
    let (r, rp) = if q { (y, x) } else { (x, y) };
    let mut phi = 0.25 * std::f64::consts::PI * rp / r;
    if q {
        phi = 0.5 * std::f64::consts::PI - phi;
    }
    (r * phi.cos(), r * phi.sin())
}

/// Mitsuba's `sample_visible_11`: a slope of the visible normals of the α = 1
/// distribution for an incident direction of cos θ = `cos_theta`.
fn sample_visible_11(d: Distribution, cos_theta: f64, sx: f64, sy: f64) -> (f64, f64) {
    match d {
        Distribution::Beckmann => {
            let tan_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt() / cos_theta;
            let cot_theta = 1.0 / tan_theta;
            let maxval = erf(cot_theta);
            let (sx, sy) = (sx.clamp(1e-6, 1.0 - 1e-6), sy.clamp(1e-6, 1.0 - 1e-6));
            let mut x = maxval - (maxval + 1.0) * erf((-sx.ln()).sqrt());
            let inv_sqrt_pi = 1.0 / std::f64::consts::PI.sqrt();
            let tail = if tan_theta == 0.0 {
                0.0
            } else {
                inv_sqrt_pi * tan_theta * (-cot_theta * cot_theta).exp()
            };
            let sx = sx * (1.0 + maxval + tail);
            for _ in 0..3 {
                let slope = erfinv(x);
                let value = 1.0 + x + inv_sqrt_pi * tan_theta * (-slope * slope).exp() - sx;
                let derivative = 1.0 - slope * tan_theta;
                x -= value / derivative;
            }
            (erfinv(x), erfinv(2.0 * sy - 1.0))
        }
        Distribution::Ggx => {
            let (px, py) = disk_concentric(sx, sy);
            let s = 0.5 * (1.0 + cos_theta);
            let py = (1.0 - px * px).max(0.0).sqrt() * (1.0 - s) + py * s;
            let z = (1.0 - px * px - py * py).max(0.0).sqrt();
            let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
            let norm = 1.0 / (sin_theta * py + cos_theta * z);
            ((cos_theta * py - sin_theta * z) * norm, px * norm)
        }
    }
}

/// Mitsuba's visible-normal `sample` for wi in the xz-plane (x >= 0), isotropic α.
fn sample_visible(d: Distribution, alpha: f64, wi: DVec3, sx: f64, sy: f64) -> DVec3 {
    // Stretch wi; it stays in the xz-plane, so its φ is 0 (cos φ = 1, sin φ = 0).
    let wp = DVec3::new(alpha * wi.x, 0.0, wi.z).normalize();
    let (slope_x, slope_y) = sample_visible_11(d, wp.z, sx, sy);
    DVec3::new(-slope_x * alpha, -slope_y * alpha, 1.0).normalize()
}

/// Mitsuba's `fresnel(cos_theta_i, eta)` for cos_theta_i >= 0: (F, cos θt <= 0).
fn fresnel(cos_i: f64, eta: f64) -> (f64, f64) {
    let eta_ti = 1.0 / eta;
    let ct2 = 1.0 - (1.0 - cos_i * cos_i) * eta_ti * eta_ti;
    let ct = ct2.max(0.0).sqrt();
    if eta == 1.0 || cos_i == 0.0 {
        return (if eta == 1.0 { 0.0 } else { 1.0 }, -ct);
    }
    let a_s = (cos_i - eta * ct) / (cos_i + eta * ct);
    let a_p = (ct - eta * cos_i) / (ct + eta * cos_i);
    (0.5 * (a_s * a_s + a_p * a_p), -ct)
}

/// Mitsuba's `eval_transmittance` (`transmit`) or `eval_reflectance` of the rough
/// interface of relative index `eta` at incident cos θ = `mu` (> 0).
pub fn mitsuba_rough_interface(
    d: Distribution,
    alpha: f64,
    mu: f64,
    eta: f64,
    transmit: bool,
) -> f64 {
    let res = if eta > 1.0 { 32 } else { 128 };
    let nodes = gauss_legendre(res);
    let wi = DVec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
    let mut sum = 0.0;
    for &(ny, wy) in &nodes {
        for &(nx, wx) in &nodes {
            let m = sample_visible(d, alpha, wi, 0.5 * nx + 0.5, 0.5 * ny + 0.5);
            let wim = wi.dot(m);
            let (f, cos_t) = fresnel(wim, eta);
            let value = if transmit {
                let eta_ti = 1.0 / eta;
                let t = m * (wim * eta_ti + cos_t) - wi * eta_ti;
                if t.z * wi.z >= 0.0 {
                    0.0
                } else {
                    smith_g1(d, alpha, t, m) * (1.0 - f)
                }
            } else {
                let r = 2.0 * wim * m - wi;
                if r.z <= 0.0 {
                    0.0
                } else {
                    smith_g1(d, alpha, r, m) * f
                }
            };
            sum += value * wx * wy * 0.25;
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadrature_and_special_functions() {
        let gl = gauss_legendre(32);
        assert!((gl.iter().map(|p| p.1).sum::<f64>() - 2.0).abs() < 1e-13);
        // Exact for x^62: ∫ x^62 dx over [-1, 1] = 2/63.
        let i: f64 = gl.iter().map(|&(x, w)| w * x.powi(62)).sum();
        assert!((i - 2.0 / 63.0).abs() < 1e-13, "{i}");
        for (x, e) in [
            (0.5, 0.520_499_877_813_046_5),
            (2.0, 0.995_322_265_018_952_7),
            (3.0, 0.999_977_909_503_001_4),
        ] {
            assert!((erf(x) - e).abs() < 1e-14, "erf({x}) = {}", erf(x));
            assert!((erf(-x) + e).abs() < 1e-14);
            assert!((erfinv(e) - x).abs() < 1e-9, "erfinv({e}) = {}", erfinv(e));
        }
    }
}
