//! `shapegroup` and `instance`: Mitsuba 3's geometry instancing. A `shapegroup` with an
//! `id` holds shapes that are not visible on their own; each `instance` places the
//! group once more by its `to_world` (the group's shapes keep their own `to_world`,
//! read as a map into the group's space). The renderer traces a two-level tree: a
//! top-level BVH over the scene's own shapes and the instances' boxes, and one
//! bottom-level BVH per group, shared by its instances ([`crate::accel::instance`]).
//!
//! As in Mitsuba 3 (shapegroup.cpp, instance.cpp): a group holds shapes only (a nested
//! `shapegroup` or `instance` is refused: no instances of instances), no shape in a
//! group may carry an emitter ("Instancing of emitters is not supported"), and an
//! instance names exactly one shapegroup. A group without an `id` loads and is never
//! seen, as in Mitsuba.
//!
//! ```xml
//! <shape type="shapegroup" id="tree">
//!     <shape type="obj"><string name="filename" value="tree.obj"/></shape>
//! </shape>
//! <shape type="instance">
//!     <ref id="tree"/>
//!     <transform name="to_world"><translate x="3"/></transform>
//! </shape>
//! ```

use glam::Mat4;

use super::TO_WORLD;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::xml::Dialect;

pub const SHAPEGROUP: PluginDoc = PluginDoc::new(
    Family::Shape,
    Dialect::Mitsuba,
    "shapegroup",
    "Shapes made available for instancing (not visible on their own); no emitters, no \
     nested groups or instances.",
    &[Param::new(
        "(nested)",
        "shape",
        "",
        "the shapes of the group, each with its own to_world into the group's space",
    )],
);

pub const INSTANCE: PluginDoc = PluginDoc::new(
    Family::Shape,
    Dialect::Mitsuba,
    "instance",
    "One more copy of a shapegroup, named by a <ref>, placed by to_world.",
    &[
        Param::new("(nested)", "ref", "", "the shapegroup, exactly one"),
        TO_WORLD,
    ],
);

/// A `shapegroup`: the shapes of the scene that are seen only through instances.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ShapeGroup {
    /// Its `id`, for messages.
    pub name: String,
    /// Indices into `Scene::meshes` and `Scene::quadrics`, in the group's space.
    pub meshes: Vec<u32>,
    pub quadrics: Vec<u32>,
}

/// An `instance`: group `group` (index into `Scene::groups`) mapped by `to_world`
/// (affine and invertible, checked at load).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Instance {
    pub group: u32,
    pub to_world: Mat4,
}

/// Whether `m` can place an instance: finite, affine, invertible.
pub fn placeable(m: &Mat4) -> bool {
    m.is_finite() && m.row(3) == glam::Vec4::W && m.determinant().abs() > 0.0
}
