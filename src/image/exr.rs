//! OpenEXR: linear float RGB, the renderer's output and the references' format.

use std::path::Path;

use exr::prelude::{read_first_rgba_layer_from_file, write_rgb_file};

use super::{file_error, Image, Result};

/// Writes `img` as a 32-bit float RGB EXR.
pub fn write_exr(path: &Path, img: &Image) -> Result<()> {
    let w = img.width as usize;
    write_rgb_file(path, w, img.height as usize, |x, y| {
        let i = 3 * (y * w + x);
        (img.rgb[i], img.rgb[i + 1], img.rgb[i + 2])
    })
    .map_err(|e| file_error(path, e))
}

/// Reads the first RGB(A) layer of an EXR (half or float channels, as written by
/// Mitsuba and others); alpha is ignored, a missing channel reads as 0.
pub fn read_exr(path: &Path) -> Result<Image> {
    let image = read_first_rgba_layer_from_file(
        path,
        |resolution, _channels| Image::new(resolution.width() as u32, resolution.height() as u32),
        |img: &mut Image, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            let i = 3 * (pos.y() * img.width as usize + pos.x());
            img.rgb[i] = r;
            img.rgb[i + 1] = g;
            img.rgb[i + 2] = b;
        },
    )
    .map_err(|e| file_error(path, e))?;
    Ok(image.layer_data.channel_data.pixels)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_keeps_every_float() {
        let mut img = Image::new(5, 3);
        for (i, v) in img.rgb.iter_mut().enumerate() {
            *v = i as f32 * 0.37 - 2.0;
        }
        img.rgb[7] = 1e-30;
        img.rgb[8] = 6.5e4;
        let path = std::env::temp_dir().join(format!("wavetrace-exr-{}.exr", std::process::id()));
        write_exr(&path, &img).unwrap();
        let back = read_exr(&path).unwrap();
        assert_eq!(back, img);
        let _ = std::fs::remove_file(path);
    }

    #[test]
    fn errors_name_the_file() {
        let e = read_exr(Path::new("/nonexistent/x.exr")).unwrap_err();
        assert!(e.to_string().starts_with("/nonexistent/x.exr: "), "{e}");
    }
}
