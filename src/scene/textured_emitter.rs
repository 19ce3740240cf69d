//! Sampling a textured area emitter by its texture, as Mitsuba 3's `area` emitter does
//! when its radiance varies over the surface (src/emitters/area.cpp,
//! `sample_direction`): a point p in texture coordinates is drawn from the bitmap's
//! luminance (src/textures/bitmap.cpp, `sample_position`), mapped back to the
//! surface's uv by the inverse of `to_uv`, and from there to the surface; its density
//! per unit area is the texture-space density over |∂x/∂u × ∂x/∂v|. The GLSL mirror is
//! `shaders/emitter/emitter_texture.glsl`; this is its CPU reference.
//!
//! Density in texture coordinates (a 2-D distribution over the texels by luminance,
//! [`Distribution2D`]; texel (i, j) has probability P_ij):
//! - nearest filtering: piecewise constant, P_ij W H on texel (i, j)'s cell;
//! - bilinear filtering: Mitsuba's choice, a texel by P and then a tent-distributed
//!   offset of up to one texel around its centre in each axis (wrapped for `repeat`,
//!   reflected into [0, 1] for `clamp` and `mirror`), whose density is the bilinear
//!   interpolation of P_ij W H with the texture's own wrap mode.
//!
//! Either way the density is in proportion to the luminance of the filtered texture
//! itself (luminance is linear), so it is positive wherever the texture is and the
//! estimator stays unbiased. The texels' densities are stored beside the CDFs (the
//! product of two CDF differences, computed in floats as the GPU would), so a lookup
//! costs one load (nearest) or four (bilinear).
//!
//! Supported, as in Mitsuba: bitmap textures whose `to_uv` maps the unit square onto
//! itself (a flip, a transpose, a multiple of 90°; |det| = 1, inverse = transpose), on
//! - meshes whose uv map is one affine map tiling [0, 1]² exactly once ([`AffineUvMap`];
//!   Mitsuba's `rectangle` is one), and
//! - spheres (uv = (φ/2π, θ/π): |∂x/∂u × ∂x/∂v| = 2π² r² sin θ).
//!
//! Every other textured emitter (other textures, other `to_uv`, cubes and general
//! meshes, disks, cylinders) keeps uniform area sampling weighted by the texture,
//! which is unbiased too: `SceneRecords` leaves its `dist_width` at 0.

use glam::{DVec3, Vec2, Vec3};

use super::distribution2d::Distribution2D;
use super::texture::{apply_uv, filtered_lookup, Texture, Wrap};
use super::Mesh;

/// Luminance of linear sRGB (Rec. 709).
fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// Whether the affine `to_uv` maps the unit square onto itself (its four corners onto
/// the four corners, within Mitsuba's tolerance: bitmap.cpp,
/// `check_sampling_transform`).
pub fn is_square_symmetry(to_uv: &[[f32; 3]; 2]) -> bool {
    let corners = [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
    let mut hits = 0u32;
    for c in corners {
        let p = apply_uv(to_uv, c);
        for (k, q) in corners.iter().enumerate() {
            if (p - *q).length_squared() < 1e-8 {
                hits |= 1 << k;
            }
        }
    }
    hits == 0xf
}

/// The texture-space sampling distribution of a bitmap emitter texture.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureSampling {
    pub dist: Distribution2D,
    /// Per texel (row 0 first), P_ij W H: the density (in texture coordinates) of its
    /// cell under nearest filtering, the interpolated values under bilinear.
    pub density: Vec<f32>,
    pub nearest: bool,
    pub wrap: Wrap,
    pub to_uv: [[f32; 3]; 2],
}

impl TextureSampling {
    /// The distribution of `texture`, or `None` where it cannot be sampled (module
    /// doc): not a bitmap, a `to_uv` that is no symmetry of the unit square, or no
    /// positive texel.
    pub fn new(texture: &Texture) -> Option<TextureSampling> {
        let Texture::Bitmap {
            width,
            height,
            texels,
            nearest,
            wrap,
            to_uv,
        } = texture
        else {
            return None;
        };
        if !is_square_symmetry(to_uv) {
            return None;
        }
        let weights: Vec<f64> = texels
            .iter()
            .map(|t| {
                let l = luminance(*t);
                if l > 0.0 {
                    l as f64
                } else {
                    0.0
                }
            })
            .collect();
        if !weights.iter().any(|&w| w > 0.0) || !weights.iter().all(|w| w.is_finite()) {
            return None;
        }
        let dist = Distribution2D::from_weights(*width, *height, &weights);
        let cells = (*width * *height) as f32;
        let density = (0..*height)
            .flat_map(|j| (0..*width).map(move |i| (i, j)))
            .map(|(i, j)| dist.cell_probability_f32(i, j) * cells)
            .collect();
        Some(TextureSampling {
            dist,
            density,
            nearest: *nearest,
            wrap: *wrap,
            to_uv: *to_uv,
        })
    }

    /// The words of the distribution buffer: the CDFs, then the texels' densities.
    pub fn buffer(&self) -> Vec<f32> {
        let mut b = self.dist.cdf.clone();
        b.extend_from_slice(&self.density);
        b
    }

    /// Density of [`Self::sample`] at texture-space point `p` (through `to_uv`), per
    /// unit area of texture coordinates: looked up as the texture looks up its texels.
    pub fn density(&self, p: Vec2) -> f32 {
        let w = self.dist.width;
        filtered_lookup(
            p,
            (w, self.dist.height),
            self.nearest,
            self.wrap,
            |i, j| self.density[(j * w + i) as usize],
            |a, b, t| a + (b - a) * t,
        )
    }

    /// A texture-space point in [0, 1]² from the uniform pair `u` (u.x picks the row,
    /// u.y the column, as `dist2d_sample_cell`).
    pub fn sample(&self, u: Vec2) -> Vec2 {
        let ((i, j), f) = self.dist.sample_cell(u);
        let res = Vec2::new(self.dist.width as f32, self.dist.height as f32);
        let cell = Vec2::new(i as f32, j as f32);
        if self.nearest {
            return (cell + f) / res;
        }
        let tent = |x: f32| {
            // Mitsuba's warp::square_to_tent: density 1 - |t| on [-1, 1].
            let x = 2.0 * x - 1.0;
            x.signum() * (1.0 - (1.0 - x.abs()).max(0.0).sqrt())
        };
        let p = (cell + 0.5 + Vec2::new(tent(f.x), tent(f.y))) / res;
        p.to_array()
            .map(|c| match self.wrap {
                Wrap::Repeat if c < 0.0 => c + 1.0,
                Wrap::Repeat if c > 1.0 => c - 1.0,
                Wrap::Repeat => c,
                _ if c < 0.0 => -c,
                _ if c > 1.0 => 2.0 - c,
                _ => c,
            })
            .into()
    }

    /// Surface uv of texture-space point `p`: the inverse of `to_uv`, its transpose
    /// (to_uv's linear part is a signed permutation).
    pub fn surface_uv(&self, p: Vec2) -> Vec2 {
        let m = &self.to_uv;
        let q = p - Vec2::new(m[0][2], m[1][2]);
        Vec2::new(m[0][0] * q.x + m[1][0] * q.y, m[0][1] * q.x + m[1][1] * q.y)
    }

    /// The texture-space point of surface uv `uv` (`to_uv`).
    pub fn texture_point(&self, uv: Vec2) -> Vec2 {
        apply_uv(&self.to_uv, uv)
    }
}

/// A mesh whose surface is the image of the unit uv square under one affine map, each
/// point once: x(u, v) = `origin` + u `du` + v `dv`, with the geometric normal
/// `normal` that every hit on it finds (vertex normals and `flip_normals` applied as
/// `surface_at` applies them).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AffineUvMap {
    pub origin: Vec3,
    pub du: Vec3,
    pub dv: Vec3,
    pub normal: Vec3,
}

impl AffineUvMap {
    /// The map of `mesh`, or `None` unless (all checked here, so that no sampled point
    /// lies off the surface or twice on it):
    /// - every vertex lies where one affine map of its uv puts it (within 1e-5 of the
    ///   map's size);
    /// - the uv triangles all have the same orientation, lie in [0, 1]², have total
    ///   area 1, and every edge not shared with a neighbour (same two uvs, opposite
    ///   direction) lies on the square's boundary: the triangles' winding number is
    ///   then constant inside the square and, by the area, 1, so they tile it once;
    /// - the vertex normals (if any) all lie on one side of the plane.
    pub fn of_mesh(mesh: &Mesh) -> Option<AffineUvMap> {
        if mesh.uvs.len() != mesh.positions.len() || mesh.indices.is_empty() {
            return None;
        }
        let uv = |v: u32| mesh.uvs[v as usize].as_dvec2();
        let pos = |v: u32| mesh.positions[v as usize].as_dvec3();
        // The map from the first triangle (PBR 4th ed., sec. 6.5.3: ∂p/∂u, ∂p/∂v).
        let [a, b, c] = mesh.indices[0];
        let (duv0, duv1) = (uv(b) - uv(a), uv(c) - uv(a));
        let (dp0, dp1) = (pos(b) - pos(a), pos(c) - pos(a));
        let det = duv0.x * duv1.y - duv0.y * duv1.x;
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let du = (duv1.y * dp0 - duv0.y * dp1) / det;
        let dv = (duv0.x * dp1 - duv1.x * dp0) / det;
        let origin = pos(a) - uv(a).x * du - uv(a).y * dv;
        let tol = 1e-5 * (du.length() + dv.length());
        if !(tol > 0.0 && tol.is_finite()) {
            return None;
        }
        let mut area = 0.0;
        let mut edges = std::collections::HashMap::new();
        let key = |v: u32| mesh.uvs[v as usize].to_array().map(f32::to_bits);
        let inside = |p: glam::DVec2| {
            p.cmpge(glam::DVec2::splat(-1e-6)).all()
                && p.cmple(glam::DVec2::splat(1.0 + 1e-6)).all()
        };
        for t in &mesh.indices {
            let [a, b, c] = *t;
            let d = (uv(b) - uv(a)).perp_dot(uv(c) - uv(a));
            if d * det <= 0.0 {
                return None; // degenerate in uv, or turned over
            }
            area += d.abs() * 0.5;
            for v in [a, b, c] {
                if (origin + uv(v).x * du + uv(v).y * dv - pos(v)).length() > tol || !inside(uv(v))
                {
                    return None;
                }
            }
            for (p, q) in [(a, b), (b, c), (c, a)] {
                let (kp, kq) = (key(p), key(q));
                let (k, s) = if kp < kq {
                    ((kp, kq), 1)
                } else {
                    ((kq, kp), -1)
                };
                *edges.entry(k).or_insert(0i32) += s;
            }
        }
        if (area - 1.0).abs() > 1e-5 {
            return None;
        }
        let on_boundary = |p: [u32; 2], q: [u32; 2]| {
            let (p, q) = (p.map(f32::from_bits), q.map(f32::from_bits));
            (0..2).any(|k| p[k] == q[k] && (p[k] == 0.0 || p[k] == 1.0))
        };
        for ((p, q), n) in edges {
            if n != 0 && (n.abs() > 1 || !on_boundary(p, q)) {
                return None;
            }
        }
        // A triangle's geometric normal is cross(p1 - p0, p2 - p0) = 2 a_uv (du × dv).
        let mut normal: DVec3 = du.cross(dv).normalize() * det.signum();
        if !normal.is_finite() {
            return None;
        }
        if !mesh.normals.is_empty() {
            let sides: Vec<f64> = mesh
                .normals
                .iter()
                .map(|n| n.as_dvec3().dot(normal))
                .collect();
            if sides.iter().all(|&s| s < 0.0) {
                normal = -normal;
            } else if !sides.iter().all(|&s| s > 0.0) {
                return None;
            }
        }
        if mesh.flip_normals {
            normal = -normal;
        }
        Some(AffineUvMap {
            origin: origin.as_vec3(),
            du: du.as_vec3(),
            dv: dv.as_vec3(),
            normal: normal.as_vec3(),
        })
    }

    /// The surface point at uv.
    pub fn point(&self, uv: Vec2) -> Vec3 {
        self.origin + uv.x * self.du + uv.y * self.dv
    }

    /// |∂x/∂u × ∂x/∂v|: surface area per unit uv area.
    pub fn jacobian(&self) -> f32 {
        self.du.cross(self.dv).length()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::mesh;
    use glam::Mat4;

    /// A 5 x 3 bitmap with one bright texel and a dark one.
    fn bitmap(nearest: bool, wrap: Wrap, to_uv: [[f32; 3]; 2]) -> Texture {
        let mut texels: Vec<[f32; 3]> = (0..15)
            .map(|k| [0.5 + (k % 5) as f32 * 0.3, 1.0 + (k / 5) as f32, 0.2])
            .collect();
        texels[7] = [40.0, 30.0, 20.0];
        texels[3] = [0.0; 3];
        Texture::Bitmap {
            width: 5,
            height: 3,
            texels,
            nearest,
            wrap,
            to_uv,
        }
    }

    const IDENTITY: [[f32; 3]; 2] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    /// u' = 1 - v, v' = u: a quarter turn of the square.
    const TURN: [[f32; 3]; 2] = [[0.0, -1.0, 1.0], [1.0, 0.0, 0.0]];

    fn all_kinds() -> Vec<Texture> {
        let mut v = Vec::new();
        for nearest in [true, false] {
            for wrap in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror] {
                for to_uv in [IDENTITY, TURN] {
                    v.push(bitmap(nearest, wrap, to_uv));
                }
            }
        }
        v
    }

    /// Midpoint rule over an n x n grid of [0, 1]².
    fn grid(n: usize) -> impl Iterator<Item = Vec2> {
        (0..n * n).map(move |k| {
            Vec2::new(
                ((k % n) as f32 + 0.5) / n as f32,
                ((k / n) as f32 + 0.5) / n as f32,
            )
        })
    }

    #[test]
    fn density_integrates_to_one_and_follows_the_luminance() {
        for t in all_kinds() {
            let s = TextureSampling::new(&t).unwrap();
            // Cells aligned with the texels': the midpoint rule is exact on their
            // constant or bilinear pieces.
            let n = 300;
            let integral: f64 = grid(n).map(|p| s.density(p) as f64).sum::<f64>() / (n * n) as f64;
            assert!((integral - 1.0).abs() < 1e-3, "{t:?}: {integral}");
            // In proportion to the filtered texture's luminance, which the texture sees
            // at surface uv to_uv⁻¹(p): positive wherever the texture is.
            // The mean over the square is the texels' mean for both filters and every
            // wrap mode (each texel's tent integrates to 1 / W H).
            let Texture::Bitmap { texels, .. } = &t else {
                unreachable!()
            };
            let mean = texels.iter().map(|c| luminance(*c)).sum::<f32>() / texels.len() as f32;
            for p in grid(37) {
                let lum = luminance(t.eval(s.surface_uv(p)).to_array());
                let want = lum / mean;
                assert!(
                    (s.density(p) - want).abs() < 1e-4 * want.max(1.0),
                    "{t:?} at {p}: density {} for luminance {lum} (mean {mean})",
                    s.density(p)
                );
            }
        }
    }

    #[test]
    fn samples_follow_the_density() {
        for t in all_kinds() {
            let s = TextureSampling::new(&t).unwrap();
            // 20 x 12 bins (finer than the texels, their edges on the texels' edges
            // and centres: the midpoint rule below is exact), from pseudo-random
            // uniform numbers (a 64-bit LCG, Knuth's MMIX constants).
            let (bw, bh) = (20, 12);
            let mut count = vec![0f64; bw * bh];
            let samples = 400_000;
            let mut state = 1u64;
            let mut next = || {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (state >> 40) as f32 / (1u64 << 24) as f32
            };
            for _ in 0..samples {
                let u = Vec2::new(next(), next());
                let p = s.sample(u);
                assert!(p.cmpge(Vec2::ZERO).all() && p.cmple(Vec2::ONE).all(), "{p}");
                let i = ((p.x * bw as f32) as usize).min(bw - 1);
                let j = ((p.y * bh as f32) as usize).min(bh - 1);
                count[j * bw + i] += 1.0;
            }
            let k = 8;
            for j in 0..bh {
                for i in 0..bw {
                    let mut e = 0.0;
                    for q in grid(k) {
                        let p =
                            Vec2::new((i as f32 + q.x) / bw as f32, (j as f32 + q.y) / bh as f32);
                        e += s.density(p) as f64;
                    }
                    let e = e / (k * k * bw * bh) as f64;
                    let o = count[j * bw + i] / samples as f64;
                    // Five standard deviations of a binomial count.
                    let sigma = (e * (1.0 - e) / samples as f64).sqrt();
                    assert!(
                        (o - e).abs() < 5.0 * sigma + 1e-6,
                        "{t:?} bin ({i}, {j}): {o} vs {e}"
                    );
                }
            }
        }
    }

    #[test]
    fn to_uv_must_map_the_square_onto_itself() {
        assert!(is_square_symmetry(&IDENTITY));
        assert!(is_square_symmetry(&TURN));
        assert!(is_square_symmetry(&[[-1.0, 0.0, 1.0], [0.0, 1.0, 0.0]]));
        assert!(!is_square_symmetry(&[[2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]));
        assert!(!is_square_symmetry(&[[1.0, 0.0, 0.5], [0.0, 1.0, 0.0]]));
        assert!(TextureSampling::new(&bitmap(
            true,
            Wrap::Repeat,
            [[2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]
        ))
        .is_none());
        let s = TextureSampling::new(&bitmap(true, Wrap::Repeat, TURN)).unwrap();
        for p in grid(9) {
            let uv = s.surface_uv(p);
            assert!((s.texture_point(uv) - p).length() < 1e-6);
        }
        let checker = Texture::Checkerboard {
            color0: Vec3::ONE,
            color1: Vec3::ZERO,
            to_uv: IDENTITY,
        };
        assert!(TextureSampling::new(&checker).is_none());
    }

    #[test]
    fn buffer_holds_the_cdfs_then_the_densities() {
        let s = TextureSampling::new(&bitmap(true, Wrap::Repeat, IDENTITY)).unwrap();
        let b = s.buffer();
        assert_eq!(b.len(), 4 + 3 * 6 + 15);
        assert_eq!(&b[..22], &s.dist.cdf[..]);
        // The dark texel is never sampled; the bright one most often.
        assert_eq!(b[22 + 3], 0.0);
        assert!(s.density.iter().all(|&d| d <= b[22 + 7]));
        let sum: f32 = s.density.iter().sum();
        assert!((sum / 15.0 - 1.0).abs() < 1e-5);
    }

    fn rectangle(to_world: Mat4) -> Mesh {
        let mut m = mesh::rectangle();
        mesh::transform(&mut m, to_world);
        m
    }

    #[test]
    fn a_rectangle_is_one_affine_map() {
        let to_world = Mat4::from_translation(Vec3::new(0.2, 2.4, 0.3))
            * Mat4::from_rotation_x(90f32.to_radians())
            * Mat4::from_scale(Vec3::new(0.8, 0.5, 1.0));
        let m = rectangle(to_world);
        let map = AffineUvMap::of_mesh(&m).unwrap();
        for (p, uv) in m.positions.iter().zip(&m.uvs) {
            assert!((map.point(*uv) - *p).length() < 1e-5);
        }
        assert!((map.jacobian() - 4.0 * 0.8 * 0.5).abs() < 1e-5);
        // Facing down, as the rectangle's +z turned by 90° about x.
        assert!(
            (map.normal - Vec3::new(0.0, -1.0, 0.0)).length() < 1e-5,
            "{}",
            map.normal
        );
        let mut flipped = m.clone();
        flipped.flip_normals = true;
        assert_eq!(AffineUvMap::of_mesh(&flipped).unwrap().normal, -map.normal);
    }

    #[test]
    fn meshes_that_do_not_tile_the_square_once_are_refused() {
        // The cube: six faces over the same square.
        let mut cube = mesh::cube();
        mesh::transform(&mut cube, Mat4::IDENTITY);
        assert!(AffineUvMap::of_mesh(&cube).is_none());
        // Half the square.
        let mut half = rectangle(Mat4::IDENTITY);
        half.indices.pop();
        assert!(AffineUvMap::of_mesh(&half).is_none());
        // uvs over [0, 2]².
        let mut big = rectangle(Mat4::IDENTITY);
        big.uvs.iter_mut().for_each(|uv| *uv *= 2.0);
        assert!(AffineUvMap::of_mesh(&big).is_none());
        // A bent quad: not one affine map.
        let mut bent = rectangle(Mat4::IDENTITY);
        bent.positions[3].z = 0.3;
        assert!(AffineUvMap::of_mesh(&bent).is_none());
        // No uvs.
        let mut bare = rectangle(Mat4::IDENTITY);
        bare.uvs.clear();
        assert!(AffineUvMap::of_mesh(&bare).is_none());
        // A 2 x 2 grid of quads sharing vertices tiles the square: accepted.
        let mut g = Mesh::default();
        for j in 0..3 {
            for i in 0..3 {
                let uv = Vec2::new(i as f32 / 2.0, j as f32 / 2.0);
                g.uvs.push(uv);
                g.positions.push(Vec3::new(3.0 * uv.x, 1.0, -2.0 * uv.y));
            }
        }
        for j in 0..2 {
            for i in 0..2 {
                let v = j * 3 + i;
                g.indices.push([v, v + 1, v + 4]);
                g.indices.push([v, v + 4, v + 3]);
            }
        }
        let map = AffineUvMap::of_mesh(&g).unwrap();
        assert!((map.jacobian() - 6.0).abs() < 1e-5);
        // Two triangles overlapping: total area 1 but a fold.
        let mut fold = g.clone();
        fold.indices[0] = [0, 1, 3];
        assert!(AffineUvMap::of_mesh(&fold).is_none());
    }
}
