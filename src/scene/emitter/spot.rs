//! `spot`: a spot light ([`Emitter::Spot`]), as Mitsuba 3's spotlight: full intensity
//! inside the beam width, falling linearly in angle to 0 at the cutoff.
//!
//! ```xml
//! <emitter type="spot"><transform name="to_world"><lookat origin="0,5,0" target="0,0,0"/></transform>
//!     <rgb name="intensity" value="10"/><float name="cutoff_angle" value="30"/></emitter>
//! ```

use glam::Vec3;

use crate::gpu::layout::{EmitterRecord, EMITTER_SPOT, NONE};

use super::{Emitter, SAMPLING_WEIGHT};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Emitter,
    Dialect::Mitsuba,
    "spot",
    "A spot light at the origin of to_world shining down its +z.",
    &[
        Param::new(
            "to_world",
            "transform",
            "identity",
            "places the light at its origin, looking down +z",
        ),
        Param::new(
            "intensity",
            "rgb",
            "1",
            "radiant intensity on the axis (W/sr)",
        ),
        Param::new(
            "cutoff_angle",
            "float",
            "20",
            "angle (degrees) where the light ends, in (0, 180]",
        ),
        Param::new(
            "beam_width",
            "float",
            "3/4 cutoff_angle",
            "angle (degrees) of full intensity, in [0, cutoff_angle]",
        ),
        SAMPLING_WEIGHT,
    ],
);

/// A Mitsuba `spot` emitter.
pub fn mitsuba(props: &Properties) -> Result<Emitter, Error> {
    let m = props
        .transform_opt("to_world")?
        .unwrap_or(glam::Mat4::IDENTITY);
    let axis = m.transform_vector3(Vec3::Z);
    if axis.length_squared() == 0.0 || !axis.is_finite() {
        return Err(props.error("to_world", "the spot light's transform collapses its axis"));
    }
    let cutoff_deg = props.float("cutoff_angle", 20.0)?;
    if !(cutoff_deg > 0.0 && cutoff_deg <= 180.0) {
        return Err(props.error("cutoff_angle", "cutoff_angle must lie in (0, 180] degrees"));
    }
    let beam_width_deg = props.float("beam_width", 0.75 * cutoff_deg)?;
    if !(beam_width_deg >= 0.0 && beam_width_deg <= cutoff_deg) {
        return Err(props.error(
            "beam_width",
            "beam_width must lie in [0, cutoff_angle] degrees",
        ));
    }
    Ok(Emitter::Spot {
        position: m.w_axis.truncate(),
        axis: axis.normalize(),
        intensity: props.color("intensity", Vec3::ONE)?,
        cutoff_deg,
        beam_width_deg,
    })
}

/// The GPU record of a spot light.
pub fn record(
    position: Vec3,
    axis: Vec3,
    intensity: Vec3,
    cutoff_deg: f32,
    beam_width_deg: f32,
) -> EmitterRecord {
    let (cutoff, beam) = (cutoff_deg.to_radians(), beam_width_deg.to_radians());
    EmitterRecord {
        position: position.into(),
        kind: EMITTER_SPOT,
        radiance: intensity.into(),
        shape: NONE,
        axis: axis.into(),
        cos_cutoff: cutoff.cos(),
        cutoff,
        // A zero-width transition is a hard edge: a huge slope.
        inv_transition: 1.0 / (cutoff - beam).max(1e-6),
        ..Default::default()
    }
}
