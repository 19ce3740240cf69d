//! Environment maps: Mitsuba 3's `envmap` lat-long convention, bilinear evaluation,
//! and the piecewise-constant 2D distribution that importance-samples it. The GLSL
//! mirror is `shaders/emitter/envmap.glsl`; this is its CPU reference.
//!
//! Convention (measured on Mitsuba 3.9.1's `envmap`): a direction d in the map's own
//! frame has u = atan2(d.x, −d.z) / 2π (wrapped to [0, 1)) and v = acos(d.y) / π, so
//! +y is up, the image centre (u = ½) lies along +z and its left and right edges
//! along −z. Lookups are bilinear, periodic in u with texel i centred at
//! u = (i + ½)/W, and in v run from row 0 at the north pole (v = 0) to row H − 1 at
//! the south pole (v = 1): y = v (H − 1).
//!
//! Sampling (PBR 3rd ed., sec. 14.2.4, "Infinite Area Lights"): a W x H grid of cells
//! over (u, v); cell (i, j) has weight (largest luminance among the texels its
//! bilinear lookups touch) x sin θ at its centre, so the density is positive wherever
//! the map is. A marginal CDF picks the row, the row's conditional CDF the column,
//! and the point is uniform in the cell. Density per unit solid angle:
//! p(ω) = p(u, v) / (2π² sin θ).

use glam::{Mat3, Vec2, Vec3};

use super::distribution2d::Distribution2D;

/// Lat-long coordinates of unit direction `d` given in the map's frame.
pub fn direction_to_uv(d: Vec3) -> Vec2 {
    let mut u = d.x.atan2(-d.z) * (0.5 * std::f32::consts::FRAC_1_PI);
    if u < 0.0 {
        u += 1.0;
    }
    let v = d.y.clamp(-1.0, 1.0).acos() * std::f32::consts::FRAC_1_PI;
    Vec2::new(u, v)
}

/// The unit direction (map frame) at lat-long coordinates `uv`.
pub fn uv_to_direction(uv: Vec2) -> Vec3 {
    let (st, ct) = (uv.y * std::f32::consts::PI).sin_cos();
    let (sp, cp) = (uv.x * std::f32::consts::TAU).sin_cos();
    Vec3::new(st * sp, ct, -st * cp)
}

/// The map at `uv`: bilinear, periodic in u, pole to pole in v.
pub fn eval(width: u32, height: u32, texels: &[[f32; 3]], uv: Vec2) -> Vec3 {
    let x = uv.x * width as f32 - 0.5;
    let y = uv.y * (height - 1) as f32;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let texel = |i: i32, j: i32| {
        let i = i.rem_euclid(width as i32) as u32;
        let j = j.clamp(0, height as i32 - 1) as u32;
        Vec3::from(texels[(j * width + i) as usize])
    };
    let (x0, y0) = (x0 as i32, y0 as i32);
    let a = texel(x0, y0).lerp(texel(x0 + 1, y0), fx);
    let b = texel(x0, y0 + 1).lerp(texel(x0 + 1, y0 + 1), fx);
    a.lerp(b, fy)
}

/// Luminance of linear sRGB (Rec. 709).
pub fn luminance(c: Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// The sampling distribution of a map: `cdf` is its [`Distribution2D`]'s (the
/// marginal CDF over rows, then each row's conditional CDF over columns, as in the
/// GPU buffer).
#[derive(Debug, Clone, PartialEq)]
pub struct Distribution {
    pub width: u32,
    pub height: u32,
    pub cdf: Vec<f32>,
    /// ∫ L dω / 4π: the map's mean luminance over the sphere (before `scale`).
    pub mean_luminance: f64,
}

impl Distribution {
    /// `importance` false: every cell weighs sin θ alone (uniform over the sphere).
    pub fn build(width: u32, height: u32, texels: &[[f32; 3]], importance: bool) -> Distribution {
        let (w, h) = (width as usize, height as usize);
        let lum: Vec<f32> = texels.iter().map(|t| luminance(Vec3::from(*t))).collect();
        let mut weights = vec![0f64; w * h];
        let mut mean = 0f64;
        for j in 0..h {
            // Rows of texels the lookups in this cell's v range touch.
            let y_lo = (j as f32 / h as f32) * (h - 1) as f32;
            let y_hi = ((j + 1) as f32 / h as f32) * (h - 1) as f32;
            let (r0, r1) = (y_lo.floor() as usize, (y_hi.ceil() as usize).min(h - 1));
            let theta = (j as f64 + 0.5) / h as f64 * std::f64::consts::PI;
            let sin = theta.sin();
            for i in 0..w {
                let mut m = 0f32;
                for r in r0..=r1 {
                    for di in [w - 1, 0, 1] {
                        m = m.max(lum[r * w + (i + di) % w]);
                    }
                }
                weights[j * w + i] = if importance { m.max(0.0) as f64 } else { 1.0 } * sin;
                let uv = Vec2::new((i as f32 + 0.5) / w as f32, (j as f32 + 0.5) / h as f32);
                mean += luminance(eval(width, height, texels, uv)) as f64 * sin;
            }
        }
        // Cell area in (u, v) is 1/(W H); dω = 2π² sin θ du dv; divide by 4π.
        let mean_luminance = mean * 2.0 * std::f64::consts::PI * std::f64::consts::PI
            / (w * h) as f64
            / (4.0 * std::f64::consts::PI);
        let cdf = Distribution2D::from_weights(width, height, &weights).cdf;
        Distribution {
            width,
            height,
            cdf,
            mean_luminance,
        }
    }

    /// Probability of cell (i, j), from the stored CDFs as the GPU computes it.
    pub fn cell_probability(&self, i: u32, j: u32) -> f64 {
        let (w, h) = (self.width as usize, self.height as usize);
        let (i, j) = (i as usize, j as usize);
        let base = h + 1 + j * (w + 1);
        (self.cdf[j + 1] - self.cdf[j]) as f64
            * (self.cdf[base + i + 1] - self.cdf[base + i]) as f64
    }

    /// Density per unit solid angle of sampling direction `d` (map frame).
    pub fn pdf(&self, d: Vec3) -> f64 {
        let uv = direction_to_uv(d);
        let i = ((uv.x * self.width as f32) as u32).min(self.width - 1);
        let j = ((uv.y * self.height as f32) as u32).min(self.height - 1);
        let sin = (1.0 - (d.y as f64).powi(2)).max(0.0).sqrt();
        if sin <= 0.0 {
            return 0.0;
        }
        let p_uv = self.cell_probability(i, j) * (self.width * self.height) as f64;
        p_uv / (2.0 * std::f64::consts::PI * std::f64::consts::PI * sin)
    }
}

/// Checks that `m` (an envmap's `to_world`) is a rotation, possibly uniformly scaled,
/// and returns the rotation.
pub fn rotation_of(m: Mat3) -> Option<Mat3> {
    let s = m.x_axis.length();
    if !(s > 0.0 && s.is_finite()) {
        return None;
    }
    let r = m * (1.0 / s);
    let err = (r.transpose() * r - Mat3::IDENTITY)
        .to_cols_array()
        .iter()
        .fold(0f32, |a, v| a.max(v.abs()));
    (err < 1e-3 && r.determinant() > 0.0).then_some(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 8 x 4 map with texel (x, y) = (x + 1, y + 1, 1): the values Mitsuba 3.9.1's
    /// envmap returns looking along these directions.
    #[test]
    fn lookups_match_mitsuba() {
        let texels: Vec<[f32; 3]> = (0..4)
            .flat_map(|y| (0..8).map(move |x| [x as f32 + 1.0, y as f32 + 1.0, 1.0]))
            .collect();
        let look = |d: Vec3| eval(8, 4, &texels, direction_to_uv(d.normalize()));
        for (d, want) in [
            (Vec3::Y, [4.5, 1.0]),
            (-Vec3::Y, [4.5, 4.0]),
            (-Vec3::Z, [4.5, 2.5]),
            (Vec3::X, [2.5, 2.5]),
            (-Vec3::X, [6.5, 2.5]),
            (Vec3::new(0.7, 0.1, -0.7), [1.5, 2.40386]),
            (Vec3::new(0.05, 0.5, -1.0), [4.05474, 2.05773]),
            (Vec3::new(-0.05, 0.5, -1.0), [4.94526, 2.05773]),
        ] {
            let v = look(d);
            assert!(
                (v.x - want[0]).abs() < 1e-3 && (v.y - want[1]).abs() < 1e-3,
                "{d}: {v}, Mitsuba {want:?}"
            );
        }
    }

    #[test]
    fn uv_and_direction_are_inverse() {
        for k in 0..100 {
            let uv = Vec2::new(
                (k as f32 * 0.618).fract(),
                (k as f32 * 0.01 + 0.005).min(0.995),
            );
            let back = direction_to_uv(uv_to_direction(uv));
            assert!((back - uv).abs().max_element() < 1e-4, "{uv} -> {back}");
        }
    }

    #[test]
    fn distribution_is_normalized_and_covers_the_map() {
        let mut texels = vec![[0.1f32; 3]; 16 * 8];
        texels[3 * 16 + 5] = [100.0; 3];
        let d = Distribution::build(16, 8, &texels, true);
        let total: f64 = (0..8)
            .flat_map(|j| (0..16).map(move |i| (i, j)))
            .map(|(i, j)| d.cell_probability(i, j))
            .sum();
        assert!((total - 1.0).abs() < 1e-5, "{total}");
        // The bright texel's cell is the likeliest.
        assert!(d.cell_probability(5, 3) > 10.0 * d.cell_probability(12, 3));
        for j in 0..8 {
            for i in 0..16 {
                assert!(d.cell_probability(i, j) > 0.0);
            }
        }
    }
}
