//! `obj`: a Wavefront OBJ mesh (read by [`crate::scene::obj`]).
//!
//! Mitsuba 3 flips the texture v coordinate by default (`flip_tex_coords`); Nori's
//! `<mesh type="obj">` does not, and keeps face normals where the file has none.
//!
//! ```xml
//! <shape type="obj"><string name="filename" value="bunny.obj"/></shape>
//! ```

use glam::Mat4;

use super::{Mesh, FACE_NORMALS, FLIP_NORMALS, TO_WORLD};
use crate::scene::builder;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::{Dialect, Element};
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Shape,
    Dialect::Mitsuba,
    "obj",
    "A Wavefront OBJ triangle mesh; vertex normals computed where the file has none.",
    &[
        Param::new("filename", "string", "", "the .obj file (required)"),
        Param::new("flip_tex_coords", "boolean", "true", "v = 1 - v"),
        TO_WORLD,
        FACE_NORMALS,
        FLIP_NORMALS,
    ],
);

pub const NORI: PluginDoc = PluginDoc::new(
    Family::Shape,
    Dialect::Nori,
    "obj",
    "A Wavefront OBJ triangle mesh (texture v as in the file, face normals where the file has none).",
    &[
        Param::new("filename", "string", "", "the .obj file (required)"),
        Param::new("toWorld", "transform", "identity", "object to world"),
    ],
);

/// A Mitsuba `obj` mesh in object space.
pub fn mitsuba(el: &Element, props: &Properties) -> Result<Mesh, Error> {
    let path = builder::mesh_path(el, props, "filename")?;
    let flip_tex = props.boolean("flip_tex_coords", true)?;
    crate::scene::obj::load(&path, flip_tex)
}

/// A Nori `<mesh type="obj">`: the mesh in object space and its `toWorld`.
pub fn nori(el: &Element, props: &Properties) -> Result<(Mesh, Mat4), Error> {
    let path = builder::mesh_path(el, props, "filename")?;
    let to_world = props.transform("toWorld")?;
    props.finish()?;
    Ok((crate::scene::obj::load(&path, false)?, to_world))
}
