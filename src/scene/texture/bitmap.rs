//! `bitmap`: an image file, as Mitsuba 3.9.1's `bitmap` (src/textures/bitmap.cpp).
//!
//! Every format Mitsuba reads ([`super::read_image`]): PNG, JPEG, BMP, TGA, PPM
//! (8 or 16 bits, sRGB-encoded: decoded to linear unless `raw`), OpenEXR, RGBE `.hdr`
//! and PFM (floats, linear). `filter_type` (`bilinear` | `nearest`), `wrap_mode`
//! (`repeat` | `mirror` | `clamp`) and `to_uv` act as in Mitsuba (texture.glsl and
//! [`super::filtered_lookup`]). `format` is Mitsuba's storage precision, honoured by
//! rounding the texels as that storage would hold them: `auto` (8-bit sources as 8
//! bits, 16-bit ones as half floats, float ones as they are), `variant` (floats),
//! `float16` (also `fp16`: half floats, after the sRGB decoding) or `uint8` (8 bits
//! per channel, of the sRGB-encoded values for sRGB sources, else of the linear ones
//! clamped to [0, 1]). An 8-bit texel is decoded before it is interpolated, as
//! Mitsuba's, so `uint8` and `variant` look up the same values. `accel` (CUDA
//! hardware lookups) is read and ignored.
//!
//! ```xml
//! <texture type="bitmap" name="reflectance"><string name="filename" value="bricks.jpg"/></texture>
//! ```

use super::{read_image, srgb_to_linear, Depth, Texture, Wrap, TO_UV};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::{Dialect, Element};
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Texture,
    Dialect::Mitsuba,
    "bitmap",
    "An image (PNG, JPEG, BMP, TGA, PPM: sRGB; EXR, HDR, PFM: linear), row 0 at v = 0.",
    &[
        Param::new("filename", "string", "", "the image (required)"),
        Param::new(
            "raw",
            "boolean",
            "false",
            "no sRGB decoding of integer images",
        ),
        Param::new("filter_type", "string", "bilinear", "bilinear or nearest"),
        Param::new("wrap_mode", "string", "repeat", "repeat, mirror or clamp"),
        TO_UV,
        Param::new(
            "format",
            "string",
            "auto",
            "storage precision: auto, variant, float16 (fp16) or uint8",
        ),
        Param::new("accel", "boolean", "true", "read and ignored"),
    ],
);

/// Mitsuba's storage precision of a bitmap (`format`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Storage {
    Float,
    Half,
    Byte,
}

/// A Mitsuba `bitmap` texture.
pub fn mitsuba(props: &Properties, el: &Element, to_uv: [[f32; 3]; 2]) -> Result<Texture, Error> {
    let name = props
        .string_opt("filename")?
        .ok_or_else(|| props.object_error("bitmap texture needs a 'filename'"))?;
    let raw = props.boolean("raw", false)?;
    let nearest = match props.string("filter_type", "bilinear")?.as_str() {
        "bilinear" => false,
        "nearest" => true,
        other => {
            return Err(props.error(
                "filter_type",
                format!("filter_type must be bilinear or nearest, found '{other}'"),
            ))
        }
    };
    let wrap = match props.string("wrap_mode", "repeat")?.as_str() {
        "repeat" => Wrap::Repeat,
        "mirror" => Wrap::Mirror,
        "clamp" => Wrap::Clamp,
        other => {
            return Err(props.error(
                "wrap_mode",
                format!("wrap_mode must be repeat, mirror or clamp, found '{other}'"),
            ))
        }
    };
    let storage = match props.string("format", "auto")?.as_str() {
        "auto" => None,
        "variant" => Some(Storage::Float),
        "float16" | "fp16" => Some(Storage::Half),
        "uint8" => Some(Storage::Byte),
        other => {
            return Err(props.error(
                "format",
                format!("format must be auto, variant, float16 or uint8, found '{other}'"),
            ))
        }
    };
    props.boolean("accel", true)?;
    let path = el
        .resolve(&name)
        .map_err(|tried| props.error("filename", format!("image file {tried} not found")))?;
    let img = read_image(&path).map_err(|e| props.error("filename", e))?;
    let (width, height) = (img.width, img.height);
    let texels = stored_texels(img, raw, storage);
    Ok(Texture::Bitmap {
        width,
        height,
        texels,
        nearest,
        wrap,
        to_uv,
    })
}

/// The linear texels of `img` as a bitmap of `storage` (None: `auto`) holds them.
pub fn stored_texels(
    img: super::SourceImage,
    raw: bool,
    storage: Option<Storage>,
) -> Vec<[f32; 3]> {
    let storage = storage.unwrap_or(match img.depth {
        Depth::U8 => Storage::Byte,
        Depth::U16 => Storage::Half,
        Depth::F32 => Storage::Float,
    });
    let srgb = img.srgb && !raw;
    let depth = img.depth;
    let mut texels = img.texels;
    for c in texels.iter_mut().flatten() {
        *c = match storage {
            Storage::Float => *c,
            // An 8-bit source's values are 8-bit already.
            Storage::Byte if depth == Depth::U8 => *c,
            // Rounded half to even, as Mitsuba's conversion (0.3 -> 76, 0.5 -> 128).
            Storage::Byte => (c.clamp(0.0, 1.0) * 255.0).round_ties_even() / 255.0,
            // Half of the decoded value (below).
            Storage::Half => *c,
        };
        if srgb {
            *c = srgb_to_linear(*c);
        }
        if storage == Storage::Half {
            *c = half::f16::from_f32(*c).to_f32();
        }
    }
    texels
}

#[cfg(test)]
mod tests {
    use super::super::SourceImage;
    use super::*;

    fn source(texels: Vec<[f32; 3]>, depth: Depth) -> SourceImage {
        SourceImage {
            width: texels.len() as u32,
            height: 1,
            texels,
            depth,
            srgb: depth != Depth::F32,
        }
    }

    fn close(got: &[[f32; 3]], want: &[[f32; 3]], tol: f32) {
        for (g, w) in got.iter().zip(want) {
            for c in 0..3 {
                assert!((g[c] - w[c]).abs() <= tol, "{got:?}\n vs {want:?}");
            }
        }
    }

    /// Values Mitsuba 3.9.1 (scalar_rgb, nearest) returns for an EXR and a 16-bit PNG
    /// in each `format`.
    #[test]
    fn formats_store_as_mitsuba() {
        let exr = || source(vec![[2.0, 0.3, 0.123_456_7], [0.5, -0.2, 0.77]], Depth::F32);
        let f = |s| stored_texels(exr(), false, s);
        close(&f(None), &[[2.0, 0.3, 0.123_456_7], [0.5, -0.2, 0.77]], 0.0);
        close(
            &f(Some(Storage::Half)),
            &[[2.0, 0.300_049, 0.123_474], [0.5, -0.199_951, 0.770_02]],
            1e-6,
        );
        close(
            &f(Some(Storage::Byte)),
            &[[1.0, 0.298_039, 0.121_569], [0.501_961, 0.0, 0.768_628]],
            1e-6,
        );
        let png16 = || {
            let v = |x: f32| x / 65535.0;
            source(
                vec![
                    [v(1000.0), v(30000.0), v(65535.0)],
                    [0.0, v(12345.0), v(40000.0)],
                ],
                Depth::U16,
            )
        };
        let g = |s| stored_texels(png16(), false, s);
        let auto = [
            [0.001_180_65, 0.177_002, 1.0],
            [0.0, 0.029_602_1, 0.330_811],
        ];
        close(&g(None), &auto, 2e-6);
        close(&g(Some(Storage::Half)), &auto, 2e-6);
        close(
            &g(Some(Storage::Float)),
            &[
                [0.001_181_04, 0.177_015, 1.0],
                [0.0, 0.029_596_9, 0.330_774],
            ],
            2e-6,
        );
        close(
            &g(Some(Storage::Byte)),
            &[
                [0.001_214_11, 0.177_888, 1.0],
                [0.0, 0.029_556_8, 0.332_451],
            ],
            2e-6,
        );
        // raw: no decoding.
        let raw = stored_texels(png16(), true, Some(Storage::Float));
        close(&raw, &png16().texels, 0.0);
    }
}
