//! `cube`: Mitsuba's cube [-1, 1]³, outward normals ([`crate::scene::mesh::cube`]).
//! `face_normals` has no effect, as in Mitsuba.
//!
//! ```xml
//! <shape type="cube"><bsdf type="null"/><medium type="homogeneous" name="interior"/></shape>
//! ```

use super::{Mesh, FACE_NORMALS, FLIP_NORMALS, TO_WORLD};
use crate::scene::plugin::{Family, PluginDoc};
use crate::scene::xml::Dialect;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Shape,
    Dialect::Mitsuba,
    "cube",
    "The cube [-1, 1]³ with outward normals (face_normals has no effect).",
    &[TO_WORLD, FACE_NORMALS, FLIP_NORMALS],
);

/// The cube in object space.
pub fn mesh() -> Mesh {
    crate::scene::mesh::cube()
}
