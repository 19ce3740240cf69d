//! `noise` (wavetrace's; Mitsuba has none): Perlin gradient noise (Perlin 2002,
//! "Improving Noise": quintic fade, hashed lattice gradients) summed over `octaves` as
//! fractal Brownian motion, each octave at twice the frequency and half the amplitude.
//! The sum n in [-1, 1] blends `color0` and `color1` by t = ½ + ½ n.
//!
//! ```xml
//! <texture type="noise" name="reflectance"><float name="frequency" value="16"/><integer name="octaves" value="5"/></texture>
//! ```

use glam::Vec3;

use super::{Texture, MAX_OCTAVES, TO_UV};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const OCTAVES: Param = Param::new("octaves", "integer", "4", "fBm octaves, in 1..=16");
pub const SEED: Param = Param::new("seed", "integer", "0", "noise seed");
pub const COLOR0: Param = Param::new("color0", "rgb", "0", "color at t = 0");
pub const COLOR1: Param = Param::new("color1", "rgb", "1", "color at t = 1");

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Texture,
    Dialect::Mitsuba,
    "noise",
    "wavetrace's Perlin-noise fBm blending two colors.",
    &[
        Param::new("frequency", "float", "8", "lattice cells per unit uv"),
        OCTAVES,
        SEED,
        COLOR0,
        COLOR1,
        TO_UV,
    ],
);

/// What `noise` and `marble` share: frequency, octaves, seed and the two colors.
pub struct Fbm {
    pub frequency: f32,
    pub octaves: u32,
    pub seed: u32,
    pub color0: Vec3,
    pub color1: Vec3,
}

/// Reads the fBm parameters (`frequency` defaulting to `default_frequency`).
pub fn fbm(props: &Properties, default_frequency: f32) -> Result<Fbm, Error> {
    let frequency = props.float("frequency", default_frequency)?;
    if !(frequency.is_finite() && frequency > 0.0) {
        return Err(props.error("frequency", "frequency must be positive"));
    }
    let octaves = props.integer("octaves", 4)?;
    if !(1..=MAX_OCTAVES as i64).contains(&octaves) {
        return Err(props.error(
            "octaves",
            format!("octaves must be in 1..={MAX_OCTAVES}, found {octaves}"),
        ));
    }
    let seed = props.integer("seed", 0)?;
    if !(0..=u32::MAX as i64).contains(&seed) {
        return Err(props.error("seed", "seed must be a non-negative 32-bit integer"));
    }
    let (color0, color1) = (
        props.color("color0", Vec3::ZERO)?,
        props.color("color1", Vec3::ONE)?,
    );
    Ok(Fbm {
        frequency,
        octaves: octaves as u32,
        seed: seed as u32,
        color0,
        color1,
    })
}

/// A `noise` texture.
pub fn mitsuba(props: &Properties, to_uv: [[f32; 3]; 2]) -> Result<Texture, Error> {
    let f = fbm(props, 8.0)?;
    Ok(Texture::Noise {
        color0: f.color0,
        color1: f.color1,
        frequency: f.frequency,
        octaves: f.octaves,
        seed: f.seed,
        to_uv,
    })
}
