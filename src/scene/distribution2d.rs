//! Piecewise-constant 2-D distributions over a W x H grid of cells covering [0, 1]²
//! (Pharr, Jakob, Humphreys, PBR 3rd ed., sec. 13.6.7, "Piecewise-Constant 2D
//! Distributions"): a marginal CDF picks the row, that row's conditional CDF the
//! column, and the point is uniform in the cell. Environment maps (`scene::envmap`)
//! and textured area emitters (`scene::textured_emitter`) sample by one.
//!
//! The GPU mirror is `shaders/sampling/distribution2d.glsl`; [`Distribution2D::cdf`] is
//! its layout in the distribution buffer: H + 1 marginal values (0 first, 1 last),
//! then per row W + 1 conditional values.

use glam::Vec2;

/// A 2-D distribution in the GPU's layout.
#[derive(Debug, Clone, PartialEq)]
pub struct Distribution2D {
    pub width: u32,
    pub height: u32,
    pub cdf: Vec<f32>,
}

impl Distribution2D {
    /// The distribution whose cell (i, j) has probability in proportion to
    /// `weights[j W + i]` (non-negative). A row of zero weight gets uniform
    /// conditionals and, if every weight is zero, uniform marginals: the CDFs stay
    /// well formed, and such rows are never picked unless all are.
    pub fn from_weights(width: u32, height: u32, weights: &[f64]) -> Distribution2D {
        let (w, h) = (width as usize, height as usize);
        assert_eq!(weights.len(), w * h, "one weight per cell");
        let mut cdf = vec![0f32; (h + 1) + h * (w + 1)];
        let rows: Vec<f64> = (0..h)
            .map(|j| weights[j * w..(j + 1) * w].iter().sum())
            .collect();
        let total: f64 = rows.iter().sum();
        let mut acc = 0f64;
        for j in 0..h {
            acc += if total > 0.0 {
                rows[j] / total
            } else {
                1.0 / h as f64
            };
            cdf[j + 1] = acc as f32;
            let base = h + 1 + j * (w + 1);
            let mut racc = 0f64;
            for i in 0..w {
                racc += if rows[j] > 0.0 {
                    weights[j * w + i] / rows[j]
                } else {
                    1.0 / w as f64
                };
                cdf[base + i + 1] = racc as f32;
            }
            cdf[base + w] = 1.0;
        }
        cdf[h] = 1.0;
        Distribution2D { width, height, cdf }
    }

    /// Probability of cell (i, j), from the stored CDFs as the GPU computes it.
    pub fn cell_probability(&self, i: u32, j: u32) -> f64 {
        let (m, c) = self.differences(i, j);
        m as f64 * c as f64
    }

    /// [`Self::cell_probability`] in the GPU's float arithmetic: the difference of two
    /// neighbouring CDF values is exact in floats (Sterbenz), so this is the
    /// probability with which sampling picks the cell, to the resolution of the
    /// uniform numbers.
    pub fn cell_probability_f32(&self, i: u32, j: u32) -> f32 {
        let (m, c) = self.differences(i, j);
        m * c
    }

    /// The marginal and conditional probabilities of cell (i, j): differences of
    /// neighbouring CDF values.
    fn differences(&self, i: u32, j: u32) -> (f32, f32) {
        let (w, h) = (self.width as usize, self.height as usize);
        let (i, j) = (i as usize, j as usize);
        let base = h + 1 + j * (w + 1);
        (
            self.cdf[j + 1] - self.cdf[j],
            self.cdf[base + i + 1] - self.cdf[base + i],
        )
    }

    /// Index k in [0, n) with cdf[k] <= x < cdf[k + 1] among the n + 1 values at
    /// `base` (the last such k: never a zero-probability entry).
    fn find(&self, base: usize, n: usize, x: f32) -> usize {
        let (mut lo, mut hi) = (0, n);
        while lo + 1 < hi {
            let mid = (lo + hi) / 2;
            if self.cdf[base + mid] <= x {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    }

    /// The cell that (u.x: row, u.y: column) picks and the position of u within it,
    /// in [0, 1]² (x along the row, y across rows): the CPU reference of
    /// `dist2d_sample_cell`.
    pub fn sample_cell(&self, u: Vec2) -> ((u32, u32), Vec2) {
        let (w, h) = (self.width as usize, self.height as usize);
        let j = self.find(0, h, u.x);
        let (m0, m1) = (self.cdf[j], self.cdf[j + 1]);
        let base = h + 1 + j * (w + 1);
        let i = self.find(base, w, u.y);
        let (c0, c1) = (self.cdf[base + i], self.cdf[base + i + 1]);
        let f = Vec2::new(
            ((u.y - c0) / (c1 - c0)).clamp(0.0, 1.0),
            ((u.x - m0) / (m1 - m0)).clamp(0.0, 1.0),
        );
        ((i as u32, j as u32), f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_get_their_weights_share() {
        let weights: Vec<f64> = (0..12)
            .map(|k| [0.0, 1.0, 3.0, 0.5][k % 4] * (k / 4 + 1) as f64)
            .collect();
        let d = Distribution2D::from_weights(4, 3, &weights);
        let total: f64 = weights.iter().sum();
        let mut sum = 0.0;
        for j in 0..3 {
            for i in 0..4 {
                let p = d.cell_probability(i, j);
                assert!((p - weights[(j * 4 + i) as usize] / total).abs() < 1e-6);
                sum += p;
            }
        }
        assert!((sum - 1.0).abs() < 1e-6, "{sum}");
    }

    #[test]
    fn sampling_inverts_the_cdfs() {
        let weights = [1.0, 0.0, 2.0, 4.0, 0.0, 0.0, 1.0, 1.0, 3.0];
        let d = Distribution2D::from_weights(3, 3, &weights);
        let n = 300;
        let mut count = [0usize; 9];
        for a in 0..n {
            for b in 0..n {
                let u = Vec2::new((a as f32 + 0.5) / n as f32, (b as f32 + 0.5) / n as f32);
                let ((i, j), f) = d.sample_cell(u);
                assert!(f.cmpge(Vec2::ZERO).all() && f.cmple(Vec2::ONE).all());
                count[(j * 3 + i) as usize] += 1;
            }
        }
        for (k, c) in count.iter().enumerate() {
            let p = d.cell_probability(k as u32 % 3, k as u32 / 3);
            assert!(
                (*c as f64 / (n * n) as f64 - p).abs() < 2.0 / n as f64,
                "cell {k}: {c} of {}, p {p}",
                n * n
            );
        }
        // Zero-weight cells are never picked.
        assert_eq!(count[1] + count[4] + count[5], 0);
    }

    #[test]
    fn all_zero_weights_are_uniform() {
        let d = Distribution2D::from_weights(2, 2, &[0.0; 4]);
        for j in 0..2 {
            for i in 0..2 {
                assert_eq!(d.cell_probability(i, j), 0.25);
            }
        }
    }
}
