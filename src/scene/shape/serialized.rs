//! `serialized`: one mesh of a Mitsuba `.serialized` file (read by
//! [`crate::scene::serialized`]).
//!
//! ```xml
//! <shape type="serialized"><string name="filename" value="scene.serialized"/><integer name="shape_index" value="2"/></shape>
//! ```

use super::{Mesh, FACE_NORMALS, FLIP_NORMALS, TO_WORLD};
use crate::scene::builder;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::{Dialect, Element};
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Shape,
    Dialect::Mitsuba,
    "serialized",
    "One mesh of a Mitsuba .serialized file.",
    &[
        Param::new("filename", "string", "", "the .serialized file (required)"),
        Param::new("shape_index", "integer", "0", "which mesh of the file"),
        TO_WORLD,
        FACE_NORMALS,
        FLIP_NORMALS,
    ],
);

/// A Mitsuba `serialized` mesh in object space.
pub fn mitsuba(el: &Element, props: &Properties) -> Result<Mesh, Error> {
    let path = builder::mesh_path(el, props, "filename")?;
    let index = props.integer("shape_index", 0)?;
    let index = u32::try_from(index).map_err(|_| {
        props.error(
            "shape_index",
            format!("shape_index must be >= 0, found {index}"),
        )
    })?;
    crate::scene::serialized::load(&path, index)
}
