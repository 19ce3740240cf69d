//! Ray against a round cubic B-spline curve segment (Mitsuba's `bsplinecurve`, Embree's
//! round B-spline curves): the surface swept by the circle of centre c(u) and radius
//! r(u) in the plane normal to the tangent c'(u), 0 <= u <= 1, c and r the uniform
//! cubic B-spline of four control points and their radii; no end caps, and only the
//! ray's entry counts (a hit whose normal faces along the ray is culled, as Embree
//! culls curves' back faces). Mitsuba 3.9.1 reports such hits: measured, the hit point
//! lies on that circle (`(p - c(u)).c'(u) = 0`, `|p - c(u)| = r(u)`) and its normal is
//! the gradient of that surface (the curvature-corrected one of [`normal`]).
//! Mirrored by `shaders/shape/intersect_bspline.glsl`, operation for operation.
//!
//! The search: the segment is cut into [`PIECES`] pieces, each held by the round cone
//! ([`super::curve::intersect_linear`]) between the ends of its chord with the radii
//! grown by a bound on how far the curve and its radius stray from the chord
//! (|c''| h² / 8, |c''| at most the control polygon's larger second difference); the
//! entry into each cone the ray meets starts a Newton iteration in (t, u) on the two
//! equations above, and the nearest converged front-facing hit on the segment wins.
//! The ray is first moved next to the segment and the control points taken relative
//! to its middle (thin hair far away keeps its radius, as for linear curves).

use glam::{Vec3, Vec4};

/// Pieces of a segment, each bounded by a cone.
pub const PIECES: usize = 8;
/// Newton steps from each cone's entry.
pub const NEWTON_STEPS: usize = 8;

/// Centre, first and second derivatives, radius and its derivative of the segment of
/// control points `cp` (xyz, radius in w) at `u` (Mitsuba's cubic_interpolation).
pub fn eval(cp: &[Vec4; 4], u: f32) -> (Vec3, Vec3, Vec3, f32, f32) {
    let u2 = u * u;
    let u3 = u2 * u;
    let b = [
        (-u3 + 3.0 * u2 - 3.0 * u + 1.0) / 6.0,
        (3.0 * u3 - 6.0 * u2 + 4.0) / 6.0,
        (-3.0 * u3 + 3.0 * u2 + 3.0 * u + 1.0) / 6.0,
        u3 / 6.0,
    ];
    let db = [
        (-3.0 * u2 + 6.0 * u - 3.0) / 6.0,
        (9.0 * u2 - 12.0 * u) / 6.0,
        (-9.0 * u2 + 6.0 * u + 3.0) / 6.0,
        3.0 * u2 / 6.0,
    ];
    let ddb = [1.0 - u, 3.0 * u - 2.0, 1.0 - 3.0 * u, u];
    let mut c = Vec4::ZERO;
    let mut dc = Vec4::ZERO;
    let mut ddc = Vec4::ZERO;
    for k in 0..4 {
        c += b[k] * cp[k];
        dc += db[k] * cp[k];
        ddc += ddb[k] * cp[k];
    }
    (c.truncate(), dc.truncate(), ddc.truncate(), c.w, dc.w)
}

/// The unnormalized normal at a point `q` from the centre, Mitsuba's: the gradient of
/// the swept circle's surface, (|c'|² - q.c'') q - r r' c'.
pub fn normal(q: Vec3, dc: Vec3, ddc: Vec3, r: f32, dr: f32) -> Vec3 {
    (dc.dot(dc) - q.dot(ddc)) * q - (r * dr) * dc
}

/// Where the ray `o + t d` enters the segment of control points `cp` (xyz, radius in
/// w) with `tmin < t < tmax`: `(t, u)`.
pub fn intersect_bspline(
    o: Vec3,
    d: Vec3,
    cp: &[Vec4; 4],
    tmin: f32,
    tmax: f32,
) -> Option<(f32, f32)> {
    let len = d.length();
    let dn = d / len;
    let mid = (cp[1].truncate() + cp[2].truncate()) * 0.5;
    let shift = (mid - o).dot(dn);
    let ol = o + shift * dn - mid;
    let l = cp.map(|p| p - mid.extend(0.0));
    // The size of the moved coordinates, whose rounding bounds the residuals.
    let ext = l
        .iter()
        .fold(0.0f32, |e, p| e.max(p.truncate().abs().max_element()));
    // Second differences bound |c''| and |r''| (c'' = (1-u) A + u B).
    let a = l[0] - 2.0 * l[1] + l[2];
    let b = l[1] - 2.0 * l[2] + l[3];
    let h = 1.0 / PIECES as f32;
    let grow = (a.truncate().length().max(b.truncate().length()) + a.w.abs().max(b.w.abs()))
        * (h * h * 0.125)
        * 1.01;
    // The search range in the moved ray's t.
    let (lo, hi) = (tmin * len - shift, tmax * len - shift);
    let mut best_t = f32::INFINITY;
    let mut best_u = 0.0;
    let (mut c0, _, _, mut r0, _) = eval(&l, 0.0);
    for i in 0..PIECES {
        let u1 = (i + 1) as f32 * h;
        let (c1, _, _, r1, _) = eval(&l, u1);
        let cone = super::curve::intersect_linear(
            ol,
            dn,
            c0,
            c1,
            r0.max(0.0) + grow,
            r1.max(0.0) + grow,
            true,
            f32::NEG_INFINITY,
            f32::INFINITY,
        );
        c0 = c1;
        r0 = r1;
        let Some((te, v)) = cone else { continue };
        let mut t = te.max(lo);
        if t >= best_t || t.is_nan() {
            continue;
        }
        let mut u = (i as f32 + v) * h;
        for _ in 0..NEWTON_STEPS {
            let (c, dc, ddc, r, dr) = eval(&l, u);
            let q = ol + t * dn - c;
            let f1 = q.dot(dc);
            let f2 = q.dot(q) - r * r;
            let j00 = dn.dot(dc);
            let j01 = q.dot(ddc) - dc.dot(dc);
            let j10 = 2.0 * q.dot(dn);
            let j11 = -2.0 * (q.dot(dc) + r * dr);
            let det = j00 * j11 - j01 * j10;
            if det != 0.0 {
                t -= (f1 * j11 - f2 * j01) / det;
                u -= (j00 * f2 - j10 * f1) / det;
            }
            u = u.clamp(-0.5, 1.5);
        }
        let (c, dc, ddc, r, dr) = eval(&l, u);
        let q = ol + t * dn - c;
        let ql = q.length();
        // On the circle's radius to 1e-4 of it, in its plane to 1e-3 (which only moves
        // u), both above the rounding of coordinates of size `ext + |t|`.
        let scale = 1e-6 * (ext + t.abs());
        let converged = (ql - r).abs() <= 1e-4 * r.abs() + scale
            && q.dot(dc).abs() <= (1e-3 * (ql + r.abs()) + scale) * dc.length();
        let front = normal(q, dc, ddc, r, dr).dot(dn) < 0.0;
        if converged && front && (0.0..=1.0).contains(&u) && t > lo && t < hi && t < best_t {
            best_t = t;
            best_u = u;
        }
    }
    best_t
        .is_finite()
        .then_some(((shift + best_t) / len, best_u))
}

/// The hit geometry at point `p` and segment parameter `u`, as Mitsuba 3.9.1 reports
/// it: the unit normal (geometric and shading), the angle around the curve / 2π from
/// Mitsuba's frame (+z made normal to the tangent, +y where the tangent is ±z), and the
/// direction around the curve (its ∂p/∂u, whose part normal to n is the shading
/// tangent).
pub fn surface(cp: &[Vec4; 4], p: Vec3, u: f32) -> (Vec3, f32, Vec3) {
    let (c, dc, ddc, r, dr) = eval(cp, u);
    let q = p - c;
    let n = normal(q, dc, ddc, r, dr).normalize();
    let tangent = dc.normalize();
    let rot = if tangent.z.abs() == 1.0 {
        Vec3::Y
    } else {
        (Vec3::Z - tangent * tangent.z).normalize()
    };
    let radial = rot.cross(tangent);
    let qn = q.normalize();
    let mut a = rot.dot(qn).atan2(radial.dot(qn));
    if a < 0.0 {
        a += std::f32::consts::TAU;
    }
    (n, a / std::f32::consts::TAU, tangent.cross(qn))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn segment() -> [Vec4; 4] {
        [
            Vec4::new(-1.2, -0.15, -0.13, 0.06),
            Vec4::new(-0.9, -0.24, -0.14, 0.12),
            Vec4::new(-0.6, -0.24, -0.03, 0.09),
            Vec4::new(-0.3, -0.15, 0.09, 0.05),
        ]
    }

    #[test]
    fn hits_lie_on_the_swept_circle_and_face_the_ray() {
        let cp = segment();
        let mut rng = 7u32;
        let mut next = || {
            rng = rng.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (rng >> 8) as f32 / (1 << 24) as f32
        };
        let mut hits = 0;
        for _ in 0..500 {
            let u = next();
            let (c, _, _, r, _) = eval(&cp, u);
            let target = c + Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * r;
            let o = target + Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize() * 3.0;
            let d = target - o;
            let Some((t, u)) = intersect_bspline(o, d, &cp, 0.0, f32::MAX) else {
                continue;
            };
            hits += 1;
            let p = o + t * d;
            let (c, dc, ddc, r, dr) = eval(&cp, u);
            let q = p - c;
            assert!((q.length() - r).abs() < 1e-5, "{} {r}", q.length());
            assert!(q.dot(dc.normalize()).abs() < 1e-5);
            assert!(normal(q, dc, ddc, r, dr).dot(d) < 0.0);
        }
        assert!(hits > 300, "{hits}");
        // From inside: no hit (back faces are culled).
        let (c, ..) = eval(&cp, 0.5);
        assert!(intersect_bspline(c, Vec3::Z, &cp, 0.0, f32::MAX).is_none());
        assert!(intersect_bspline(c, Vec3::Y, &cp, 0.0, f32::MAX).is_none());
    }

    #[test]
    fn thin_hair_far_away() {
        // A straight hair of radius 1e-4 seen from 10 units (an ulp of t is 1e-6
        // there): the hit lies on the surface, and a ray just beside it misses.
        let cp = [-1.0f32, 0.0, 1.0, 2.0].map(|y| Vec4::new(0.0, y, 0.0, 1e-4));
        let o = Vec3::new(5e-5, 0.5, 10.0);
        let (t, u) = intersect_bspline(o, -Vec3::Z, &cp, 0.0, f32::MAX).unwrap();
        let p = o - t * Vec3::Z;
        let r = Vec3::new(p.x, 0.0, p.z).length();
        assert!((r - 1e-4).abs() < 2e-6, "{r}");
        assert!((u - 0.5).abs() < 1e-4, "{u}");
        let beside = Vec3::new(1.1e-4, 0.5, 10.0);
        assert!(intersect_bspline(beside, -Vec3::Z, &cp, 0.0, f32::MAX).is_none());
    }

    #[test]
    fn mitsuba_hit() {
        // Mitsuba 3.9.1 (Embree) on this segment alone (one curve of four points).
        let cp = segment();
        let o = Vec3::new(0.3, 1.1, 2.0);
        let d = Vec3::new(-1.049_789_2, -1.305_589_2, -2.061_362_5);
        let (t, u) = intersect_bspline(o, d, &cp, 0.0, f32::MAX).unwrap();
        assert!((t - 0.969_213_5).abs() < 2e-6, "{t}");
        let p = o + t * d;
        let p_mi = Vec3::new(-0.717_469_8, -0.165_394_63, 0.002_099_661);
        assert!((p - p_mi).length() < 3e-6, "{p}");
        let (n, around, dpdu) = surface(&cp, p, u);
        let n_mi = Vec3::new(-0.182_703_21, 0.706_552_6, 0.683_668_8);
        assert!((n - n_mi).length() < 1e-4, "{n}");
        // uv = (around / 2π, (u + segment number) / segments) with one segment.
        assert!((around - 0.122_173_21).abs() < 1e-4, "{around}");
        assert!((u - 0.698_404_5).abs() < 1e-4, "{u}");
        let s = (dpdu - n * n.dot(dpdu)).normalize();
        let s_mi = Vec3::new(-0.199_622_18, -0.707_547_96, 0.677_884_16);
        assert!((s - s_mi).length() < 1e-4, "{s}");
    }
}
