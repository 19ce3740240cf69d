//! Ray against a round linear curve segment (Mitsuba's `linearcurve`, Embree's round
//! linear curves): the union of the spheres of centre `c0 + v (c1 - c0)` and radius
//! `r0 + v (r1 - r0)`, 0 <= v <= 1, which is the cone touching the two end spheres,
//! capped by them. Only the ray's entry counts (Embree culls curves' back faces).
//! Mirrored by `shaders/shape/intersect_curve.glsl`, operation for operation.
//!
//! The body: a point p lies on the envelope of the sphere family where it is on sphere
//! v and d/dv (|p - c(v)|² - r(v)²) = 0, that is (p - c(v)).a = r(v) (r0 - r1) with
//! a = c1 - c0. Solved for v: v = y / d2 with y = (p - c0).a - r0 (r0 - r1) and
//! d2 = a.a - (r0 - r1)²; put back, the envelope is the quadric
//! d2 (|p - c0|² - r0²) - y² = 0, whose ray roots count where 0 <= y <= d2 (for
//! d2 <= 0 one end sphere holds the other, and the spheres alone are the shape).
//! For thin curves far from the ray origin the ray is first moved to the point
//! nearest the segment's middle (the cancellation of |o - c0|² against r0² would
//! otherwise lose the radius), and its direction made unit.

use glam::Vec3;

/// Where the ray `o + t d` enters the segment with `tmin < t < tmax`: `(t, v)`, v the
/// parameter of the touching sphere's centre (0 and 1 on the end caps). The start
/// sphere counts where `start_cap` (a curve's first segment): elsewhere it is the
/// previous segment's end sphere, and a hit there is that segment's, as in Embree.
#[allow(clippy::too_many_arguments)]
pub fn intersect_linear(
    o: Vec3,
    d: Vec3,
    c0: Vec3,
    c1: Vec3,
    r0: f32,
    r1: f32,
    start_cap: bool,
    tmin: f32,
    tmax: f32,
) -> Option<(f32, f32)> {
    let len = d.length();
    let dn = d / len;
    let shift = ((c0 + c1) * 0.5 - o).dot(dn);
    let os = o + shift * dn;
    let a = c1 - c0;
    let oa = os - c0;
    let dr = r0 - r1;
    let m0 = a.dot(a);
    let m1 = a.dot(oa);
    let m2 = a.dot(dn);
    let m3 = dn.dot(oa);
    let m5 = oa.dot(oa);
    let d2 = m0 - dr * dr;
    let y0 = m1 - r0 * dr;
    // k2 = d2 - m2², k1 = d2 m3 - y0 m2 and k0 = d2 (m5 - r0²) - y0², with the
    // differences of products along the axis written as cross products (Lagrange's
    // identity), which keep the thin radius that the products cancel.
    let (ad, ao) = (a.cross(dn), a.cross(oa));
    let k2 = ad.dot(ad) - dr * dr;
    let k1 = ao.dot(ad) - dr * dr * m3 + r0 * dr * m2;
    let k0 = ao.dot(ao) - dr * dr * m5 + 2.0 * m1 * r0 * dr - m0 * r0 * r0;
    let h = k1 * k1 - k0 * k2;
    // The stable pair of roots (Haines et al. 2019, Ray Tracing Gems ch. 7, eq. 7.8);
    // the entry is the smaller where the ray crosses the cone (k2 > 0), the larger
    // where it runs steeper than the cone and enters its nappe from the far side.
    let q = -(k1 + h.max(0.0).sqrt().copysign(k1));
    let (ta, tb) = (q / k2, k0 / q);
    let t_body = if k2 > 0.0 { ta.min(tb) } else { ta.max(tb) };
    let y = y0 + t_body * m2;
    let body = d2 > 0.0 && h >= 0.0 && q != 0.0 && y >= 0.0 && y <= d2 && t_body.is_finite();
    let mut best = (f32::INFINITY, 0.0);
    if body {
        best = (t_body, y / d2);
    }
    // The end spheres' entries, from the ray's closest approach to each centre.
    for (c, r, v) in [(c0, r0, 0.0), (c1, r1, 1.0)] {
        if v == 0.0 && !start_cap {
            continue;
        }
        let oc = os - c;
        let b = oc.dot(dn);
        let perp = oc - b * dn;
        let hs = r * r - perp.dot(perp);
        let t = -b - hs.max(0.0).sqrt();
        if hs >= 0.0 && t < best.0 {
            best = (t, v);
        }
    }
    let t = (shift + best.0) / len;
    (best.0.is_finite() && t > tmin && t < tmax).then_some((t, best.1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cone_caps_and_culled_back_faces() {
        // Values from Mitsuba 3.9.1 (Embree) on the curve (-1,0,0; 0.2) - (0,0.5,0; 0.3).
        let (c0, c1) = (Vec3::new(-1.0, 0.0, 0.0), Vec3::new(0.0, 0.5, 0.0));
        let hit = |o: Vec3, d: Vec3| intersect_linear(o, d, c0, c1, 0.2, 0.3, true, 0.0, f32::MAX);
        let (t, v) = hit(Vec3::new(0.0, 0.5, 5.0), -Vec3::Z).unwrap();
        assert!((t - 4.7).abs() < 1e-5 && v == 1.0, "{t} {v}");
        let (t, v) = hit(Vec3::new(-0.5, 0.2, 5.0), -Vec3::Z).unwrap();
        assert!(
            (t - 4.755_051).abs() < 1e-5 && v > 0.0 && v < 1.0,
            "{t} {v}"
        );
        let (t, v) = hit(Vec3::new(-1.15, 0.0, 5.0), -Vec3::Z).unwrap();
        assert!((t - 4.867_712_5).abs() < 1e-5 && v == 0.0, "{t} {v}");
        // A scaled direction gives the same point.
        let (t, _) = hit(Vec3::new(-1.15, 0.0, 5.0), -2.0 * Vec3::Z).unwrap();
        assert!((t - 4.867_712_5 / 2.0).abs() < 1e-5, "{t}");
        // From inside: no hit.
        assert!(hit(Vec3::new(-0.5, 0.25, 0.0), Vec3::X).is_none());
        // Beside it: none.
        assert!(hit(Vec3::new(-0.5, 0.7, 5.0), -Vec3::Z).is_none());
    }

    #[test]
    fn thin_hair_far_away() {
        // A hair of radius 1e-4 seen from 10 units (an ulp of t is 1e-6 there): the
        // hit lies on the surface.
        let (c0, c1) = (Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
        let o = Vec3::new(5e-5, 0.5, 10.0);
        let (t, v) =
            intersect_linear(o, -Vec3::Z, c0, c1, 1e-4, 1e-4, true, 0.0, f32::MAX).unwrap();
        let p = o - t * Vec3::Z;
        let r = Vec3::new(p.x, 0.0, p.z).length();
        assert!((r - 1e-4).abs() < 2e-6, "{r}");
        assert!((v - 0.5).abs() < 1e-5, "{v}");
        assert!(intersect_linear(
            Vec3::new(1.1e-4, 0.5, 10.0),
            -Vec3::Z,
            c0,
            c1,
            1e-4,
            1e-4,
            true,
            0.0,
            f32::MAX
        )
        .is_none());
    }

    #[test]
    fn curves_stay_in_the_tree_beside_quadrics_apart() {
        use crate::accel::{brute_force_closest, prims_from_shapes, Bvh, FlatPrims};
        use crate::gpu::layout::{PRIM_LINEAR_CURVE, PRIM_SPHERE};
        use crate::scene::{Mesh, Quadric};
        let curves = crate::scene::shape::linearcurve::parse(
            std::path::Path::new("c.txt"),
            b"-0.8 0 0 0.1\n0 0.3 0 0.15\n0.8 0 0 0.1\n\n0 -1 -1 0.05\n0 -1 1 0.05\n",
        )
        .unwrap();
        let floor = Mesh {
            positions: vec![
                Vec3::new(-2.0, -1.5, -2.0),
                Vec3::new(2.0, -1.5, -2.0),
                Vec3::new(0.0, -1.5, 2.0),
            ],
            indices: vec![[0, 2, 1]],
            ..Mesh::default()
        };
        let ball = Quadric::sphere(Vec3::new(0.0, -0.6, 0.0), 0.3, 0);
        let bvh = Bvh::build(prims_from_shapes(&[floor, curves], &[ball]));
        // The sphere apart, the curves' three segments in the tree with the triangle;
        // a scene this small is no flat one, since a curve's kind needs three bits.
        assert_eq!(bvh.apart, 1);
        assert_eq!(bvh.prims[0].kind, PRIM_SPHERE);
        assert_eq!(
            bvh.prims
                .iter()
                .filter(|p| p.kind == PRIM_LINEAR_CURVE)
                .count(),
            3
        );
        let flat = FlatPrims::of(&bvh, 8);
        assert!(!flat.flat_only && flat.count == 1);
        // Segment 1 starts where segment 0 ends: only segment 0 and 2 have start caps.
        let starts: Vec<(u32, bool)> = bvh
            .prims
            .iter()
            .filter(|p| p.kind == PRIM_LINEAR_CURVE)
            .map(|p| (p.index, p.p2[2] < 0.0))
            .collect();
        for (index, cap) in starts {
            assert_eq!(cap, index != 1, "segment {index}");
        }
        // The traversal finds what testing every primitive finds.
        let mut rng = 1u32;
        let mut next = || {
            rng = rng.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (rng >> 8) as f32 / (1 << 24) as f32 * 2.0 - 1.0
        };
        let mut hits = 0;
        for _ in 0..2000 {
            let o = Vec3::new(next(), next(), next()) * 3.0;
            let target = Vec3::new(next(), next() * 0.5, next() * 0.5);
            let d = target - o;
            let a = bvh.closest(o, d, 0.0, f32::MAX);
            let b = brute_force_closest(&bvh.prims, o, d, 0.0, f32::MAX);
            assert_eq!(a.map(|h| (h.prim, h.t)), b.map(|h| (h.prim, h.t)));
            hits += a.is_some_and(|h| bvh.prims[h.prim as usize].kind == PRIM_LINEAR_CURVE) as u32;
        }
        assert!(hits > 100, "{hits} curve hits");
    }
}
