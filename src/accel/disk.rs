//! Ray/disk intersection for Mitsuba's `disk` under any affine `to_world`: the unit
//! disk x² + y² ≤ 1, z = 0 mapped to `c + x a1 + y a2`, tested in world space.
//!
//! The plane through `c` with normal `m = a1 × a2` is hit at `t = (c − o)·m / d·m`;
//! the hit's object coordinates come from the dual basis of (a1, a2) in the plane,
//! `b1 = (a2 × m) / |m|²`, `b2 = (m × a1) / |m|²` (so `a_i · b_j = δ_ij`), which is the
//! disk's own parameterization (Mitsuba maps the ray to object space instead; the
//! point and its (x, y) are the same up to rounding).
//!
//! Mirrored line for line by `shaders/shape/intersect_disk.glsl`.

use glam::Vec3;

/// The `t` in the open range `(tmin, tmax)` at which `o + t d` meets the disk, with
/// the hit's object-space (x, y).
#[inline]
pub fn intersect(
    o: Vec3,
    d: Vec3,
    c: Vec3,
    a1: Vec3,
    a2: Vec3,
    tmin: f32,
    tmax: f32,
) -> Option<(f32, f32, f32)> {
    let m = a1.cross(a2);
    let denom = d.dot(m);
    if denom == 0.0 {
        return None; // parallel to the plane (or a degenerate disk)
    }
    let t = (c - o).dot(m) / denom;
    if !(t > tmin && t < tmax) {
        return None;
    }
    let q = o + t * d - c;
    let inv = 1.0 / m.dot(m);
    let x = q.dot(a2.cross(m)) * inv;
    let y = q.dot(m.cross(a1)) * inv;
    if x * x + y * y > 1.0 {
        return None;
    }
    Some((t, x, y))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_and_sheared_disks() {
        let hit = intersect(
            Vec3::new(0.3, 0.2, 5.0),
            -Vec3::Z,
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            0.0,
            10.0,
        );
        let (t, x, y) = hit.unwrap();
        assert!((t - 5.0).abs() < 1e-6 && (x - 0.3).abs() < 1e-6 && (y - 0.2).abs() < 1e-6);
        assert!(intersect(
            Vec3::new(0.8, 0.8, 5.0),
            -Vec3::Z,
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            0.0,
            10.0
        )
        .is_none());
        assert!(intersect(
            Vec3::new(0.0, 0.0, 5.0),
            -Vec3::Z,
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            0.0,
            4.9
        )
        .is_none());
        // An ellipse with a sheared frame: the object coordinates of its world points
        // come back exactly.
        let (c, a1, a2) = (
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(2.0, 0.5, 0.0),
            Vec3::new(0.3, 1.0, 1.0),
        );
        for (x, y) in [(0.5, -0.3), (-0.9, 0.1), (0.0, 0.99)] {
            let p = c + x * a1 + y * a2;
            let o = p + Vec3::new(0.2, -3.0, 1.0);
            let (t, hx, hy) = intersect(o, p - o, c, a1, a2, 0.0, 2.0).unwrap();
            assert!((t - 1.0).abs() < 1e-5 && (hx - x).abs() < 1e-5 && (hy - y).abs() < 1e-5);
        }
        assert!(intersect(Vec3::Z, Vec3::X, Vec3::ZERO, Vec3::X, Vec3::Y, 0.0, 10.0).is_none());
    }
}
