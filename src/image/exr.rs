//! OpenEXR files.
//!
//! Reading takes the R, G and B channels of the first layer that has them, whatever
//! their sample type (half, float or uint) and whether or not there is an alpha channel,
//! so EXRs written by Mitsuba (`hdrfilm`, RGB or RGBA, float16 or float32), Nori and
//! OpenEXR tools all load. Alpha is ignored: renders here are opaque.
//!
//! Writing produces one layer of three float32 channels R, G, B, ZIP-compressed in
//! blocks of 16 scan lines (lossless, small for the reference images in `scenes/refs`);
//! [`write_channels`] writes any named channels in half or single precision (a film's
//! RGBA, luminance or XYZ output), and [`read_channels`] reads them all back.

use std::path::Path;

use ::exr::meta::BlockDescription;
use ::exr::prelude::{
    f16, read_first_rgba_layer_from_file, AnyChannel, AnyChannels, AttributeValue, Encoding,
    FlatSamples, Image as ExrImage, Layer, LayerAttributes, SmallVec, SpecificChannels, Text, Vec2,
    WritableImage,
};

use super::{Error, Image};

/// Reads the R, G, B channels of the first layer of an EXR file as a linear image.
pub fn read(path: impl AsRef<Path>) -> Result<Image, Error> {
    let path = path.as_ref();
    check_size(path)?;
    let exr = read_first_rgba_layer_from_file(
        path,
        |size, _channels| match (u32::try_from(size.width()), u32::try_from(size.height())) {
            (Ok(width), Ok(height)) => Some(Image::new(width, height)),
            _ => None,
        },
        |image: &mut Option<Image>, position, (r, g, b, _a): (f32, f32, f32, f32)| {
            if let Some(image) = image {
                image.set_pixel(position.x() as u32, position.y() as u32, [r, g, b]);
            }
        },
    )
    .map_err(|cause| Error::Exr {
        path: path.to_owned(),
        cause,
    })?;
    exr.layer_data
        .channel_data
        .pixels
        .ok_or_else(|| Error::Format {
            path: path.to_owned(),
            message: "image too large".into(),
        })
}

/// Reads the headers of an EXR file and refuses it if a layer has more than
/// [`super::MAX_TEXELS`] pixels: the EXR format allows 10^9 x 10^9, and the pixel
/// storage is allocated from the header before any pixel is read.
fn check_size(path: &Path) -> Result<(), Error> {
    let meta = ::exr::meta::MetaData::read_from_file(path, false).map_err(|cause| Error::Exr {
        path: path.to_owned(),
        cause,
    })?;
    let refuse = |message| Error::Format {
        path: path.to_owned(),
        message,
    };
    for header in &meta.headers {
        let size = header.layer_size;
        super::check_texels(size.width() as u64, size.height() as u64).map_err(refuse)?;
        // The exr crate reserves a block's claimed byte count before reading it,
        // trusting the claim up to the largest block the header allows: bound that.
        let pixels = match header.blocks {
            BlockDescription::Tiles(t) => {
                (t.tile_size.width() as u64).checked_mul(t.tile_size.height() as u64)
            }
            BlockDescription::ScanLines => {
                (header.compression.scan_lines_per_block() as u64).checked_mul(size.width() as u64)
            }
        };
        let bytes = pixels.and_then(|p| p.checked_mul(header.channels.bytes_per_pixel as u64));
        if bytes.is_none_or(|b| b > MAX_BLOCK_BYTES) {
            return Err(refuse(format!(
                "blocks of {} pixels x {} bytes, over the {} MiB wavetrace reads",
                pixels.map_or("too many".to_string(), |p| p.to_string()),
                header.channels.bytes_per_pixel,
                MAX_BLOCK_BYTES >> 20
            )));
        }
    }
    Ok(())
}

/// The largest uncompressed block (a tile, or a run of scan lines) an EXR may have:
/// a scan-line block of a 65536-wide RGBA float image with PIZ compression (32 lines)
/// is 32 MiB. Fuzz builds lower it with [`super::MAX_TEXELS`].
const MAX_BLOCK_BYTES: u64 = if cfg!(fuzzing) { 16 << 20 } else { 256 << 20 };

/// Writes an image as an EXR file with float32 R, G, B channels.
pub fn write(image: &Image, path: impl AsRef<Path>) -> Result<(), Error> {
    let path = path.as_ref();
    let channels = SpecificChannels::rgb(|position: Vec2<usize>| {
        let [r, g, b] = image.pixel(position.x() as u32, position.y() as u32);
        (r, g, b)
    });
    let size = (image.width as usize, image.height as usize);
    ExrImage::from_encoded_channels(size, Encoding::SMALL_LOSSLESS, channels)
        .write()
        .to_file(path)
        .map_err(|cause| Error::Exr {
            path: path.to_owned(),
            cause,
        })
}

/// The precision of the channels [`write_channels`] writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Precision {
    /// 16-bit floats (OpenEXR `HALF`): values above 65504 become infinite.
    Half,
    Float,
}

/// Writes one layer of channels named `names`, `data` holding `names.len()` values per
/// pixel, interleaved, top row first. Channels are stored sorted by name, as OpenEXR
/// requires (readers find them by name).
pub fn write_channels(
    path: impl AsRef<Path>,
    width: u32,
    height: u32,
    names: &[&str],
    data: &[f32],
    precision: Precision,
) -> Result<(), Error> {
    write_channels_with_text(path, width, height, names, data, precision, &[])
}

/// [`write_channels`], with up to two text attributes `(name, value)` in the header
/// (UTF-8; OpenEXR's `string` type, which readers that do not know them skip). The exr
/// crate keeps a header's own attributes in hash maps, written in their (random)
/// iteration order; with at most one in each of its two maps (the layer's and the
/// image's) the same image is always the same bytes.
pub fn write_channels_with_text(
    path: impl AsRef<Path>,
    width: u32,
    height: u32,
    names: &[&str],
    data: &[f32],
    precision: Precision,
    text: &[(&str, &str)],
) -> Result<(), Error> {
    let path = path.as_ref();
    let n = names.len();
    if n == 0 || data.len() != n * width as usize * height as usize {
        return Err(Error::Format {
            path: path.to_owned(),
            message: format!(
                "{} values for a {width}x{height} image of {n} channels",
                data.len()
            ),
        });
    }
    let mut channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::new();
    for (c, name) in names.iter().enumerate() {
        let values = data.iter().skip(c).step_by(n).copied();
        let samples = match precision {
            Precision::Half => FlatSamples::F16(values.map(f16::from_f32).collect()),
            Precision::Float => FlatSamples::F32(values.collect()),
        };
        channels.push(AnyChannel::new(*name, samples));
    }
    if text.len() > 2 {
        return Err(Error::Format {
            path: path.to_owned(),
            message: format!(
                "{} text attributes, at most 2 keep a file's bytes fixed",
                text.len()
            ),
        });
    }
    let attribute = |(name, value): &(&str, &str)| {
        (
            Text::from_slice_unchecked(name.as_bytes()),
            AttributeValue::Text(Text::from_slice_unchecked(value.as_bytes())),
        )
    };
    let mut attributes = LayerAttributes::default();
    attributes.other.extend(text.first().map(attribute));
    let layer = Layer::new(
        (width as usize, height as usize),
        attributes,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels),
    );
    let mut image = ExrImage::from_layer(layer);
    image.attributes.other.extend(text.get(1).map(attribute));
    image.write().to_file(path).map_err(|cause| Error::Exr {
        path: path.to_owned(),
        cause,
    })
}

/// One channel of an EXR file read by [`read_channels`].
#[derive(Debug, Clone, PartialEq)]
pub struct Channel {
    pub name: String,
    /// Whether it was stored as 16-bit floats.
    pub half: bool,
    /// Its values, row-major, top row first.
    pub values: Vec<f32>,
}

/// Reads every channel of the first layer of an EXR file: (width, height, channels
/// in the file's order, which is by name).
pub fn read_channels(path: impl AsRef<Path>) -> Result<(u32, u32, Vec<Channel>), Error> {
    read_channels_with_text(path).map(|(w, h, channels, _)| (w, h, channels))
}

/// The text attributes of an EXR header (name, value; UTF-8, lossily), as
/// [`write_channels_with_text`] writes them.
pub type TextAttributes = Vec<(String, String)>;

/// [`read_channels`], and the text attributes of the image's and the layer's header.
pub fn read_channels_with_text(
    path: impl AsRef<Path>,
) -> Result<(u32, u32, Vec<Channel>, TextAttributes), Error> {
    use ::exr::prelude::traits::*;
    let path = path.as_ref();
    check_size(path)?;
    let image = ::exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|cause| Error::Exr {
            path: path.to_owned(),
            cause,
        })?;
    let layer = image.layer_data;
    let text = image
        .attributes
        .other
        .iter()
        .chain(&layer.attributes.other)
        .filter_map(|(name, value)| match value {
            AttributeValue::Text(t) => Some((
                String::from_utf8_lossy(name.as_slice()).into_owned(),
                String::from_utf8_lossy(t.as_slice()).into_owned(),
            )),
            _ => None,
        })
        .collect();
    let channels = layer
        .channel_data
        .list
        .iter()
        .map(|c| Channel {
            name: c.name.to_string(),
            half: matches!(c.sample_data, FlatSamples::F16(_)),
            values: c.sample_data.values_as_f32().collect(),
        })
        .collect();
    Ok((
        layer.size.width() as u32,
        layer.size.height() as u32,
        channels,
        text,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    /// A path in the system temp folder, unique to this test process and `name`.
    fn temp_path(name: &str) -> PathBuf {
        std::env::temp_dir().join(format!("wavetrace-{}-{name}", std::process::id()))
    }

    fn gradient(width: u32, height: u32) -> Image {
        let mut image = Image::new(width, height);
        for y in 0..height {
            for x in 0..width {
                // Values that need all of float32's bits, plus a negative and a large one.
                let v = (x as f32 + 0.1) / (y as f32 + 0.3);
                image.set_pixel(x, y, [v, -v, 1.0e6 * v]);
            }
        }
        image
    }

    #[test]
    fn round_trip_is_exact() {
        let path = temp_path("round_trip.exr");
        let image = gradient(37, 19);
        write(&image, &path).unwrap();
        let back = read(&path).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!(back, image);
    }

    #[test]
    fn reads_half_rgba_taking_rgb() {
        let path = temp_path("half_rgba.exr");
        // Quarters are exact in half precision.
        ::exr::prelude::write_rgba_file(&path, 4, 3, |x, y| {
            (
                f16::from_f32(x as f32 * 0.25),
                f16::from_f32(y as f32 * 0.25),
                f16::from_f32(2.0),
                f16::from_f32(0.5),
            )
        })
        .unwrap();
        let image = read(&path).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!((image.width, image.height), (4, 3));
        assert_eq!(image.pixel(3, 2), [0.75, 0.5, 2.0]);
        assert_eq!(image.pixel(0, 1), [0.0, 0.25, 2.0]);
    }

    /// `testdata/mitsuba_rgba_f16.exr` was written by Mitsuba 3's `Bitmap` (OpenEXR
    /// library): 8x4, RGBA float16, pixel (x, y) = (x/8, y/4, 0.25, 0.5). See
    /// `tools/make_image_testdata.py`.
    #[test]
    fn reads_mitsuba_rgba_half_exr() {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("src/image/testdata/mitsuba_rgba_f16.exr");
        let image = read(path).unwrap();
        assert_eq!((image.width, image.height), (8, 4));
        for y in 0..4 {
            for x in 0..8 {
                assert_eq!(image.pixel(x, y), [x as f32 / 8.0, y as f32 / 4.0, 0.25]);
            }
        }
    }

    /// The AO reference rendered by Mitsuba 3 (`tools/mitsuba_ref.py`): RGB float32.
    #[test]
    fn reads_mitsuba_reference() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/refs/ao.exr");
        let image = read(path).unwrap();
        assert_eq!((image.width, image.height), (128, 128));
        assert_eq!(image.non_finite_count(), 0);
        // Ambient occlusion lies in [0, 1]; allow for Monte Carlo noise above 1.
        assert!(image.rgb.iter().all(|&v| (0.0..1.05).contains(&v)));
    }

    #[test]
    fn channels_round_trip_in_half_and_float() {
        let path = temp_path("channels.exr");
        // 3x2 pixels of (Y, A), values exact in half precision.
        let data: Vec<f32> = (0..12).map(|i| i as f32 * 0.25 - 1.0).collect();
        for precision in [Precision::Half, Precision::Float] {
            write_channels(&path, 3, 2, &["Y", "A"], &data, precision).unwrap();
            let (w, h, channels) = read_channels(&path).unwrap();
            assert_eq!((w, h), (3, 2));
            let names: Vec<&str> = channels.iter().map(|c| c.name.as_str()).collect();
            assert_eq!(names, ["A", "Y"]);
            for c in &channels {
                assert_eq!(c.half, precision == Precision::Half);
            }
            let y: Vec<f32> = data.iter().step_by(2).copied().collect();
            let a: Vec<f32> = data.iter().skip(1).step_by(2).copied().collect();
            assert_eq!(channels[1].values, y);
            assert_eq!(channels[0].values, a);
        }
        // RGBA files also read as RGB images.
        write_channels(
            &path,
            1,
            1,
            &["R", "G", "B", "A"],
            &[1.0, 2.0, 3.0, 0.5],
            Precision::Half,
        )
        .unwrap();
        assert_eq!(read(&path).unwrap().pixel(0, 0), [1.0, 2.0, 3.0]);
        std::fs::remove_file(&path).ok();
        assert!(write_channels(&path, 2, 2, &["Y"], &[0.0; 3], Precision::Float).is_err());
    }

    #[test]
    fn text_attributes_round_trip_and_keep_the_bytes_fixed() {
        let (a, b) = (temp_path("text_a.exr"), temp_path("text_b.exr"));
        let text = [
            ("wavetrace.one", "{\"x\": 1}"),
            ("wavetrace.two", "2 of 3 ü"),
        ];
        for p in [&a, &b] {
            write_channels_with_text(p, 1, 1, &["Y"], &[0.5], Precision::Float, &text).unwrap();
        }
        let (_, _, channels, read) = read_channels_with_text(&a).unwrap();
        assert_eq!(channels[0].values, [0.5]);
        for (k, v) in text {
            assert!(read.iter().any(|(rk, rv)| rk == k && rv == v), "{read:?}");
        }
        assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
        std::fs::remove_file(&a).ok();
        std::fs::remove_file(&b).ok();
    }

    #[test]
    fn missing_file_names_the_file() {
        let err = read("/nonexistent/wavetrace.exr").unwrap_err();
        assert!(
            err.to_string().starts_with("/nonexistent/wavetrace.exr: "),
            "{err}"
        );
    }
}
