//! `marble` (wavetrace's): stripes along u bent by the fBm of [`super::noise`],
//! through a cosine: t = ½ − ½ cos(2π (`frequency` u + `variation` n)), blending
//! `color0` and `color1` (Perlin 1985, "An Image Synthesizer", marble).
//!
//! ```xml
//! <texture type="marble" name="reflectance"><float name="variation" value="2"/></texture>
//! ```

use super::noise::{fbm, COLOR0, COLOR1, OCTAVES, SEED};
use super::{Texture, TO_UV};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Texture,
    Dialect::Mitsuba,
    "marble",
    "wavetrace's marble: stripes along u bent by Perlin-noise fBm.",
    &[
        Param::new("frequency", "float", "4", "stripes per unit u"),
        Param::new(
            "variation",
            "float",
            "1",
            "how much the noise bends the stripes",
        ),
        OCTAVES,
        SEED,
        COLOR0,
        COLOR1,
        TO_UV,
    ],
);

/// A `marble` texture.
pub fn mitsuba(props: &Properties, to_uv: [[f32; 3]; 2]) -> Result<Texture, Error> {
    let f = fbm(props, 4.0)?;
    let variation = props.float("variation", 1.0)?;
    if !variation.is_finite() {
        return Err(props.error("variation", "variation must be finite"));
    }
    Ok(Texture::Marble {
        color0: f.color0,
        color1: f.color1,
        frequency: f.frequency,
        variation,
        octaves: f.octaves,
        seed: f.seed,
        to_uv,
    })
}
