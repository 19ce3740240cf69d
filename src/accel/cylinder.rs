//! Ray/cylinder intersection for Mitsuba's `cylinder`: the capless tube of radius
//! `r` around the axis from `c` to `c + a` (`0 ≤ (p − c)·a / |a|² ≤ 1`), in world
//! space.
//!
//! With `f = o − c` and both `f` and `d` projected off the axis (`f⊥`, `d⊥`), the tube
//! is `|f⊥ + t d⊥|² = r²`: the quadratic of the sphere, solved the same stable way
//! (Haines et al. 2019, Ray Tracing Gems ch. 7, eqs. 7.5 and 7.8; see
//! [`super::sphere`]). Each root in range is kept if it lies between the ends; the
//! near one first, so a ray from inside the tube finds the far wall (Mitsuba's order).
//!
//! Mirrored line for line by `shaders/shape/intersect_cylinder.glsl`.

use glam::Vec3;

/// The nearest `t` in `(tmin, tmax)` at which `o + t d` meets the tube between its
/// ends.
#[inline]
pub fn intersect(o: Vec3, d: Vec3, c: Vec3, a: Vec3, r: f32, tmin: f32, tmax: f32) -> Option<f32> {
    let inv_len2 = 1.0 / a.dot(a);
    let f = o - c;
    let fz = f.dot(a) * inv_len2;
    let dz = d.dot(a) * inv_len2;
    let fp = f - fz * a;
    let dp = d - dz * a;
    let qa = dp.dot(dp);
    if qa == 0.0 {
        return None; // along the axis
    }
    let bp = -fp.dot(dp);
    let l = fp + (bp / qa) * dp;
    let disc = qa * (r * r - l.dot(l));
    if disc < 0.0 {
        return None;
    }
    let cc = fp.dot(fp) - r * r;
    let q = bp + if bp >= 0.0 { disc.sqrt() } else { -disc.sqrt() };
    if q == 0.0 {
        return None;
    }
    let t0 = cc / q;
    let t1 = q / qa;
    let (tn, tf) = if t0 < t1 { (t0, t1) } else { (t1, t0) };
    for t in [tn, tf] {
        let z = fz + t * dz;
        if t > tmin && t < tmax && (0.0..=1.0).contains(&z) {
            return Some(t);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tube_from_outside_inside_and_past_the_ends() {
        let (c, a) = (Vec3::ZERO, Vec3::Z * 2.0);
        // Through the side: the near wall.
        assert_eq!(
            intersect(Vec3::new(-3.0, 0.0, 1.0), Vec3::X, c, a, 1.0, 0.0, 10.0),
            Some(2.0)
        );
        // From inside: the far wall.
        assert_eq!(
            intersect(Vec3::new(0.0, 0.0, 1.0), Vec3::X, c, a, 1.0, 0.0, 10.0),
            Some(1.0)
        );
        // Above the top end, and along the axis: nothing.
        assert_eq!(
            intersect(Vec3::new(-3.0, 0.0, 2.5), Vec3::X, c, a, 1.0, 0.0, 10.0),
            None
        );
        assert_eq!(
            intersect(Vec3::new(0.0, 0.0, -1.0), Vec3::Z, c, a, 1.0, 0.0, 10.0),
            None
        );
        // Entering through the open top end: the inside of the wall.
        let t = intersect(
            Vec3::new(0.0, 0.0, 3.0),
            Vec3::new(0.5, 0.0, -1.0),
            c,
            a,
            1.0,
            0.0,
            10.0,
        )
        .unwrap();
        assert!((t - 2.0).abs() < 1e-6, "{t}");
        // A slanted, offset tube.
        let (c, a) = (Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.0, 3.0, 4.0));
        let p = c + 0.5 * a + Vec3::X * 0.25;
        let t = intersect(p - Vec3::X * 4.0, Vec3::X, c, a, 0.25, 0.0, 10.0).unwrap();
        assert!((t - 3.5).abs() < 1e-5, "{t}"); // the near wall, 2 r before the axis
    }
}
