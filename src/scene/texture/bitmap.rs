//! `bitmap`: an image file (EXR or Radiance HDR: linear; PNG or JPEG: sRGB, converted
//! to linear unless `raw` = true), as Mitsuba 3.9.1's `bitmap`.
//!
//! ```xml
//! <texture type="bitmap" name="reflectance"><string name="filename" value="bricks.jpg"/></texture>
//! ```

use super::{load_image, Texture, Wrap, TO_UV};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::{Dialect, Element};
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Texture,
    Dialect::Mitsuba,
    "bitmap",
    "An image (EXR, HDR: linear; PNG, JPEG: sRGB), row 0 at v = 0.",
    &[
        Param::new("filename", "string", "", "the image (required)"),
        Param::new("raw", "boolean", "false", "take 8-bit images as linear"),
        Param::new("filter_type", "string", "bilinear", "bilinear or nearest"),
        Param::new("wrap_mode", "string", "repeat", "repeat, mirror or clamp"),
        TO_UV,
        Param::new("format", "string", "", "read and ignored"),
        Param::new("accel", "boolean", "", "read and ignored"),
    ],
);

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
    props.ignore(&["format", "accel"]);
    let path = el
        .resolve(&name)
        .map_err(|tried| props.error("filename", format!("image file {tried} not found")))?;
    let (width, height, texels) = load_image(&path, raw).map_err(|e| props.error("filename", e))?;
    Ok(Texture::Bitmap {
        width,
        height,
        texels,
        nearest,
        wrap,
        to_uv,
    })
}
