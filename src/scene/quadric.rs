//! What Mitsuba's analytic shapes share: the frame a `cylinder` is built in (the
//! shapes themselves are `scene::shape::{sphere, disk, cylinder}`).

use glam::Vec3;

/// The orthonormal basis Mitsuba builds around a unit `n` (`coordinate_system`, the
/// branchless construction of Duff et al. 2017, "Building an Orthonormal Basis,
/// Revisited", JCGT 6(1)); `frame_basis` in shaders/common/frame.glsl is the same.
pub fn coordinate_system(n: Vec3) -> (Vec3, Vec3) {
    let sign = n.z.signum();
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
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
