//! Portable float maps (`.pfm`): a text header, then float32 samples, bottom row first.
//!
//! Header: `PF` (three channels) or `Pf` (one), the width and height, and a scale
//! whose sign gives the byte order (negative: little endian). This writes little
//! endian with scale -1, as Mitsuba does; [`read`] takes either byte order and, as
//! Mitsuba's `Bitmap::read_pfm`, multiplies the samples by |scale|.

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

/// Reads a PFM file: (width, height, channels (1 or 3), samples interleaved, top row
/// first). The size is checked against [`super::MAX_TEXELS`] before anything is
/// allocated; a file shorter than its header says is an error.
pub fn read(path: impl AsRef<Path>) -> Result<(u32, u32, usize, Vec<f32>), Error> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|cause| Error::Io {
        path: path.to_owned(),
        cause,
    })?;
    parse(&bytes).map_err(|message| Error::Format {
        path: path.to_owned(),
        message,
    })
}

/// [`read`] on the file's bytes.
fn parse(bytes: &[u8]) -> Result<(u32, u32, usize, Vec<f32>), String> {
    let channels = match bytes.get(..2) {
        Some(b"PF") => 3,
        Some(b"Pf") => 1,
        _ => return Err("not a PFM file (no 'PF' or 'Pf' header)".into()),
    };
    // Three whitespace-separated tokens after the tag, then one whitespace byte.
    let mut at = 2;
    let mut token = || -> Result<&[u8], String> {
        while bytes.get(at).is_some_and(u8::is_ascii_whitespace) {
            at += 1;
        }
        let start = at;
        while bytes.get(at).is_some_and(|b| !b.is_ascii_whitespace()) {
            at += 1;
        }
        if start == at || at >= bytes.len() {
            return Err("truncated PFM header".into());
        }
        Ok(&bytes[start..at])
    };
    let number = |t: &[u8]| std::str::from_utf8(t).ok().map(str::to_owned);
    let (w, h, scale) = (number(token()?), number(token()?), number(token()?));
    let bad = || "could not parse the PFM header (width, height, scale)".to_string();
    let width: u32 = w.and_then(|s| s.parse().ok()).ok_or_else(bad)?;
    let height: u32 = h.and_then(|s| s.parse().ok()).ok_or_else(bad)?;
    let scale: f32 = scale
        .and_then(|s| s.parse().ok())
        .filter(|s: &f32| s.is_finite() && *s != 0.0)
        .ok_or_else(bad)?;
    super::check_texels(width.into(), height.into())?;
    let data_start = at + 1;
    let row = width as usize * channels;
    let count = row * height as usize;
    let data = bytes
        .get(data_start..)
        .filter(|d| d.len() >= 4 * count)
        .ok_or_else(|| {
            format!("PFM data is truncated ({width} x {height} x {channels} floats expected)")
        })?;
    let little = scale < 0.0;
    let factor = scale.abs();
    let mut out = vec![0.0f32; count];
    // Rows are stored bottom row first.
    for (y, dst) in out.chunks_mut(row.max(1)).enumerate() {
        let src = &data[4 * row * (height as usize - 1 - y)..];
        for (x, v) in dst.iter_mut().enumerate() {
            let b = [src[4 * x], src[4 * x + 1], src[4 * x + 2], src[4 * x + 3]];
            let f = if little {
                f32::from_le_bytes(b)
            } else {
                f32::from_be_bytes(b)
            };
            *v = if factor == 1.0 { f } else { f * factor };
        }
    }
    Ok((width, height, channels, out))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_what_it_writes_and_big_endian() {
        let path = std::env::temp_dir().join(format!("wavetrace-{}-r.pfm", std::process::id()));
        let data: Vec<f32> = (0..12).map(|i| i as f32 * 0.25 - 1.0).collect();
        write(&path, 2, 2, 3, &data).unwrap();
        let got = read(&path).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!(got, (2, 2, 3, data));
        // Big endian (positive scale), scale 2, one channel, 2 x 1.
        let mut bytes = b"Pf\n2 1\n2.0\n".to_vec();
        for v in [1.5f32, -3.0] {
            bytes.extend_from_slice(&v.to_be_bytes());
        }
        assert_eq!(parse(&bytes).unwrap(), (2, 1, 1, vec![3.0, -6.0]));
        assert!(parse(&bytes[..bytes.len() - 1])
            .unwrap_err()
            .contains("truncated"));
        assert!(parse(b"PF\n2").is_err());
        assert!(parse(b"P6\n2 2\n255\n").is_err());
        assert!(parse(b"PF\n100000 100000\n-1\n")
            .unwrap_err()
            .contains("more than"));
    }

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
