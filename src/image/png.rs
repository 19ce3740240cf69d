//! 8-bit sRGB PNG output, for looking at renders.
//!
//! Each linear value `v` becomes `round(255 * oetf(clamp(v * 2^exposure, 0, 1)))`,
//! where `oetf` is the sRGB transfer function (IEC 61966-2-1). NaN becomes 0 so a bad
//! pixel shows up black rather than aborting the write. This is the whole tonemap:
//! values above 1 clip, as they do in Mitsuba's and Nori's PNG output.

use std::path::Path;

use super::{Error, Image};

/// The sRGB opto-electronic transfer function: linear `[0, 1]` to encoded `[0, 1]`
/// (IEC 61966-2-1: `12.92 v` below 0.0031308, else `1.055 v^(1/2.4) - 0.055`).
pub fn srgb_oetf(v: f32) -> f32 {
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// One linear value to an 8-bit sRGB code, after scaling by `scale` (= 2^exposure).
fn encode(v: f32, scale: f32) -> u8 {
    let v = v * scale;
    // NaN to 0 explicitly: `clamp` would keep it.
    let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
    (srgb_oetf(v) * 255.0 + 0.5) as u8
}

/// The image as 8-bit sRGB bytes, 3 per pixel, top row first; `exposure` in stops
/// multiplies every value by `2^exposure` before the clamp (0 leaves them as they are).
pub fn to_srgb8(image: &Image, exposure: f32) -> Vec<u8> {
    let scale = exposure.exp2();
    image.rgb.iter().map(|&v| encode(v, scale)).collect()
}

/// Writes an 8-bit sRGB PNG of `image` with `exposure` in stops (see [`to_srgb8`]).
pub fn write(image: &Image, path: impl AsRef<Path>, exposure: f32) -> Result<(), Error> {
    let path = path.as_ref();
    let bytes = to_srgb8(image, exposure);
    ::image::save_buffer_with_format(
        path,
        &bytes,
        image.width,
        image.height,
        ::image::ExtendedColorType::Rgb8,
        ::image::ImageFormat::Png,
    )
    .map_err(|source| Error::Png {
        path: path.to_owned(),
        source,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn oetf_matches_the_standard() {
        assert_eq!(srgb_oetf(0.0), 0.0);
        assert!((srgb_oetf(1.0) - 1.0).abs() < 1e-6);
        // Both branches meet at the threshold (continuity to about 1e-7).
        let t = 0.003_130_8;
        assert!((12.92 * t - (1.055 * f32::powf(t, 1.0 / 2.4) - 0.055)).abs() < 1e-6);
        // Linear 0.5 is code 188 (0.7354 * 255 = 187.5...), 0.18 is 118.
        assert_eq!(encode(0.5, 1.0), 188);
        assert_eq!(encode(0.18, 1.0), 118);
    }

    #[test]
    fn clamps_and_zeroes_bad_values() {
        assert_eq!(encode(-1.0, 1.0), 0);
        assert_eq!(encode(7.0, 1.0), 255);
        assert_eq!(encode(f32::NAN, 1.0), 0);
        assert_eq!(encode(f32::INFINITY, 1.0), 255);
    }

    #[test]
    fn exposure_is_in_stops() {
        let image = Image::from_rgb(1, 1, vec![0.25, 0.125, 1.0]).unwrap();
        assert_eq!(to_srgb8(&image, 1.0), vec![188, encode(0.25, 1.0), 255]);
        assert_eq!(to_srgb8(&image, -2.0)[2], encode(0.25, 1.0));
    }

    #[test]
    fn writes_a_png_that_reads_back() {
        let path = std::env::temp_dir().join(format!("wavetrace-{}-write.png", std::process::id()));
        let mut image = Image::new(5, 3);
        image.set_pixel(4, 2, [1.0, 0.5, 0.0]);
        image.set_pixel(0, 1, [0.0, 0.0, 2.0]);
        write(&image, &path, 0.0).unwrap();
        let back = ::image::open(&path).unwrap().to_rgb8();
        std::fs::remove_file(&path).ok();
        assert_eq!(back.dimensions(), (5, 3));
        assert_eq!(back.get_pixel(4, 2).0, [255, 188, 0]);
        assert_eq!(back.get_pixel(0, 1).0, [0, 0, 255]);
        assert_eq!(back.get_pixel(1, 1).0, [0, 0, 0]);
    }

    #[test]
    fn unwritable_path_names_the_file() {
        let err = write(&Image::new(1, 1), "/nonexistent/dir/out.png", 0.0).unwrap_err();
        assert!(
            err.to_string().starts_with("/nonexistent/dir/out.png: "),
            "{err}"
        );
    }
}
