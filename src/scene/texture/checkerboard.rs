//! `checkerboard`: `color0` where (u mod 1 > ½) equals (v mod 1 > ½), `color1`
//! elsewhere, as Mitsuba 3.9.1's.
//!
//! ```xml
//! <texture type="checkerboard" name="reflectance"><rgb name="color0" value="0.8"/></texture>
//! ```

use glam::Vec3;

use super::{Texture, TO_UV};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Texture,
    Dialect::Mitsuba,
    "checkerboard",
    "Two colors in a checker pattern of 2 x 2 cells per unit uv.",
    &[
        Param::new("color0", "rgb", "0.4", "first color"),
        Param::new("color1", "rgb", "0.2", "second color"),
        TO_UV,
    ],
);

/// A Mitsuba `checkerboard` texture.
pub fn mitsuba(props: &Properties, to_uv: [[f32; 3]; 2]) -> Result<Texture, Error> {
    Ok(Texture::Checkerboard {
        color0: props.color("color0", Vec3::splat(0.4))?,
        color1: props.color("color1", Vec3::splat(0.2))?,
        to_uv,
    })
}
