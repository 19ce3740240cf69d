//! A test's histograms as a picture, as Nori's warptest shows them: the observed
//! counts, the expected counts (same colour scale) and the standardized residual
//! (O − E) / √E per cell, side by side. Cells are laid out as the grid's rows (θ'
//! rings from the axis, or the chart's first coordinate) by columns (azimuth, or the
//! chart's second coordinate).

use std::path::Path;

use super::Outcome;

/// Pixels per cell side.
const CELL: u32 = 10;
/// Pixels between panels.
const GAP: u32 = 8;

/// Viridis at eleven stops (van der Walt and Smith 2015, matplotlib's default map),
/// linearly interpolated: perceptually ordered from dark blue to yellow.
const VIRIDIS: [[u8; 3]; 11] = [
    [68, 1, 84],
    [72, 36, 117],
    [65, 68, 135],
    [53, 95, 141],
    [42, 120, 142],
    [33, 145, 140],
    [34, 168, 132],
    [68, 191, 112],
    [122, 209, 81],
    [189, 223, 38],
    [253, 231, 37],
];

fn viridis(x: f64) -> [u8; 3] {
    let x = if x.is_finite() {
        x.clamp(0.0, 1.0)
    } else {
        1.0
    };
    let f = x * (VIRIDIS.len() - 1) as f64;
    let i = (f as usize).min(VIRIDIS.len() - 2);
    let t = f - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    [0, 1, 2].map(|c| (a[c] as f64 + t * (b[c] as f64 - a[c] as f64)).round() as u8)
}

/// Blue (negative) through white to red (positive), saturating at |r| = 4.
fn diverging(r: f64) -> [u8; 3] {
    let t = if r.is_finite() {
        (r / 4.0).clamp(-1.0, 1.0)
    } else {
        1.0
    };
    let fade = |c: f64| (255.0 * (1.0 - t.abs()) + c * t.abs()).round() as u8;
    if t >= 0.0 {
        [fade(200.0), fade(30.0), fade(30.0)]
    } else {
        [fade(30.0), fade(70.0), fade(200.0)]
    }
}

/// The three panels as an RGB image: width, height, pixels.
pub fn render(outcome: &Outcome) -> (u32, u32, Vec<u8>) {
    let (rows, cols) = (outcome.grid.rows() as u32, outcome.grid.cols() as u32);
    let (pw, ph) = (cols * CELL, rows * CELL);
    let (w, h) = (3 * pw + 2 * GAP, ph);
    let mut px = vec![255u8; (w * h * 3) as usize];
    // One scale for both histograms: the largest expected count, or observed.
    let top = outcome
        .expected
        .iter()
        .chain(&outcome.observed)
        .fold(0.0f64, |m, &v| m.max(v))
        .max(1.0);
    for r in 0..rows {
        for c in 0..cols {
            let cell = (r * cols + c) as usize;
            let (o, e) = (outcome.observed[cell], outcome.expected[cell]);
            let residual = if e > 0.0 {
                (o - e) / e.sqrt()
            } else if o > 0.0 {
                f64::INFINITY
            } else {
                0.0
            };
            let colours = [viridis(o / top), viridis(e / top), diverging(residual)];
            for (panel, colour) in colours.iter().enumerate() {
                let x0 = panel as u32 * (pw + GAP) + c * CELL;
                for y in r * CELL..(r + 1) * CELL {
                    for x in x0..x0 + CELL {
                        let i = ((y * w + x) * 3) as usize;
                        px[i..i + 3].copy_from_slice(colour);
                    }
                }
            }
        }
    }
    (w, h, px)
}

/// Writes [`render`] as a PNG.
pub fn write_png(outcome: &Outcome, path: &Path) -> Result<(), crate::image::Error> {
    let (w, h, px) = render(outcome);
    ::image::save_buffer(path, &px, w, h, ::image::ExtendedColorType::Rgb8).map_err(|cause| {
        crate::image::Error::Png {
            path: path.to_owned(),
            cause,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::warptest::{chi2, Grid, PlaneGrid};

    #[test]
    fn panels_show_counts_and_residuals() {
        let grid = Grid::Plane(PlaneGrid {
            chart: crate::warptest::Chart::Disk,
            res: 2,
        });
        let observed = vec![10.0, 20.0, 30.0, 100.0];
        let expected = vec![10.0, 20.0, 30.0, 40.0];
        let outcome = Outcome {
            grid,
            chi2: chi2(&observed, &expected),
            observed,
            expected,
            samples: 160,
            excluded: 0,
            outside: 0,
            pdf_integral: 1.0,
        };
        let (w, h, px) = render(&outcome);
        assert_eq!((w, h), (3 * 2 * CELL + 2 * GAP, 2 * CELL));
        let at = |x: u32, y: u32| {
            let i = ((y * w + x) * 3) as usize;
            [px[i], px[i + 1], px[i + 2]]
        };
        // Cell 0 equal in both histograms; cell 3 brightest in the observed one.
        assert_eq!(at(1, 1), at(2 * CELL + GAP + 1, 1));
        assert_eq!(at(CELL + 1, CELL + 1), viridis(1.0));
        // Residual panel: white where O = E, red where O > E.
        let x3 = 2 * (2 * CELL + GAP);
        assert_eq!(at(x3 + 1, 1), [255, 255, 255]);
        assert_eq!(at(x3 + CELL + 1, CELL + 1), diverging(9.5));
        assert!(at(x3 + CELL + 1, CELL + 1)[0] > 150);
    }
}
