//! 8-bit sRGB PNG output, for looking at renders.
//!
//! Each linear value `v` becomes `round(255 * oetf(clamp(v * 2^exposure, 0, 1)))`,
//! where `oetf` is the sRGB transfer function (IEC 61966-2-1). NaN becomes 0 so a bad
//! pixel shows up black rather than aborting the write. This is the whole tonemap:
//! values above 1 clip, as they do in Mitsuba's and Nori's PNG output, and negative
//! values (a Mitchell or Lanczos filter's ringing next to a bright edge) clip to 0.
//! [`write_channels`] also writes grey, grey + alpha and RGBA PNGs; alpha is stored
//! linearly (`round(255 clamp(a, 0, 1))`), and the colour it comes with must be
//! straight, not premultiplied, as PNG defines it.

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
    .map_err(|cause| Error::Png {
        path: path.to_owned(),
        cause,
    })
}

/// Writes 8-bit sRGB bytes already encoded (3 per pixel, top row first) as a PNG:
/// the viewer's picture, tone mapped on the GPU as [`to_srgb8`] does.
pub fn write_rgb8(
    path: impl AsRef<Path>,
    width: u32,
    height: u32,
    rgb: &[u8],
) -> Result<(), Error> {
    let path = path.as_ref();
    ::image::save_buffer_with_format(
        path,
        rgb,
        width,
        height,
        ::image::ExtendedColorType::Rgb8,
        ::image::ImageFormat::Png,
    )
    .map_err(|cause| Error::Png {
        path: path.to_owned(),
        cause,
    })
}

/// Writes `data` (`channels` interleaved values per pixel, top row first) as an 8-bit
/// PNG: 1 channel grey, 2 grey + alpha, 3 RGB, 4 RGBA. Colour channels are encoded as
/// [`to_srgb8`] does, alpha linearly.
pub fn write_channels(
    path: impl AsRef<Path>,
    width: u32,
    height: u32,
    channels: usize,
    data: &[f32],
    exposure: f32,
) -> Result<(), Error> {
    let path = path.as_ref();
    let format_error = |message: String| Error::Format {
        path: path.to_owned(),
        message,
    };
    let color = match channels {
        1 => ::image::ExtendedColorType::L8,
        2 => ::image::ExtendedColorType::La8,
        3 => ::image::ExtendedColorType::Rgb8,
        4 => ::image::ExtendedColorType::Rgba8,
        n => {
            return Err(format_error(format!(
                "a PNG holds 1 to 4 channels, not {n}"
            )))
        }
    };
    if data.len() != channels * width as usize * height as usize {
        return Err(format_error(format!(
            "{} values for a {width}x{height} image of {channels} channels",
            data.len()
        )));
    }
    let scale = exposure.exp2();
    let has_alpha = channels.is_multiple_of(2);
    let bytes: Vec<u8> = data
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            if has_alpha && i % channels == channels - 1 {
                let a = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
                (a * 255.0 + 0.5) as u8
            } else {
                encode(v, scale)
            }
        })
        .collect();
    ::image::save_buffer_with_format(
        path,
        &bytes,
        width,
        height,
        color,
        ::image::ImageFormat::Png,
    )
    .map_err(|cause| Error::Png {
        path: path.to_owned(),
        cause,
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
    fn grey_alpha_and_rgba_pngs() {
        let path =
            std::env::temp_dir().join(format!("wavetrace-{}-channels.png", std::process::id()));
        write_channels(&path, 2, 1, 2, &[0.5, 1.0, -0.2, 0.25], 0.0).unwrap();
        let back = ::image::open(&path).unwrap().to_luma_alpha8();
        assert_eq!(back.get_pixel(0, 0).0, [188, 255]);
        // Negative values clip to black; alpha is linear.
        assert_eq!(back.get_pixel(1, 0).0, [0, 64]);
        write_channels(&path, 1, 1, 4, &[1.0, 0.5, 0.0, 0.5], 0.0).unwrap();
        let back = ::image::open(&path).unwrap().to_rgba8();
        assert_eq!(back.get_pixel(0, 0).0, [255, 188, 0, 128]);
        std::fs::remove_file(&path).ok();
        assert!(write_channels(&path, 1, 1, 5, &[0.0; 5], 0.0).is_err());
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
