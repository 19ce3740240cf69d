//! 8-bit sRGB PNG previews of linear renders.

use std::path::Path;

use super::{file_error, Image, Result};

/// The sRGB transfer function (IEC 61966-2-1) of a linear value, clamped to [0, 1].
pub fn srgb_encode(linear: f32) -> f32 {
    let v = if linear.is_nan() {
        0.0
    } else {
        linear.clamp(0.0, 1.0)
    };
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// Writes `img` as an 8-bit sRGB PNG (values clamped to [0, 1]).
pub fn write_png(path: &Path, img: &Image) -> Result<()> {
    let bytes: Vec<u8> = img
        .rgb
        .iter()
        .map(|&v| (srgb_encode(v) * 255.0 + 0.5) as u8)
        .collect();
    image::save_buffer(path, &bytes, img.width, img.height, image::ColorType::Rgb8)
        .map_err(|e| file_error(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_curve_matches_the_standard() {
        assert_eq!(srgb_encode(0.0), 0.0);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_encode(0.18) - 0.4613).abs() < 1e-3);
        assert_eq!(srgb_encode(f32::NAN), 0.0);
        assert_eq!(srgb_encode(7.0), srgb_encode(1.0));
    }

    #[test]
    fn writes_a_readable_png() {
        let mut img = Image::new(4, 2);
        img.rgb[0] = 1.0;
        let path = std::env::temp_dir().join(format!("wavetrace-png-{}.png", std::process::id()));
        write_png(&path, &img).unwrap();
        let back = image::open(&path).unwrap().to_rgb8();
        assert_eq!(back.dimensions(), (4, 2));
        assert_eq!(back.get_pixel(0, 0).0, [255, 0, 0]);
        let _ = std::fs::remove_file(path);
    }
}
