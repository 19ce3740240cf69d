//! `cylinder`: a cylinder without caps, intersected exactly
//! ([`super::QuadricKind::Cylinder`]); its object-to-world map is `to_world ·
//! translate(p0) · frame(d / |d|) · scale(radius, radius, |d|)`, d = p1 − p0 and
//! `frame(n)` the rotation taking z to n and x, y to
//! [`coordinate_system`]`(n)`, as Mitsuba 3.9 composes it (src/shapes/cylinder.cpp).
//!
//! ```xml
//! <shape type="cylinder"><point name="p1" value="0,2,0"/><float name="radius" value="0.3"/></shape>
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
    "cylinder",
    "A cylinder without caps, intersected exactly.",
    &[
        Param::new("p0", "point", "0,0,0", "centre of one end"),
        Param::new("p1", "point", "0,0,1", "centre of the other end"),
        Param::new("radius", "float", "1", "radius, > 0"),
        TO_WORLD,
        FLIP_NORMALS,
    ],
);

/// The orthonormal basis Mitsuba builds around a unit `n` (`coordinate_system`, the
/// branchless construction of Duff et al. 2017, "Building an Orthonormal Basis,
/// Revisited", JCGT 6(1)); `frame_basis` in shaders/sampling/frame.glsl is the same.
pub fn coordinate_system(n: Vec3) -> (Vec3, Vec3) {
    let sign = n.z.signum();
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// A Mitsuba cylinder: its unit cylinder's object-to-world map.
pub fn mitsuba(props: &Properties) -> Result<Geometry, Error> {
    let to_world = props.transform("to_world")?;
    let p0 = props.point("p0", Vec3::ZERO)?;
    let p1 = props.point("p1", Vec3::Z)?;
    let radius = super::sphere::positive_radius(props, "cylinder")?;
    let d = p1 - p0;
    let length = d.length();
    if !(length > 0.0 && length.is_finite()) {
        return Err(props.error("p1", "a cylinder needs p0 and p1 apart"));
    }
    let n = d / length;
    let (s, t) = coordinate_system(n);
    let frame = Mat4::from_cols(s.extend(0.0), t.extend(0.0), n.extend(0.0), glam::Vec4::W);
    Ok(Geometry::Quadric(
        QuadricKind::Cylinder,
        to_world
            * Mat4::from_translation(p0)
            * frame
            * Mat4::from_scale(Vec3::new(radius, radius, length)),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coordinate_system_is_mitsubas() {
        // Values printed by Mitsuba 3.9.1's mi.coordinate_system.
        let (s, t) = coordinate_system(Vec3::new(0.48, 0.6, -0.64));
        assert!(
            (s - Vec3::new(0.859512, -0.17561, 0.48)).length() < 1e-5,
            "{s}"
        );
        assert!(
            (t - Vec3::new(0.17561, -0.780488, -0.6)).length() < 1e-5,
            "{t}"
        );
        let (s, t) = coordinate_system(Vec3::new(0.6, 0.0, 0.8));
        assert!((s - Vec3::new(0.8, 0.0, -0.6)).length() < 1e-6, "{s}");
        assert!((t - Vec3::Y).length() < 1e-6, "{t}");
        for n in [Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(0.0, 0.6, -0.8)] {
            let (s, t) = coordinate_system(n);
            assert!(s.dot(t).abs() < 1e-6 && s.dot(n).abs() < 1e-6);
            assert!((s.cross(t) - n).length() < 1e-6, "right-handed around {n}");
        }
    }
}
