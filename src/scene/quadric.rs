//! Mitsuba's analytic shapes, `sphere`, `disk` and `cylinder`: their parameters
//! composed into one object-to-world map of the unit shape, as Mitsuba 3.9 composes
//! them (src/shapes/sphere.cpp, disk.cpp, cylinder.cpp).

use glam::{Mat4, Vec3};

use super::properties::Properties;
use super::shape::QuadricKind;
use super::Error;

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

/// Reads a Mitsuba quadric's own parameters from `props` and returns its kind and
/// object-to-world map (the unit shape to world space), `to_world` included:
///
/// - `sphere`: `center` (0, 0, 0), `radius` (1): `to_world · translate(center) ·
///   scale(radius)`.
/// - `disk`: `to_world` alone.
/// - `cylinder`: `p0` (0, 0, 0), `p1` (0, 0, 1), `radius` (1): `to_world ·
///   translate(p0) · frame(d / |d|) · scale(radius, radius, |d|)`, d = p1 − p0 and
///   `frame(n)` the rotation taking z to n and x, y to [`coordinate_system`]`(n)`.
///
/// `None` for any other type.
pub fn from_mitsuba(t: &str, props: &Properties) -> Result<Option<(QuadricKind, Mat4)>, Error> {
    let to_world = props.transform("to_world")?;
    let positive_radius = || -> Result<f32, Error> {
        let r = props.float("radius", 1.0)?;
        if !(r > 0.0 && r.is_finite()) {
            return Err(props.error("radius", format!("{t} radius must be positive, found {r}")));
        }
        Ok(r)
    };
    Ok(Some(match t {
        "sphere" => {
            let center = props.point("center", Vec3::ZERO)?;
            let radius = positive_radius()?;
            (
                QuadricKind::Sphere,
                to_world * Mat4::from_translation(center) * Mat4::from_scale(Vec3::splat(radius)),
            )
        }
        "disk" => (QuadricKind::Disk, to_world),
        "cylinder" => {
            let p0 = props.point("p0", Vec3::ZERO)?;
            let p1 = props.point("p1", Vec3::Z)?;
            let radius = positive_radius()?;
            let d = p1 - p0;
            let length = d.length();
            if !(length > 0.0 && length.is_finite()) {
                return Err(props.error("p1", "a cylinder needs p0 and p1 apart"));
            }
            let n = d / length;
            let (s, t) = coordinate_system(n);
            let frame = Mat4::from_cols(s.extend(0.0), t.extend(0.0), n.extend(0.0), glam::Vec4::W);
            (
                QuadricKind::Cylinder,
                to_world
                    * Mat4::from_translation(p0)
                    * frame
                    * Mat4::from_scale(Vec3::new(radius, radius, length)),
            )
        }
        _ => return Ok(None),
    }))
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
