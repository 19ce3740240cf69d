//! Watertight ray/triangle intersection (Woop, Benthin, Wald 2013, "Watertight
//! Ray/Triangle Intersection", JCGT 2(1)).
//!
//! The ray is sheared and scaled once so that it becomes the +z axis from the origin
//! (section 3, "ray transformation"); each triangle is then tested in 2D with three
//! edge functions. The edge function of a shared edge is computed from the same
//! transformed vertices in both triangles and comes out exactly negated, so a ray that
//! crosses the edge is counted by at least one of them: no ray leaks through a closed
//! mesh. A ray that hits an edge or vertex exactly (an edge function is 0) is counted
//! by every triangle sharing it.
//!
//! Mirrored line for line by `shaders/shape/intersect_triangle.glsl`.
//!
//! Departures from the paper, the same in GLSL:
//! - no backface culling (the two-sided test of section 4, listing 2 without `#ifdef`);
//! - the paper's double-precision re-evaluation of zero edge functions (also in
//!   pbrt-v4's `IntersectTriangle`) is left out: a zero edge function is
//!   accepted as it is, which can only add hits on exact edges and vertices, never lose
//!   one, since watertightness rests on the exact negation above, not on fp64; and
//!   kernels stay free of fp64, which some GPUs lack;
//! - edge functions are products of two coordinates relative to the ray origin, so
//!   they overflow f32 beyond about 1e18 (no hits, no NaN) and go denormal below about
//!   1e-19 (GPUs flushing denormals then miss).
//! - `t` is computed by one division and compared with `(tmin, tmax)` instead of the
//!   paper's scaled comparison, so the range is open at both ends.

use glam::Vec3;

/// The per-ray part of the test: the axis permutation `k` and shear `s`
/// (Woop et al. 2013, listing 1).
#[derive(Clone, Copy, Debug)]
pub struct TriangleRay {
    /// `kx, ky, kz`: `kz` is the dimension where |d| is largest; `kx, ky` follow it
    /// cyclically and are swapped when `d[kz] < 0` to keep the winding.
    pub k: [usize; 3],
    /// `Sx = d[kx] / d[kz]`, `Sy = d[ky] / d[kz]`, `Sz = 1 / d[kz]`.
    pub s: Vec3,
}

impl TriangleRay {
    /// Precomputes the shear for direction `d` (any length, not zero).
    pub fn new(d: Vec3) -> TriangleRay {
        let a = d.abs();
        let kz = if a.x > a.y {
            if a.x > a.z {
                0
            } else {
                2
            }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        TriangleRay {
            k: [kx, ky, kz],
            s: Vec3::new(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]),
        }
    }
}

/// γ(n) = n ε / (1 - n ε), ε = 2^-24 (PBR 4th ed., sec. 6.8.1), rounded up;
/// `TRIANGLE_GAMMA*` in intersect_triangle.glsl.
pub const GAMMA2: f32 = 1.192_093e-7;
pub const GAMMA3: f32 = 1.788_139_6e-7;
pub const GAMMA5: f32 = 2.980_232_6e-7;

/// A ray/triangle hit: distance and barycentrics, `p = (1-u-v) p0 + u p1 + v p2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    pub t: f32,
    pub u: f32,
    pub v: f32,
}

/// Intersects the ray `o + t d` (with `tr = TriangleRay::new(d)`) with the triangle
/// `p0 p1 p2`; returns the hit if `tmin < t < tmax`. Both faces count.
#[inline]
pub fn intersect(
    tr: &TriangleRay,
    o: Vec3,
    p0: Vec3,
    p1: Vec3,
    p2: Vec3,
    tmin: f32,
    tmax: f32,
) -> Option<TriangleHit> {
    let [kx, ky, kz] = tr.k;
    let s = tr.s;
    // Vertices relative to the origin, sheared so the ray is +z (listing 1).
    let a = p0 - o;
    let b = p1 - o;
    let c = p2 - o;
    let ax = a[kx] - s.x * a[kz];
    let ay = a[ky] - s.y * a[kz];
    let bx = b[kx] - s.x * b[kz];
    let by = b[ky] - s.y * b[kz];
    let cx = c[kx] - s.x * c[kz];
    let cy = c[ky] - s.y * c[kz];
    // Scaled barycentrics: edge functions of the 2D triangle at the origin.
    let eu = cx * by - cy * bx;
    let ev = ax * cy - ay * cx;
    let ew = bx * ay - by * ax;
    // Outside if the signs differ; zeros (edges, vertices) count as inside.
    if (eu < 0.0 || ev < 0.0 || ew < 0.0) && (eu > 0.0 || ev > 0.0 || ew > 0.0) {
        return None;
    }
    let det = eu + ev + ew;
    if det == 0.0 {
        return None; // ray parallel to the triangle's plane, or a degenerate triangle
    }
    // Scaled hit distance from the interpolated z of the vertices.
    let az = s.z * a[kz];
    let bz = s.z * b[kz];
    let cz = s.z * c[kz];
    let rcp_det = 1.0 / det;
    let t = (eu * az + ev * bz + ew * cz) * rcp_det;
    if !(t > tmin && t < tmax) {
        return None;
    }
    // Reject hits whose t is within its own rounding error of zero, which a ray
    // leaving this very surface produces (PBR 4th ed., sec. 6.8.7: bounds on the error
    // of the sheared coordinates, the edge functions and t).
    let max_zt = az.abs().max(bz.abs()).max(cz.abs());
    let max_xt = ax.abs().max(bx.abs()).max(cx.abs());
    let max_yt = ay.abs().max(by.abs()).max(cy.abs());
    let delta_z = GAMMA3 * max_zt;
    // The shear's error involves s.x·z with |s.x| <= 1: unscaled z, in x/y units (PBR
    // uses the scaled z here, which equals it only for unit directions).
    let max_z = a[kz].abs().max(b[kz].abs()).max(c[kz].abs());
    let delta_x = GAMMA5 * (max_xt + max_z);
    let delta_y = GAMMA5 * (max_yt + max_z);
    let delta_e = 2.0 * (GAMMA2 * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = eu.abs().max(ev.abs()).max(ew.abs());
    let delta_t =
        3.0 * (GAMMA3 * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * rcp_det.abs();
    if t <= delta_t {
        return None;
    }
    Some(TriangleHit {
        t,
        u: ev * rcp_det,
        v: ew * rcp_det,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hit(o: Vec3, d: Vec3, p: [Vec3; 3]) -> Option<TriangleHit> {
        intersect(
            &TriangleRay::new(d),
            o,
            p[0],
            p[1],
            p[2],
            0.0,
            f32::INFINITY,
        )
    }

    #[test]
    fn barycentrics_reconstruct_the_hit_point() {
        let p = [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(2.0, 0.0, 1.5),
            Vec3::new(0.0, 3.0, 2.0),
        ];
        for (o, d) in [
            (Vec3::new(0.3, 0.4, -2.0), Vec3::new(0.1, 0.2, 1.0)),
            (Vec3::new(0.3, 0.4, 5.0), Vec3::new(0.1, 0.2, -1.0)),
            (Vec3::new(-3.0, 0.5, 1.2), Vec3::new(1.0, 0.0, 0.0)),
        ] {
            let h = hit(o, d, p).expect("hit");
            let q = (1.0 - h.u - h.v) * p[0] + h.u * p[1] + h.v * p[2];
            assert!((o + h.t * d - q).length() < 1e-5, "{h:?}");
        }
    }

    #[test]
    fn both_faces_hit_and_range_is_open() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let up = hit(Vec3::new(0.2, 0.2, -1.0), Vec3::Z, p).unwrap();
        let down = hit(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z, p).unwrap();
        assert_eq!(up.t, 1.0);
        assert_eq!(down.t, 1.0);
        let tr = TriangleRay::new(Vec3::Z);
        let o = Vec3::new(0.2, 0.2, -1.0);
        assert!(intersect(&tr, o, p[0], p[1], p[2], 0.0, 1.0).is_none());
        assert!(intersect(&tr, o, p[0], p[1], p[2], 1.0, 2.0).is_none());
        assert!(intersect(&tr, o, p[0], p[1], p[2], 0.0, 1.0001).is_some());
        // Behind the origin.
        assert!(hit(Vec3::new(0.2, 0.2, 1.0), Vec3::Z, p).is_none());
    }

    #[test]
    fn edges_and_vertices_are_inside_degenerate_and_parallel_miss() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        for q in [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(0.5, 0.5, 0.0)] {
            assert!(hit(q - Vec3::Z, Vec3::Z, p).is_some(), "{q}");
        }
        let flat = [Vec3::ZERO, Vec3::X, 2.0 * Vec3::X];
        assert!(hit(Vec3::new(0.5, 0.0, -1.0), Vec3::Z, flat).is_none());
        assert!(hit(Vec3::new(-1.0, 0.2, 0.0), Vec3::X, p).is_none());
    }
}
