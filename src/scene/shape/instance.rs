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
    "One more copy of a shapegroup, named by a `ref`, placed by to_world.",
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

#[cfg(test)]
mod tests {
    use crate::scene::testutil::{error_at, load, mitsuba};
    use glam::{Mat4, Vec3};

    fn scene(body: &str) -> Result<crate::scene::Scene, crate::scene::Error> {
        load(&[("s.xml", &mitsuba(body))], &[])
    }

    const GROUP: &str = r#"<shape type="shapegroup" id="g">
<shape type="rectangle"/>
<shape type="sphere"><float name="radius" value="0.5"/></shape>
</shape>"#;

    #[test]
    fn groups_and_instances_load() {
        let s = scene(&format!(
            r#"{GROUP}
<shape type="instance"><ref id="g"/></shape>
<shape type="instance"><ref id="g"/><transform name="to_world"><translate x="3"/></transform></shape>
<shape type="cube"/>"#
        ))
        .unwrap();
        assert_eq!(s.groups.len(), 1);
        assert_eq!(s.groups[0].name, "g");
        assert_eq!(s.groups[0].meshes, [0]);
        assert_eq!(s.groups[0].quadrics, [0]);
        assert_eq!(s.instances.len(), 2);
        assert_eq!(s.instances[0].to_world, Mat4::IDENTITY);
        assert_eq!(
            s.instances[1].to_world,
            Mat4::from_translation(Vec3::new(3.0, 0.0, 0.0))
        );
        assert_eq!(s.grouped_shapes(), [true, false, true]);
        // The rectangle's 2 triangles twice, and the cube's 12 once.
        assert_eq!(s.triangle_count(), 14);
        assert_eq!(s.instanced_triangle_count(), 16);
    }

    #[test]
    fn a_group_may_follow_its_instance_and_stand_unused() {
        let s = scene(&format!(
            r#"<shape type="instance"><ref id="g"/></shape>
{GROUP}
<shape type="shapegroup"><shape type="cube"/></shape>"#
        ))
        .unwrap();
        // Built once, at the first instance that names it; the group without an id
        // loads (as in Mitsuba) and is never seen.
        assert_eq!(s.groups.len(), 2);
        assert_eq!(s.instances.len(), 1);
        assert_eq!(s.instanced_triangle_count(), 2);
    }

    #[test]
    fn refused_as_mitsuba_refuses() {
        let cases: [(&str, u32, &str); 7] = [
            (
                r#"<shape type="shapegroup" id="g"><shape type="sphere"/></shape>
<shape type="instance" id="i"><ref id="g"/></shape>
<shape type="instance"><ref id="i"/></shape>"#,
                5,
                "instances of instances are not permitted",
            ),
            (
                r#"<shape type="instance"><ref id="nowhere"/></shape>"#,
                3,
                "unknown id 'nowhere'",
            ),
            (
                r#"<shape type="instance"/>"#,
                3,
                "an instance needs a shapegroup",
            ),
            (
                r#"<shape type="shapegroup" id="g"><shape type="sphere"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape></shape>"#,
                3,
                "instancing of emitters is not supported",
            ),
            (
                r#"<shape type="shapegroup" id="g">
<shape type="shapegroup" id="h"><shape type="sphere"/></shape></shape>"#,
                4,
                "nested shape groups are not permitted",
            ),
            (
                r#"<shape type="shapegroup" id="g"><shape type="sphere"/></shape>
<shape type="shapegroup" id="h">
<shape type="instance"><ref id="g"/></shape></shape>"#,
                5,
                "nested instancing is not permitted",
            ),
            (
                r#"<shape type="shapegroup" id="g"><shape type="sphere"/></shape>
<shape type="instance"><ref id="g"/><transform name="to_world"><scale value="0"/></transform></shape>"#,
                4,
                "finite, affine and invertible",
            ),
        ];
        for (body, line, want) in cases {
            let text = error_at(scene(body), "s.xml", line);
            assert!(text.contains(want), "{text}: want '{want}'");
        }
        let text = error_at(
            scene(
                r#"<shape type="shapegroup" id="g"><bsdf type="diffuse"/></shape>
<shape type="instance"><ref id="g"/></shape>"#,
            ),
            "s.xml",
            3,
        );
        assert!(text.contains("holds shapes only"), "{text}");
    }
}
