//! Portable float maps (`.pfm`): a text header, then float32 samples, bottom row first.
//!
//! Header: `PF` (three channels) or `Pf` (one), the width and height, and a scale
//! whose sign gives the byte order (negative: little endian). This writes little
//! endian with scale -1, as Mitsuba does.

use std::io::Write;
use std::path::Path;

use super::Error;

/// Writes `data` (`channels` interleaved floats per pixel, top row first; 1 or 3
/// channels) as a PFM file.
pub fn write(
    path: impl AsRef<Path>,
    width: u32,
    height: u32,
    channels: usize,
    data: &[f32],
) -> Result<(), Error> {
    let path = path.as_ref();
    let format_error = |message: String| Error::Format {
        path: path.to_owned(),
        message,
    };
    let tag = match channels {
        1 => "Pf",
        3 => "PF",
        n => return Err(format_error(format!("PFM holds 1 or 3 channels, not {n}"))),
    };
    let row = width as usize * channels;
    if data.len() != row * height as usize {
        return Err(format_error(format!(
            "{} values for a {width}x{height} image of {channels} channels",
            data.len()
        )));
    }
    let mut bytes = format!("{tag}\n{width} {height}\n-1.0\n").into_bytes();
    bytes.reserve(data.len() * 4);
    for y in (0..height as usize).rev() {
        for v in &data[y * row..(y + 1) * row] {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    std::fs::File::create(path)
        .and_then(|mut f| f.write_all(&bytes))
        .map_err(|cause| Error::Io {
            path: path.to_owned(),
            cause,
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_and_bottom_up_rows() {
        let path = std::env::temp_dir().join(format!("wavetrace-{}-t.pfm", std::process::id()));
        // 2x2 RGB: row 0 = pixels 0, 1; row 1 = pixels 2, 3.
        let data: Vec<f32> = (0..12).map(|i| i as f32 * 0.5 - 1.0).collect();
        write(&path, 2, 2, 3, &data).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        std::fs::remove_file(&path).ok();
        let header = b"PF\n2 2\n-1.0\n";
        assert_eq!(&bytes[..header.len()], header);
        let floats: Vec<f32> = bytes[header.len()..]
            .chunks(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        // The bottom row (pixels 2, 3) comes first.
        assert_eq!(&floats[..6], &data[6..]);
        assert_eq!(&floats[6..], &data[..6]);
        assert!(write(&path, 2, 2, 2, &data[..8]).is_err());
    }
}
