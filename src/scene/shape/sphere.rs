//! `sphere`: intersected exactly ([`super::QuadricKind::Sphere`]); its object-to-world
//! map is `to_world · translate(center) · scale(radius)`, as Mitsuba 3.9 composes it
//! (src/shapes/sphere.cpp).
//!
//! ```xml
//! <shape type="sphere"><point name="center" value="0,1,0"/><float name="radius" value="0.5"/></shape>
//! ```

use glam::{Mat4, Vec3};

use super::{Geometry, QuadricKind, FLIP_NORMALS, TO_WORLD};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Shape,
    Dialect::Mitsuba,
    "sphere",
    "A sphere, intersected exactly (to_world may rotate, mirror, translate and scale uniformly).",
    &[
        Param::new("center", "point", "0,0,0", "centre"),
        Param::new("radius", "float", "1", "radius, > 0"),
        TO_WORLD,
        FLIP_NORMALS,
    ],
);

/// A Mitsuba sphere: its unit sphere's object-to-world map.
pub fn mitsuba(props: &Properties) -> Result<Geometry, Error> {
    let to_world = props.transform("to_world")?;
    let center = props.point("center", Vec3::ZERO)?;
    let radius = positive_radius(props, "sphere")?;
    Ok(Geometry::Quadric(
        QuadricKind::Sphere,
        to_world * Mat4::from_translation(center) * Mat4::from_scale(Vec3::splat(radius)),
    ))
}

/// A quadric's `radius` (default 1): positive and finite.
pub fn positive_radius(props: &Properties, t: &str) -> Result<f32, Error> {
    let r = props.float("radius", 1.0)?;
    if !(r > 0.0 && r.is_finite()) {
        return Err(props.error("radius", format!("{t} radius must be positive, found {r}")));
    }
    Ok(r)
}
