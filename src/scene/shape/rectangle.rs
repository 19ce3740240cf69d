//! `rectangle`: Mitsuba's unit square [-1, 1]² in z = 0, normal +z
//! ([`crate::scene::mesh::rectangle`]). `face_normals` has no effect, as in Mitsuba.
//!
//! ```xml
//! <shape type="rectangle"><transform name="to_world"><scale value="2"/></transform></shape>
//! ```

use super::{Mesh, FACE_NORMALS, FLIP_NORMALS, TO_WORLD};
use crate::scene::plugin::{Family, PluginDoc};
use crate::scene::xml::Dialect;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Shape,
    Dialect::Mitsuba,
    "rectangle",
    "The square [-1, 1]² in z = 0, normal +z (face_normals has no effect).",
    &[TO_WORLD, FACE_NORMALS, FLIP_NORMALS],
);

/// The rectangle in object space.
pub fn mesh() -> Mesh {
    crate::scene::mesh::rectangle()
}
