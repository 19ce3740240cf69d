//! Spectra written in a scene, reduced to linear sRGB the way Mitsuba 3's RGB variants
//! do it when they load a scene (`Properties::get_texture_impl` in
//! src/core/properties.cpp, `spectrum_list_to_srgb` in src/core/spectrum.cpp;
//! checked against Mitsuba 3.9.1 `scalar_rgb`):
//!
//! - `wavelength:value` pairs: the piecewise-linear spectrum (zero outside the given
//!   range) is integrated against the CIE 1931 colour matching functions at 1000
//!   evenly spaced wavelengths over 360–830 nm, times the D65 illuminant unless the
//!   spectrum is an emitter's, scaled by 470/1000 and by Mitsuba's Y normalization
//!   (1/106.75, so that a unit spectrum under D65 is white), converted from XYZ to
//!   linear sRGB, and clamped: to [0, 1] for reflectances, to [0, ∞) for emission and
//!   for the unbounded `eta`, `k`, `int_ior`, `ext_ior`, `sigma_t`, `sigma_a`, `sigma_s`.
//!   So a reflectance spectrum is the colour of the surface under daylight, and an
//!   emitter's is its own colour.
//! - A single value v: v for anything but an emitter; an emitter's radiance v times the
//!   sRGB colour of the equal-energy spectrum, v (1.2048, 0.9483, 0.9089) (Mitsuba:
//!   "a uniform spectrum does not produce a uniform RGB response in sRGB").
//!
//! The tables are the CIE's (CIE 015:2004: the 1931 2° standard observer and the D65
//! relative spectral power distribution, every 5 nm), interpolated linearly as
//! Mitsuba's `cie1931_xyz` and `cie_d65` do; results agree with Mitsuba to float
//! rounding (tests below).

use glam::{DVec3, Vec3};

/// Mitsuba's integration range and sample count.
const LAMBDA_MIN: f64 = 360.0;
const LAMBDA_MAX: f64 = 830.0;
const STEPS: usize = 1000;
/// Mitsuba's `MI_CIE_Y_NORMALIZATION` (1 / ∫ ȳ(λ) D65(λ) dλ with D65 scaled by
/// [`D65_NORMALIZATION`]).
const CIE_Y_NORMALIZATION: f64 = 0.009367658735689113;
/// Mitsuba's `MI_CIE_D65_NORMALIZATION`, applied to the tabulated D65 (100 at 560 nm).
const D65_NORMALIZATION: f64 = 0.010101273599490354;

/// CIE 1931 x̄, ȳ, z̄ and the D65 relative spectral power, every 5 nm from 360 to
/// 830 nm (CIE 015:2004, tables T.1 and T.4).
#[rustfmt::skip]
const CIE_5NM: [[f64; 4]; 95] = [
    [0.0001299, 3.917e-6, 0.0006061, 46.6383], // 360
    [0.0002321, 6.965e-6, 0.001086, 49.3637], // 365
    [0.0004149, 1.239e-5, 0.001946, 52.0891], // 370
    [0.0007416, 2.202e-5, 0.003486, 51.0323], // 375
    [0.001368, 3.9e-5, 0.00645, 49.9755], // 380
    [0.002236, 6.4e-5, 0.01055, 52.3118], // 385
    [0.004243, 0.00012, 0.02005, 54.6482], // 390
    [0.00765, 0.000217, 0.03621, 68.7015], // 395
    [0.01431, 0.000396, 0.06785, 82.7549], // 400
    [0.02319, 0.00064, 0.1102, 87.1204], // 405
    [0.04351, 0.00121, 0.2074, 91.486], // 410
    [0.07763, 0.00218, 0.3713, 92.4589], // 415
    [0.13438, 0.004, 0.6456, 93.4318], // 420
    [0.21477, 0.0073, 1.03905, 90.057], // 425
    [0.2839, 0.0116, 1.3856, 86.6823], // 430
    [0.3285, 0.01684, 1.62296, 95.7736], // 435
    [0.34828, 0.023, 1.74706, 104.865], // 440
    [0.34806, 0.0298, 1.7826, 110.936], // 445
    [0.3362, 0.038, 1.77211, 117.008], // 450
    [0.3187, 0.048, 1.7441, 117.41], // 455
    [0.2908, 0.06, 1.6692, 117.812], // 460
    [0.2511, 0.0739, 1.5281, 116.336], // 465
    [0.19536, 0.09098, 1.28764, 114.861], // 470
    [0.1421, 0.1126, 1.0419, 115.392], // 475
    [0.09564, 0.13902, 0.81295, 115.923], // 480
    [0.05795, 0.1693, 0.6162, 112.367], // 485
    [0.03201, 0.20802, 0.46518, 108.811], // 490
    [0.0147, 0.2586, 0.3533, 109.082], // 495
    [0.0049, 0.323, 0.272, 109.354], // 500
    [0.0024, 0.4073, 0.2123, 108.578], // 505
    [0.0093, 0.503, 0.1582, 107.802], // 510
    [0.0291, 0.6082, 0.1117, 106.296], // 515
    [0.06327, 0.71, 0.07825, 104.79], // 520
    [0.1096, 0.7932, 0.05725, 106.239], // 525
    [0.1655, 0.862, 0.04216, 107.689], // 530
    [0.22575, 0.91485, 0.02984, 106.047], // 535
    [0.2904, 0.954, 0.0203, 104.405], // 540
    [0.3597, 0.9803, 0.0134, 104.225], // 545
    [0.43345, 0.99495, 0.00875, 104.046], // 550
    [0.51205, 1.0, 0.00575, 102.023], // 555
    [0.5945, 0.995, 0.0039, 100.0], // 560
    [0.6784, 0.9786, 0.00275, 98.1671], // 565
    [0.7621, 0.952, 0.0021, 96.3342], // 570
    [0.8425, 0.9154, 0.0018, 96.0611], // 575
    [0.9163, 0.87, 0.00165, 95.788], // 580
    [0.9786, 0.8163, 0.0014, 92.2368], // 585
    [1.0263, 0.757, 0.0011, 88.6856], // 590
    [1.0567, 0.6949, 0.001, 89.3459], // 595
    [1.0622, 0.631, 0.0008, 90.0062], // 600
    [1.0456, 0.5668, 0.0006, 89.8026], // 605
    [1.0026, 0.503, 0.00034, 89.5991], // 610
    [0.9384, 0.4412, 0.00024, 88.6489], // 615
    [0.85445, 0.381, 0.00019, 87.6987], // 620
    [0.7514, 0.321, 0.0001, 85.4936], // 625
    [0.6424, 0.265, 5e-5, 83.2886], // 630
    [0.5419, 0.217, 3e-5, 83.4939], // 635
    [0.4479, 0.175, 2e-5, 83.6992], // 640
    [0.3608, 0.1382, 1e-5, 81.863], // 645
    [0.2835, 0.107, 0.0, 80.0268], // 650
    [0.2187, 0.0816, 0.0, 80.1207], // 655
    [0.1649, 0.061, 0.0, 80.2146], // 660
    [0.1212, 0.04458, 0.0, 81.2462], // 665
    [0.0874, 0.032, 0.0, 82.2778], // 670
    [0.0636, 0.0232, 0.0, 80.281], // 675
    [0.04677, 0.017, 0.0, 78.2842], // 680
    [0.0329, 0.01192, 0.0, 74.0027], // 685
    [0.0227, 0.00821, 0.0, 69.7213], // 690
    [0.01584, 0.005723, 0.0, 70.6652], // 695
    [0.0113592, 0.004102, 0.0, 71.6091], // 700
    [0.00811092, 0.002929, 0.0, 72.979], // 705
    [0.00579035, 0.002091, 0.0, 74.349], // 710
    [0.00410946, 0.001484, 0.0, 67.9765], // 715
    [0.00289933, 0.001047, 0.0, 61.604], // 720
    [0.00204919, 0.00074, 0.0, 65.7448], // 725
    [0.00143997, 0.00052, 0.0, 69.8856], // 730
    [0.000999949, 0.0003611, 0.0, 72.4863], // 735
    [0.000690079, 0.0002492, 0.0, 75.087], // 740
    [0.000476021, 0.0001719, 0.0, 69.3398], // 745
    [0.000332301, 0.00012, 0.0, 63.5927], // 750
    [0.000234826, 8.48e-5, 0.0, 55.0054], // 755
    [0.00016615, 6e-5, 0.0, 46.4182], // 760
    [0.000117413, 4.24e-5, 0.0, 56.6118], // 765
    [8.30753e-5, 3e-5, 0.0, 66.8054], // 770
    [5.87065e-5, 2.12e-5, 0.0, 65.0941], // 775
    [4.15099e-5, 1.499e-5, 0.0, 63.3828], // 780
    [2.93533e-5, 1.06e-5, 0.0, 63.8434], // 785
    [2.06738e-5, 7.4657e-6, 0.0, 64.304], // 790
    [1.45598e-5, 5.2578e-6, 0.0, 61.8779], // 795
    [1.0254e-5, 3.7029e-6, 0.0, 59.4519], // 800
    [7.22146e-6, 2.6078e-6, 0.0, 55.7054], // 805
    [5.08587e-6, 1.8366e-6, 0.0, 51.959], // 810
    [3.58165e-6, 1.2934e-6, 0.0, 54.6998], // 815
    [2.52252e-6, 9.1093e-7, 0.0, 57.4406], // 820
    [1.77651e-6, 6.4153e-7, 0.0, 58.8765], // 825
    [1.25114e-6, 4.5181e-7, 0.0, 60.3125], // 830
];

/// The table row pair and weight for wavelength `lambda` (clamped to the table).
fn lookup(lambda: f64) -> [f64; 4] {
    let x = ((lambda - LAMBDA_MIN) / 5.0).clamp(0.0, (CIE_5NM.len() - 1) as f64);
    let i = (x as usize).min(CIE_5NM.len() - 2);
    let t = x - i as f64;
    let (a, b) = (CIE_5NM[i], CIE_5NM[i + 1]);
    std::array::from_fn(|k| a[k] + t * (b[k] - a[k]))
}

/// CIE 1931 2° colour matching functions at `lambda` (nm), linearly interpolated.
pub fn cie1931_xyz(lambda: f64) -> DVec3 {
    let r = lookup(lambda);
    DVec3::new(r[0], r[1], r[2])
}

/// The D65 illuminant at `lambda` (nm) with Mitsuba's normalization (about 1 at 560 nm).
pub fn cie_d65(lambda: f64) -> f64 {
    lookup(lambda)[3] * D65_NORMALIZATION
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

/// XYZ of a piecewise-linear spectrum as Mitsuba integrates it: times D65 when `d65`
/// (reflectances and other non-emitter spectra), with Mitsuba's normalization (a
/// unit spectrum under D65 has Y = 1). `wavelengths` must be increasing and as long
/// as `values`.
pub fn spectrum_to_xyz(wavelengths: &[f64], values: &[f64], d65: bool) -> DVec3 {
    let mut xyz = DVec3::ZERO;
    let (Some(&first), Some(&last)) = (wavelengths.first(), wavelengths.last()) else {
        return DVec3::ZERO;
    };
    for i in 0..STEPS {
        let w = sample_wavelength(i);
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
        let illuminant = if d65 { cie_d65(w) } else { 1.0 };
        xyz += cie1931_xyz(w) * (v * illuminant);
    }
    xyz * ((LAMBDA_MAX - LAMBDA_MIN) / STEPS as f64 * CIE_Y_NORMALIZATION)
}

/// Linear sRGB of a piecewise-linear spectrum written in a scene. `emitter`: the
/// spectrum is an emitter's (no D65, not clamped above); `bounded`: clamp to [0, 1]
/// (reflectances), else only below at 0.
pub fn spectrum_to_srgb(wavelengths: &[f64], values: &[f64], emitter: bool, bounded: bool) -> Vec3 {
    let rgb = xyz_to_srgb(spectrum_to_xyz(wavelengths, values, !emitter)).max(DVec3::ZERO);
    let rgb = if bounded && !emitter {
        rgb.min(DVec3::ONE)
    } else {
        rgb
    };
    rgb.as_vec3()
}

/// Linear sRGB of a constant spectrum `value` written in a scene: the value itself,
/// except for an emitter, where it is `value` times the equal-energy spectrum's sRGB
/// colour xyz_to_srgb(1, 1, 1) (Mitsuba's RGB variants, to match their spectral ones).
pub fn constant_to_srgb(value: f64, emitter: bool) -> Vec3 {
    if emitter {
        (xyz_to_srgb(DVec3::ONE) * value).as_vec3()
    } else {
        Vec3::splat(value as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: [f32; 3], tol: f32) -> bool {
        (a - Vec3::from(b)).abs().max_element() <= tol * Vec3::from(b).abs().max_element()
    }

    /// Values printed by Mitsuba 3.9.1 `scalar_rgb` for these spectra on a diffuse
    /// reflectance (non-emitter) and an area emitter's radiance.
    #[test]
    fn matches_mitsuba() {
        let ramp = ([400.0, 700.0], [0.2, 0.8]);
        let torus = ([400.0, 500.0, 600.0, 700.0], [0.0, 0.3, 0.8, 1.1]);
        let refl = |w: &[f64], v: &[f64]| spectrum_to_srgb(w, v, false, true);
        let emit = |w: &[f64], v: &[f64]| spectrum_to_srgb(w, v, true, false);
        let cases = [
            (refl(&ramp.0, &ramp.1), [0.681557, 0.485825, 0.280607]),
            (emit(&ramp.0, &ramp.1), [0.804123, 0.462736, 0.248906]),
            (refl(&torus.0, &torus.1), [0.970898, 0.510187, 0.108601]),
            (emit(&torus.0, &torus.1), [1.12687, 0.488194, 0.0880343]),
            (constant_to_srgb(0.5, true), [0.602397, 0.474146, 0.454458]),
            (constant_to_srgb(0.5, false), [0.5, 0.5, 0.5]),
        ];
        for (got, want) in cases {
            assert!(close(got, want, 2e-5), "{got} vs {want:?}");
        }
    }

    #[test]
    fn white_under_d65_is_white() {
        // A unit reflectance over the whole range is white: D65 is sRGB's white point.
        let rgb = spectrum_to_srgb(&[360.0, 830.0], &[1.0, 1.0], false, false);
        assert!(close(rgb, [1.0, 1.0, 1.0], 2e-3), "{rgb}");
        // The equal-energy spectrum as light is pinkish: about (1.20, 0.95, 0.91).
        let rgb = spectrum_to_srgb(&[360.0, 830.0], &[1.0, 1.0], true, false);
        assert!(close(rgb, [1.2048, 0.9483, 0.9089], 5e-3), "{rgb}");
    }

    #[test]
    fn table_values() {
        // CIE 1931: ȳ(555) = 1, x̄(600) = 1.0622, z̄(445) = 1.78; D65(560) = 100.
        assert_eq!(cie1931_xyz(555.0).y, 1.0);
        assert!((cie1931_xyz(600.0).x - 1.0622).abs() < 1e-4);
        assert!((cie1931_xyz(445.0).z - 1.78).abs() < 1e-2);
        assert!((cie_d65(560.0) / D65_NORMALIZATION - 100.0).abs() < 1e-9);
    }

    #[test]
    fn red_spectrum_is_red_and_clamped() {
        let w: Vec<f64> = (0..=30).map(|i| 400.0 + 10.0 * i as f64).collect();
        let v: Vec<f64> = w
            .iter()
            .map(|&l| if l > 600.0 { 0.9 } else { 0.05 })
            .collect();
        let rgb = spectrum_to_srgb(&w, &v, false, true);
        assert!(rgb.x > 3.0 * rgb.y && rgb.x > 3.0 * rgb.z, "{rgb}");
        assert!(rgb.max_element() <= 1.0 && rgb.min_element() >= 0.0);
    }

    #[test]
    fn outside_range_is_zero() {
        assert_eq!(
            spectrum_to_xyz(&[900.0, 1000.0], &[1.0, 1.0], true),
            DVec3::ZERO
        );
        assert_eq!(spectrum_to_xyz(&[], &[], false), DVec3::ZERO);
    }
}
