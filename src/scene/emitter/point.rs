//! `point`: an isotropic point light ([`Emitter::Point`]).
//!
//! Mitsuba 3: `position` or `to_world` (its translation), `intensity` in W/sr.
//! Nori: `position`, `power` in W (intensity = power / 4π).
//!
//! ```xml
//! <emitter type="point"><point name="position" value="0,4,0"/><rgb name="intensity" value="10"/></emitter>
//! ```

use glam::Vec3;

use crate::gpu::layout::{EmitterRecord, EMITTER_POINT, NONE};

use super::{Emitter, SAMPLING_WEIGHT};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Emitter,
    Dialect::Mitsuba,
    "point",
    "An isotropic point light.",
    &[
        Param::new(
            "position",
            "point",
            "0,0,0",
            "where the light sits (or give to_world)",
        ),
        Param::new(
            "to_world",
            "transform",
            "identity",
            "places the light at its translation",
        ),
        Param::new("intensity", "rgb", "1", "radiant intensity (W/sr)"),
        SAMPLING_WEIGHT,
    ],
);

pub const NORI: PluginDoc = PluginDoc::new(
    Family::Emitter,
    Dialect::Nori,
    "point",
    "An isotropic point light.",
    &[
        Param::new("position", "point", "0,0,0", "where the light sits"),
        Param::new(
            "power",
            "color",
            "",
            "radiant power (W; required); intensity = power / 4π",
        ),
    ],
);

/// A Mitsuba `point` emitter.
pub fn mitsuba(props: &Properties) -> Result<Emitter, Error> {
    let position = match (
        props.point_opt("position")?,
        props.transform_opt("to_world")?,
    ) {
        (Some(_), Some(_)) => {
            return Err(props.error("position", "give either 'position' or 'to_world', not both"))
        }
        (Some(p), None) => p,
        (None, Some(m)) => m.w_axis.truncate(),
        (None, None) => Vec3::ZERO,
    };
    Ok(Emitter::Point {
        position,
        intensity: props.color("intensity", Vec3::ONE)?,
    })
}

/// A Nori `point` emitter.
pub fn nori(props: &Properties) -> Result<Emitter, Error> {
    Ok(Emitter::Point {
        position: props.point("position", Vec3::ZERO)?,
        intensity: props
            .color_opt("power")?
            .ok_or_else(|| props.object_error("point emitter needs a 'power'"))?
            / (4.0 * std::f32::consts::PI),
    })
}

/// The GPU record of a point light.
pub fn record(position: Vec3, intensity: Vec3) -> EmitterRecord {
    EmitterRecord {
        position: position.into(),
        kind: EMITTER_POINT,
        radiance: intensity.into(),
        shape: NONE,
        ..Default::default()
    }
}
