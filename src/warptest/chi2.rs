//! Pearson's chi-square goodness of fit, as Nori's warptest (`src/warptest.cpp`,
//! `chi2test.cpp`) and Mitsuba's `mitsuba.chi2` use it.
//!
//! Cells expecting fewer than 5 samples are pooled into one, the statistic
//! X² = Σ (O − E)² / E has (cells − 1) degrees of freedom, and its p-value is
//! Q(dof/2, X²/2), the regularized upper incomplete gamma function.

use crate::image::metrics::ln_gamma;

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

/// Per-test significance for `m` tests at family-wise level `alpha` (Šidák).
pub fn sidak(alpha: f64, m: usize) -> f64 {
    1.0 - (1.0 - alpha).powf(1.0 / m as f64)
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

    #[test]
    fn pooling_and_empty_cells() {
        // Exact fit: X² = 0, p = 1.
        let r = chi2(&[10.0, 20.0, 30.0], &[10.0, 20.0, 30.0]);
        assert_eq!(r.statistic, 0.0);
        assert!((r.p_value - 1.0).abs() < 1e-12);
        // Three cells under 5 pool into one of 6: dof 1 with the 20-cell.
        let r = chi2(&[2.0, 2.0, 2.0, 20.0], &[2.0, 2.0, 2.0, 20.0]);
        assert_eq!(r.dof, 1);
        // Samples where nothing is expected: rejected outright.
        let r = chi2(&[0.0, 3.0, 50.0], &[0.0, 0.0, 53.0]);
        assert_eq!(r.p_value, 0.0);
    }
}
