//! Spectra written as `wavelength:value` pairs, reduced to linear sRGB the way
//! Mitsuba 3's RGB variants do it when they load a scene.
//!
//! Mitsuba (`spectrum_list_to_srgb` in `src/core/spectrum.cpp`, called from
//! `src/core/xml.cpp`) integrates the piecewise-linear spectrum against the CIE 1931
//! colour matching functions at 1000 evenly spaced wavelengths over 360–830 nm,
//! skipping wavelengths outside the given range (the spectrum is zero there), scales so
//! that a unit spectrum has luminance Y = 1, converts XYZ to linear sRGB (Rec. 709
//! primaries, D65 white) and clamps: to [0, 1] for reflectances, to [0, inf) for
//! emission and for the unbounded `eta`/`k`/`int_ior`/`ext_ior`.
//!
//! Our colour matching functions are the analytic multi-lobe fit of Wyman, Sloan and
//! Shirley 2013, "Simple Analytic Approximations to the CIE XYZ Color Matching
//! Functions", JCGT 2(2), eq. 2–4, instead of Mitsuba's 5 nm table; the
//! normalization uses the same fit, so a unit spectrum still gives Y = 1 exactly.
//! Results agree with Mitsuba to within the fit's error (about 1% of each channel).

use glam::{DVec3, Vec3};

/// Mitsuba's integration range and sample count.
const LAMBDA_MIN: f64 = 360.0;
const LAMBDA_MAX: f64 = 830.0;
const STEPS: usize = 1000;

/// Piecewise Gaussian g(x; mu, s1, s2) of Wyman et al. 2013: width s1 left of mu, s2 right.
fn lobe(x: f64, mu: f64, s1: f64, s2: f64) -> f64 {
    let t = (x - mu) / if x < mu { s1 } else { s2 };
    (-0.5 * t * t).exp()
}

/// CIE 1931 2° colour matching functions at `lambda` (nm): Wyman et al. 2013, eq. 2–4.
pub fn cie1931_xyz(lambda: f64) -> DVec3 {
    let x = 1.056 * lobe(lambda, 599.8, 37.9, 31.0) + 0.362 * lobe(lambda, 442.0, 16.0, 26.7)
        - 0.065 * lobe(lambda, 501.1, 20.4, 26.2);
    let y = 0.821 * lobe(lambda, 568.8, 46.9, 40.5) + 0.286 * lobe(lambda, 530.9, 16.3, 31.1);
    let z = 1.217 * lobe(lambda, 437.0, 11.8, 36.0) + 0.681 * lobe(lambda, 459.0, 26.0, 13.8);
    DVec3::new(x, y, z)
}

/// CIE XYZ to linear sRGB (Rec. 709 primaries, D65 white), the matrix Mitsuba uses.
pub fn xyz_to_srgb(xyz: DVec3) -> DVec3 {
    DVec3::new(
        3.240479 * xyz.x - 1.537150 * xyz.y - 0.498535 * xyz.z,
        -0.969256 * xyz.x + 1.875991 * xyz.y + 0.041556 * xyz.z,
        0.055648 * xyz.x - 0.204043 * xyz.y + 1.057311 * xyz.z,
    )
}

fn sample_wavelength(i: usize) -> f64 {
    LAMBDA_MIN + (i as f64 / (STEPS - 1) as f64) * (LAMBDA_MAX - LAMBDA_MIN)
}

/// XYZ of a piecewise-linear spectrum, scaled so that a spectrum equal to 1 over
/// 360–830 nm has Y = 1. `wavelengths` must be increasing and as long as `values`.
pub fn spectrum_to_xyz(wavelengths: &[f64], values: &[f64]) -> DVec3 {
    let mut xyz = DVec3::ZERO;
    let mut y_unit = 0.0;
    let (Some(&first), Some(&last)) = (wavelengths.first(), wavelengths.last()) else {
        return DVec3::ZERO;
    };
    for i in 0..STEPS {
        let w = sample_wavelength(i);
        let cmf = cie1931_xyz(w);
        y_unit += cmf.y;
        if w < first || w > last {
            continue;
        }
        // The interval [w0, w1] holding w (the last one when w == last).
        let k = wavelengths
            .partition_point(|&x| x <= w)
            .clamp(1, wavelengths.len().max(2) - 1);
        let v = if wavelengths.len() == 1 {
            values[0]
        } else {
            let (w0, w1, v0, v1) = (wavelengths[k - 1], wavelengths[k], values[k - 1], values[k]);
            if w1 > w0 {
                v0 + (v1 - v0) * (w - w0) / (w1 - w0)
            } else {
                v0
            }
        };
        xyz += cmf * v;
    }
    xyz / y_unit
}

/// Linear sRGB of a piecewise-linear spectrum, clamped as Mitsuba clamps: to [0, 1]
/// when `bounded` (reflectances), else only below at 0 (emission, indices of refraction).
pub fn spectrum_to_srgb(wavelengths: &[f64], values: &[f64], bounded: bool) -> Vec3 {
    let rgb = xyz_to_srgb(spectrum_to_xyz(wavelengths, values)).max(DVec3::ZERO);
    let rgb = if bounded { rgb.min(DVec3::ONE) } else { rgb };
    rgb.as_vec3()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_spectrum_has_unit_luminance() {
        let xyz = spectrum_to_xyz(&[360.0, 830.0], &[1.0, 1.0]);
        assert!((xyz.y - 1.0).abs() < 1e-9, "{xyz}");
        // Equal-energy white in sRGB is slightly pink: about (1.20, 0.95, 0.91).
        let rgb = xyz_to_srgb(xyz);
        assert!(
            (rgb.x - 1.20).abs() < 0.03 && (rgb.y - 0.95).abs() < 0.03,
            "{rgb}"
        );
    }

    #[test]
    fn fit_matches_cie_table_at_peaks() {
        // CIE 1931 table values: y(555) = 1.0000, x(600) = 1.0622, z(445) = 1.7826.
        assert!((cie1931_xyz(555.0).y - 1.0).abs() < 0.02);
        assert!((cie1931_xyz(600.0).x - 1.0622).abs() < 0.03);
        assert!((cie1931_xyz(445.0).z - 1.7826).abs() < 0.05);
    }

    #[test]
    fn red_spectrum_is_red_and_clamped() {
        let w: Vec<f64> = (0..=30).map(|i| 400.0 + 10.0 * i as f64).collect();
        let v: Vec<f64> = w
            .iter()
            .map(|&l| if l > 600.0 { 0.9 } else { 0.05 })
            .collect();
        let rgb = spectrum_to_srgb(&w, &v, true);
        assert!(rgb.x > 3.0 * rgb.y && rgb.x > 3.0 * rgb.z, "{rgb}");
        assert!(rgb.max_element() <= 1.0 && rgb.min_element() >= 0.0);
    }

    #[test]
    fn outside_range_is_zero() {
        assert_eq!(spectrum_to_xyz(&[900.0, 1000.0], &[1.0, 1.0]), DVec3::ZERO);
        assert_eq!(spectrum_to_xyz(&[], &[]), DVec3::ZERO);
    }
}
