//! Nori's `distantdisk`: light from a disk of directions at infinity; with `thetaA` =
//! 180 (the only angle supported yet) it is a constant environment
//! ([`Emitter::Constant`]).
//!
//! ```xml
//! <emitter type="distantdisk"><color name="radiance" value="1,1,1"/><float name="thetaA" value="180"/></emitter>
//! ```

use super::Emitter;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const NORI: PluginDoc = PluginDoc::new(
    Family::Emitter,
    Dialect::Nori,
    "distantdisk",
    "Light from a disk of directions at infinity; thetaA = 180 only (a constant environment).",
    &[
        Param::new("radiance", "color", "", "emitted radiance (required)"),
        Param::new(
            "thetaA",
            "float",
            "180",
            "half-angle of the disk (degrees); only 180",
        ),
        Param::new(
            "toWorld",
            "transform",
            "identity",
            "read; no effect at thetaA = 180",
        ),
    ],
);

/// A Nori `distantdisk` emitter.
pub fn nori(props: &Properties) -> Result<Emitter, Error> {
    let theta = props.float("thetaA", 180.0)?;
    if theta != 180.0 {
        return Err(props.error(
            "thetaA",
            format!("distantdisk with thetaA = {theta} is not supported yet (only 180, a constant environment)"),
        ));
    }
    props.transform("toWorld")?;
    Ok(Emitter::Constant {
        radiance: props
            .color_opt("radiance")?
            .ok_or_else(|| props.object_error("distantdisk needs a 'radiance'"))?,
    })
}
