//! `orthographic`: parallel projection, as Mitsuba 3's `orthographic`
//! ([`Projection::Orthographic`]): rays along +z of `to_world` from the film rectangle
//! x ∈ [-1, 1], y ∈ [-1/a, 1/a] (a = width / height) on the plane z = near_clip, before
//! `to_world` (whose scale sizes the rectangle), as far as far_clip.
//!
//! ```xml
//! <sensor type="orthographic">
//!     <transform name="to_world"><scale x="1.5" y="1.5"/><lookat origin="-5,0,3" target="0,0,1" up="0,0,1"/></transform>
//! </sensor>
//! ```

use super::SensorParts;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::xml::{Dialect, Element};
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Sensor,
    Dialect::Mitsuba,
    "orthographic",
    "A parallel projection of the film rectangle [-1, 1] x [-1/aspect, 1/aspect] of to_world; nests a <film>, a <sampler> and the <medium> it sits in.",
    &[
        Param::new("near_clip", "float", "0.01", "near clip distance"),
        Param::new("far_clip", "float", "10000", "far clip distance"),
        Param::new("to_world", "transform", "identity", "camera to world (its scale sizes the film)"),
    ],
);

/// A Mitsuba `<sensor type="orthographic">` (its type already checked).
pub fn mitsuba(el: &Element) -> Result<SensorParts<'_>, Error> {
    super::perspective::projective(el, "orthographic")
}
