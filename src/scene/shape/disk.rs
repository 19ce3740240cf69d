//! `disk`: the unit disk in z = 0 under `to_world` (any invertible affine map: an
//! ellipse), intersected exactly ([`super::QuadricKind::Disk`]).
//!
//! ```xml
//! <shape type="disk"><transform name="to_world"><scale value="2"/></transform></shape>
//! ```

use super::{Geometry, QuadricKind, FLIP_NORMALS, TO_WORLD};
use crate::scene::plugin::{Family, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Shape,
    Dialect::Mitsuba,
    "disk",
    "The unit disk in z = 0, normal +z, intersected exactly.",
    &[TO_WORLD, FLIP_NORMALS],
);

/// A Mitsuba disk: `to_world` alone.
pub fn mitsuba(props: &Properties) -> Result<Geometry, Error> {
    Ok(Geometry::Quadric(
        QuadricKind::Disk,
        props.transform("to_world")?,
    ))
}
