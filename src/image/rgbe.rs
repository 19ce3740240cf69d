//! Radiance RGBE files (Ward 1991, "Real Pixels", Graphics Gems II): three 8-bit
//! mantissas and a shared exponent per pixel, through the `image` crate's encoder.
//! Negative values cannot be stored and become 0.

use std::path::Path;

use super::{Error, Image};

/// Writes the image as a Radiance RGBE file.
pub fn write(image: &Image, path: impl AsRef<Path>) -> Result<(), Error> {
    let path = path.as_ref();
    let pixels: Vec<::image::Rgb<f32>> = image
        .rgb
        .chunks_exact(3)
        .map(|p| ::image::Rgb([p[0].max(0.0), p[1].max(0.0), p[2].max(0.0)]))
        .collect();
    let file = std::fs::File::create(path).map_err(|cause| Error::Io {
        path: path.to_owned(),
        cause,
    })?;
    ::image::codecs::hdr::HdrEncoder::new(std::io::BufWriter::new(file))
        .encode(&pixels, image.width as usize, image.height as usize)
        .map_err(|cause| Error::Rgbe {
            path: path.to_owned(),
            cause,
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_within_rgbe_precision() {
        let path = std::env::temp_dir().join(format!("wavetrace-{}-t.hdr", std::process::id()));
        let image = Image::from_rgb(2, 1, vec![1.0, 0.5, 0.25, 100.0, -1.0, 3.0]).unwrap();
        write(&image, &path).unwrap();
        let back = ::image::open(&path).unwrap().to_rgb32f();
        std::fs::remove_file(&path).ok();
        assert_eq!(back.dimensions(), (2, 1));
        // 8-bit mantissas: 1% relative at the brightest channel of a pixel.
        assert_eq!(back.get_pixel(0, 0).0, [1.0, 0.5, 0.25]);
        let p = back.get_pixel(1, 0).0;
        assert!((p[0] - 100.0).abs() < 1.0 && p[1] == 0.0 && (p[2] - 3.0).abs() < 0.5);
    }
}
