//! The cells a chi-square test of a sampler counts its samples in, and the quadrature
//! that gives each cell's expected count from the sampler's pdf.
//!
//! A test histograms N samples over the cells and compares with expected counts
//! N ∫_cell pdf, integrated numerically from the pdf evaluated at k x k midpoints per
//! cell ([`Grid::quadrature`], [`Grid::integrate`]).

use glam::{Vec2, Vec3};

/// A histogram over the sphere around an axis: cell (i, j) holds directions whose
/// coordinate t(θ') lies in [i, i+1) / nt and whose azimuth φ'/2π lies in [j, j+1) / np,
/// with θ' = (π/2) (2t)² for t <= 1/2 and θ' = π - (π/2) (2 - 2t)² above. Cells are
/// small near both poles, so that a narrow lobe centred on the axis (or its opposite)
/// spans several cells, and with nt even the plane orthogonal to the axis (the
/// horizon, when the axis is the normal) is a cell boundary: densities that jump
/// there (reflection vs. transmission) never straddle a cell.
#[derive(Debug, Clone)]
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

    /// The cell of direction `d` (any length but near zero, finite).
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

    /// Sums per-point values (pdf x weight) of [`SphereGrid::quadrature`] with `k`
    /// into per-cell integrals.
    pub fn integrate(&self, k: usize, pdf: &[f64], w: &[f64]) -> Vec<f64> {
        integrate(self.cells(), k, pdf, w)
    }
}

/// Per-cell sums of pdf x weight over k x k points per cell (cell-major).
fn integrate(cells: usize, k: usize, pdf: &[f64], w: &[f64]) -> Vec<f64> {
    let per = k * k;
    (0..cells)
        .map(|c| (0..per).map(|q| pdf[c * per + q] * w[c * per + q]).sum())
        .collect()
}

/// Coordinates on [0, 1]² for a planar domain, chosen so that the domain's edge is the
/// square's edge (a density jumping to 0 inside a cell would defeat the quadrature).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Chart {
    /// Unit disk: (r², φ / 2π); dA = π du dv.
    Disk,
    /// Triangle b0, b1 >= 0, b0 + b1 <= 1: (b0, b1 / (1 - b0)); dA = (1 - b0) du dv.
    Triangle,
    /// Directions through the rectangle ±`tan_x` x ±`tan_y` of the plane z = 1 (a
    /// projector's frustum): (½ + ½ x / (z tan_x), ½ + ½ y / (z tan_y)); a point there
    /// is a unit direction and dω = 4 tan_x tan_y cos³ θ du dv.
    Frustum { tan_x: f32, tan_y: f32 },
    /// The square [-1, 1]² (a rectangle's or a mesh's local coordinates): (½ + ½ x,
    /// ½ + ½ y); dA = 4 du dv.
    Square,
}

impl Chart {
    /// The chart coordinates of point `p`; outside [0, 1]² for points off the domain.
    pub fn to_square(self, p: Vec3) -> Vec2 {
        match self {
            Chart::Frustum { tan_x, tan_y } => {
                if p.z.is_nan() || p.z <= 0.0 {
                    return Vec2::splat(-1.0);
                }
                Vec2::new(
                    0.5 + 0.5 * p.x / (p.z * tan_x),
                    0.5 + 0.5 * p.y / (p.z * tan_y),
                )
            }
            Chart::Disk => {
                let phi = p.y.atan2(p.x) / (2.0 * std::f32::consts::PI);
                Vec2::new(p.length_squared(), phi.rem_euclid(1.0))
            }
            Chart::Triangle => Vec2::new(p.x, if p.x < 1.0 { p.y / (1.0 - p.x) } else { 0.0 }),
            Chart::Square => Vec2::new(0.5 + 0.5 * p.x, 0.5 + 0.5 * p.y),
        }
    }

    /// The point at chart coordinates (u, v) and the area element per unit du dv.
    pub fn point_at(self, u: f64, v: f64) -> ([f32; 4], f64) {
        match self {
            Chart::Disk => {
                let (r, phi) = (u.sqrt(), 2.0 * std::f64::consts::PI * v);
                (
                    [(r * phi.cos()) as f32, (r * phi.sin()) as f32, 0.0, 0.0],
                    std::f64::consts::PI,
                )
            }
            Chart::Triangle => ([u as f32, (v * (1.0 - u)) as f32, 0.0, 0.0], 1.0 - u),
            Chart::Square => (
                [(2.0 * u - 1.0) as f32, (2.0 * v - 1.0) as f32, 0.0, 0.0],
                4.0,
            ),
            Chart::Frustum { tan_x, tan_y } => {
                let (tx, ty) = (tan_x as f64, tan_y as f64);
                let (x, y) = ((2.0 * u - 1.0) * tx, (2.0 * v - 1.0) * ty);
                let len = (x * x + y * y + 1.0).sqrt();
                let cos = 1.0 / len;
                (
                    [(x / len) as f32, (y / len) as f32, cos as f32, 0.0],
                    4.0 * tx * ty * cos * cos * cos,
                )
            }
        }
    }
}

/// A res x res histogram of a planar domain in [`Chart`] coordinates.
#[derive(Debug, Clone, Copy)]
pub struct PlaneGrid {
    pub chart: Chart,
    pub res: usize,
}

impl PlaneGrid {
    /// The cell of point `p` (x, y); `None` off the domain (beyond rounding).
    pub fn cell_of(&self, p: Vec3) -> Option<usize> {
        let q = self.chart.to_square(p);
        let ok = q.x >= -1e-6 && q.y >= -1e-6 && q.x <= 1.0 + 1e-6 && q.y <= 1.0 + 1e-6;
        if !ok || !q.is_finite() {
            return None;
        }
        let i = ((q.x * self.res as f32) as usize).min(self.res - 1);
        let j = ((q.y * self.res as f32) as usize).min(self.res - 1);
        Some(i * self.res + j)
    }

    /// k x k midpoints per cell (cell-major) and the area each stands for.
    pub fn quadrature(&self, k: usize) -> (Vec<[f32; 4]>, Vec<f64>) {
        let m = self.res * k;
        let mut points = Vec::with_capacity(m * m);
        let mut w = Vec::with_capacity(m * m);
        for c in 0..self.res * self.res {
            let (i, j) = (c / self.res, c % self.res);
            for a in 0..k {
                for b in 0..k {
                    let u = ((i * k + a) as f64 + 0.5) / m as f64;
                    let v = ((j * k + b) as f64 + 0.5) / m as f64;
                    let (p, da) = self.chart.point_at(u, v);
                    points.push(p);
                    w.push(da / (m * m) as f64);
                }
            }
        }
        (points, w)
    }
}

/// The cells of a test: over the sphere (directions) or over a planar domain.
#[derive(Debug, Clone)]
pub enum Grid {
    Sphere(SphereGrid),
    Plane(PlaneGrid),
}

impl Grid {
    pub fn cells(&self) -> usize {
        self.rows() * self.cols()
    }

    /// The grid as an image: rows (θ' rings or the chart's u) by columns (azimuth or
    /// the chart's v); cell `r * cols + c`.
    pub fn rows(&self) -> usize {
        match self {
            Grid::Sphere(g) => g.nt,
            Grid::Plane(g) => g.res,
        }
    }

    pub fn cols(&self) -> usize {
        match self {
            Grid::Sphere(g) => g.np,
            Grid::Plane(g) => g.res,
        }
    }

    /// The cell of a sampled point: a direction, or a point in the plane (x, y).
    pub fn cell_of(&self, p: Vec3) -> Option<usize> {
        match self {
            Grid::Sphere(g) => g.cell_of(p),
            Grid::Plane(g) => g.cell_of(p),
        }
    }

    /// k x k quadrature points per cell (cell-major) and the measure (solid angle or
    /// area) each stands for.
    pub fn quadrature(&self, k: usize) -> (Vec<[f32; 4]>, Vec<f64>) {
        match self {
            Grid::Sphere(g) => g.quadrature(k),
            Grid::Plane(g) => g.quadrature(k),
        }
    }

    /// Sums per-point values (pdf x weight) into per-cell integrals.
    pub fn integrate(&self, k: usize, pdf: &[f64], w: &[f64]) -> Vec<f64> {
        integrate(self.cells(), k, pdf, w)
    }

    /// Counts of `points` per cell; also the number that fell in no cell.
    pub fn histogram(&self, points: impl IntoIterator<Item = Vec3>) -> (Vec<f64>, usize) {
        let mut counts = vec![0.0; self.cells()];
        let mut outside = 0;
        for p in points {
            match self.cell_of(p) {
                Some(c) => counts[c] += 1.0,
                None => outside += 1,
            }
        }
        (counts, outside)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadratures_measure_their_domains() {
        let sphere = Grid::Sphere(SphereGrid::new(Vec3::new(0.3, 0.1, 1.0), 32, 24));
        let (p, w) = sphere.quadrature(4);
        let area = sphere
            .integrate(4, &vec![1.0; p.len()], &w)
            .iter()
            .sum::<f64>();
        assert!((area - 4.0 * std::f64::consts::PI).abs() < 1e-3, "{area}");
        for chart in [Chart::Disk, Chart::Triangle, Chart::Square] {
            let plane = Grid::Plane(PlaneGrid { chart, res: 16 });
            let (p, w) = plane.quadrature(4);
            let area = plane
                .integrate(4, &vec![1.0; p.len()], &w)
                .iter()
                .sum::<f64>();
            let want = match chart {
                Chart::Disk => std::f64::consts::PI,
                Chart::Square => 4.0,
                _ => 0.5,
            };
            assert!((area - want).abs() < 1e-9, "{chart:?}: {area}");
            // Every quadrature point lies in the cell it stands for.
            for (q, pt) in p.iter().enumerate() {
                let c = plane.cell_of(Vec3::new(pt[0], pt[1], 0.0));
                assert_eq!(c, Some(q / 16), "{chart:?} point {q}");
            }
        }
        let (p, _) = sphere.quadrature(2);
        for (q, pt) in p.iter().enumerate() {
            assert_eq!(
                sphere.cell_of(Vec3::from_slice(pt)),
                Some(q / 4),
                "point {q}"
            );
        }
    }
}
