//! `constant`: uniform radiance arriving from every direction at infinity
//! ([`Emitter::Constant`]).
//!
//! ```xml
//! <emitter type="constant"><rgb name="radiance" value="0.5"/></emitter>
//! ```

use glam::Vec3;

use crate::gpu::layout::{EmitterRecord, EMITTER_CONSTANT, NONE};

use super::{Emitter, SAMPLING_WEIGHT};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Emitter,
    Dialect::Mitsuba,
    "constant",
    "Uniform radiance from every direction at infinity.",
    &[
        Param::new("radiance", "rgb", "1", "emitted radiance"),
        SAMPLING_WEIGHT,
    ],
);

/// A Mitsuba `constant` emitter.
pub fn mitsuba(props: &Properties) -> Result<Emitter, Error> {
    Ok(Emitter::Constant {
        radiance: props.color("radiance", Vec3::ONE)?,
    })
}

/// The GPU record of a constant environment.
pub fn record(radiance: Vec3) -> EmitterRecord {
    EmitterRecord {
        kind: EMITTER_CONSTANT,
        radiance: radiance.into(),
        shape: NONE,
        ..Default::default()
    }
}
