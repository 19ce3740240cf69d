//! `ply`: a Stanford PLY mesh, ASCII or binary (read by [`crate::scene::ply`]).
//!
//! ```xml
//! <shape type="ply"><string name="filename" value="dragon.ply"/></shape>
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
    "ply",
    "A Stanford PLY triangle mesh (ASCII or binary); vertex normals computed where the file has none.",
    &[
        Param::new("filename", "string", "", "the .ply file (required)"),
        Param::new("flip_tex_coords", "boolean", "false", "v = 1 - v"),
        TO_WORLD,
        FACE_NORMALS,
        FLIP_NORMALS,
    ],
);

/// A Mitsuba `ply` mesh in object space.
pub fn mitsuba(el: &Element, props: &Properties) -> Result<Mesh, Error> {
    let path = builder::mesh_path(el, props, "filename")?;
    let flip_tex = props.boolean("flip_tex_coords", false)?;
    let mut m = crate::scene::ply::load(&path)?;
    if flip_tex {
        m.uvs.iter_mut().for_each(|uv| uv.y = 1.0 - uv.y);
    }
    Ok(m)
}
