//! Ray/sphere intersection robust to large distances and small radii (Haines,
//! Günther, Akenine-Möller 2019, "Precision Improvements for Ray/Sphere Intersection",
//! Ray Tracing Gems, chapter 7).
//!
//! For `|o + t d - c|^2 = r^2` with `f = o - c`, the quadratic `a t^2 - 2 b' t + cc = 0`
//! has `a = d.d`, `b' = -f.d`, `cc = f.f - r^2`. Two fixes from the chapter:
//! - the discriminant `b'^2 - a cc` is computed as `a (r^2 - |l|^2)`, where
//!   `l = f + (b'/a) d` is the vector from the center to the ray's closest point
//!   (eq. 7.5), which avoids the cancellation of two huge, nearly equal terms;
//! - the roots come from `q = b' + sign(b') sqrt(disc)`, `t0 = cc / q`, `t1 = q / a`
//!   (eq. 7.8, the numerically stable quadratic of Press et al.).
//!
//! Mirrored line for line by `shaders/shape/intersect_sphere.glsl`.

use glam::Vec3;

/// The nearest `t` in the open range `(tmin, tmax)` at which `o + t d` meets the
/// sphere of center `c` and radius `r`; the far root if the near one is out of range
/// (a ray from inside). `d` need not be normalized but must not be zero.
#[inline]
pub fn intersect(o: Vec3, d: Vec3, c: Vec3, r: f32, tmin: f32, tmax: f32) -> Option<f32> {
    let f = o - c;
    let a = d.dot(d);
    let bp = -f.dot(d);
    let l = f + (bp / a) * d;
    let disc = a * (r * r - l.dot(l));
    if disc < 0.0 {
        return None;
    }
    let cc = f.dot(f) - r * r;
    let q = bp + if bp >= 0.0 { disc.sqrt() } else { -disc.sqrt() };
    if q == 0.0 {
        return None; // origin on the sphere, ray tangent to it: no hit at t > 0
    }
    let t0 = cc / q;
    let t1 = q / a;
    let (tn, tf) = if t0 < t1 { (t0, t1) } else { (t1, t0) };
    if tn > tmin && tn < tmax {
        Some(tn)
    } else if tf > tmin && tf < tmax {
        Some(tf)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_sphere_from_outside_and_inside() {
        let t = intersect(
            Vec3::new(0.0, 0.0, -3.0),
            Vec3::Z,
            Vec3::ZERO,
            1.0,
            0.0,
            10.0,
        );
        assert_eq!(t, Some(2.0));
        let t = intersect(Vec3::ZERO, Vec3::Z * 2.0, Vec3::ZERO, 1.0, 0.0, 10.0);
        assert_eq!(t, Some(0.5));
        assert_eq!(
            intersect(
                Vec3::new(0.0, 0.0, -3.0),
                Vec3::Z,
                Vec3::ZERO,
                1.0,
                0.0,
                2.0
            ),
            None
        );
        assert_eq!(
            intersect(
                Vec3::new(0.0, 2.0, -3.0),
                Vec3::Z,
                Vec3::ZERO,
                1.0,
                0.0,
                10.0
            ),
            None
        );
        assert_eq!(
            intersect(
                Vec3::new(0.0, 0.0, 3.0),
                Vec3::Z,
                Vec3::ZERO,
                1.0,
                0.0,
                10.0
            ),
            None
        );
    }

    #[test]
    fn far_spheres() {
        // The textbook discriminant b^2 - 4ac loses every bit here (b^2 ~ 4e8 with ulp
        // 32 against 4 a r^2 <= 4); the chapter-7 form keeps the hits.
        let c = Vec3::new(1e4, -3e3, 7e3);
        for o in [
            Vec3::ZERO,
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(-50.0, 0.25, 9.0),
        ] {
            // r = 1e-3, aimed exactly (unnormalized d: f = -d, so l = 0).
            let d = c - o;
            let t = intersect(o, d, c, 1e-3, 0.0, f32::INFINITY).expect("tiny far sphere");
            let dist = d.length();
            assert!((t * dist - (dist - 1e-3)).abs() <= 1e-6 * dist, "{t}");
            // r = 1, normalized directions at points within 0.9 r of the center.
            for off in [
                Vec3::ZERO,
                Vec3::new(0.9, 0.0, 0.0),
                Vec3::new(0.0, -0.5, 0.7),
            ] {
                let d = (c + off - o).normalize();
                let t = intersect(o, d, c, 1.0, 0.0, f32::INFINITY).expect("far sphere");
                let q = o + t * d;
                assert!(((q - c).length() - 1.0).abs() < 2e-3, "{q}");
            }
        }
    }
}
