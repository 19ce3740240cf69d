//! Building and preparing triangle meshes: Mitsuba's built-in `rectangle` and `cube`,
//! and the steps every mesh goes through on its way to world space (`to_world`,
//! vertex normals computed where a file has none, dropping degenerate triangles).

use glam::{Mat3, Mat4, Vec2, Vec3};
use rayon::prelude::*;

use super::Mesh;

/// Mitsuba 3.9's `rectangle` (src/shapes/rectangle.cpp): [-1, 1]² in the z = 0 plane,
/// normal +z, vertex k at ((k & 1) ? 1 : -1, (k & 2) ? 1 : -1) with uv (k & 1, k >> 1),
/// faces (1, 2, 0) and (1, 3, 2).
pub fn rectangle() -> Mesh {
    let corner = |k: u32| ((k & 1) as f32, (k >> 1) as f32);
    Mesh {
        name: "rectangle".into(),
        positions: (0..4)
            .map(|k| {
                let (x, y) = corner(k);
                Vec3::new(2.0 * x - 1.0, 2.0 * y - 1.0, 0.0)
            })
            .collect(),
        normals: vec![Vec3::Z; 4],
        uvs: (0..4).map(|k| Vec2::from(corner(k))).collect(),
        indices: vec![[1, 2, 0], [1, 3, 2]],
        ..Mesh::default()
    }
}

/// Mitsuba 3.9's `cube` (src/shapes/cube.cpp): [-1, 1]³ as 24 vertices, four per face
/// with the face's outward normal and uvs (0, 1), (1, 1), (1, 0), (0, 0), and faces
/// (4f, 4f+1, 4f+2), (4f+3, 4f, 4f+2). Faces in the table's order: -y, +y, +x, +z, -x,
/// -z; each face's corners in the order the table lists them.
pub fn cube() -> Mesh {
    #[rustfmt::skip]
    const CORNERS: [[f32; 3]; 24] = [
        [1., -1., -1.], [1., -1., 1.], [-1., -1., 1.], [-1., -1., -1.],
        [1., 1., -1.], [-1., 1., -1.], [-1., 1., 1.], [1., 1., 1.],
        [1., -1., -1.], [1., 1., -1.], [1., 1., 1.], [1., -1., 1.],
        [1., -1., 1.], [1., 1., 1.], [-1., 1., 1.], [-1., -1., 1.],
        [-1., -1., 1.], [-1., 1., 1.], [-1., 1., -1.], [-1., -1., -1.],
        [1., 1., -1.], [1., -1., -1.], [-1., -1., -1.], [-1., 1., -1.],
    ];
    #[rustfmt::skip]
    const NORMALS: [[f32; 3]; 6] = [
        [0., -1., 0.], [0., 1., 0.], [1., 0., 0.], [0., 0., 1.], [-1., 0., 0.], [0., 0., -1.],
    ];
    const UVS: [[f32; 2]; 4] = [[0., 1.], [1., 1.], [1., 0.], [0., 0.]];
    let mut m = Mesh {
        name: "cube".into(),
        ..Mesh::default()
    };
    for (i, p) in CORNERS.iter().enumerate() {
        m.positions.push(Vec3::from(*p));
        m.normals.push(Vec3::from(NORMALS[i / 4]));
        m.uvs.push(Vec2::from(UVS[i % 4]));
    }
    for f in 0..6 {
        let v = 4 * f;
        m.indices.push([v, v + 1, v + 2]);
        m.indices.push([v + 3, v, v + 2]);
    }
    m
}

/// Applies `to_world`: positions by the matrix, normals by its inverse transpose,
/// renormalized. If any normal becomes zero or non-finite the mesh keeps no normals.
pub fn transform(mesh: &mut Mesh, to_world: Mat4) {
    if to_world == Mat4::IDENTITY {
        return;
    }
    mesh.positions
        .par_iter_mut()
        .for_each(|p| *p = to_world.transform_point3(*p));
    let normal_matrix = Mat3::from_mat4(to_world).inverse().transpose();
    let ok = normal_matrix.is_finite()
        && mesh
            .normals
            .par_iter_mut()
            .map(|n| match (normal_matrix * *n).try_normalize() {
                Some(v) => {
                    *n = v;
                    true
                }
                None => false,
            })
            .reduce(|| true, |a, b| a && b);
    if !ok {
        mesh.normals.clear();
    }
}

/// Mitsuba's vertex normals for a mesh file without them (`Mesh::recompute_vertex_normals`,
/// after Thürmer and Wüthrich 1998, "Computing Vertex Normals from Polygonal
/// Facets"): each triangle's unit normal, weighted by its angle at the vertex, summed
/// and normalized. Computed on world-space positions and in the file's winding, as
/// Mitsuba does after applying `to_world` (so a mirroring transform turns them
/// inwards with the winding). A vertex on no triangle of positive area gets +x.
///
/// Returns whether every triangle has a positive, finite area: then
/// [`drop_degenerate`] has nothing to drop and the caller may skip it.
pub fn compute_vertex_normals(mesh: &mut Mesh) -> bool {
    vertex_normals_in_ranges(mesh, rayon::current_num_threads())
}

/// [`compute_vertex_normals`] over `ranges` ranges of vertices in parallel: each task
/// walks all triangles and adds, in triangle order, the corners that fall in its
/// range, so every sum is added in the order of one serial pass, bit for bit, and
/// each corner's angle (the costly part) is computed once. Every triangle has a corner
/// in some range, so the ranges together see the area of each.
fn vertex_normals_in_ranges(mesh: &mut Mesh, ranges: usize) -> bool {
    let p = &mesh.positions;
    let indices = &mesh.indices;
    let per = p.len().div_ceil(ranges.max(1)).max(1);
    let mut normals = vec![Vec3::ZERO; p.len()];
    let all_valid = normals
        .par_chunks_mut(per)
        .enumerate()
        .map(|(r, acc)| {
            let lo = (r * per) as u32;
            let len = acc.len() as u32;
            let mine = |i: u32| i.wrapping_sub(lo) < len;
            let mut all_valid = true;
            for tris in indices.chunks(LANES) {
                if !tris.iter().flatten().any(|&i| mine(i)) {
                    continue;
                }
                let w = CornerWeights::of(p, tris);
                for (j, t) in tris.iter().enumerate() {
                    if !w.valid[j] {
                        all_valid = false;
                        continue;
                    }
                    for k in 0..3 {
                        if mine(t[k]) {
                            acc[(t[k] - lo) as usize] += w.normal[j] * w.angle[k][j];
                        }
                    }
                }
            }
            all_valid
        })
        .reduce(|| true, |a, b| a && b);
    normals
        .par_iter_mut()
        .for_each(|n| *n = n.try_normalize().unwrap_or(Vec3::X));
    mesh.normals = normals;
    all_valid
}

/// Triangles whose corner weights are computed together, in straight-line code over
/// arrays the compiler turns into SIMD instructions.
const LANES: usize = 8;

/// The unit normals and corner angles of up to [`LANES`] triangles.
struct CornerWeights {
    normal: [Vec3; LANES],
    /// `angle[k][j]`: the angle of triangle j at its corner k.
    angle: [[f32; LANES]; 3],
    /// False for a triangle of zero or non-finite area (no normal, no weight).
    valid: [bool; LANES],
}

impl CornerWeights {
    fn of(p: &[Vec3], tris: &[[u32; 3]]) -> Self {
        let mut corners = [[Vec3::ZERO; 3]; LANES];
        for (v, t) in corners.iter_mut().zip(tris) {
            *v = t.map(|i| p[i as usize]);
        }
        let mut w = CornerWeights {
            normal: [Vec3::ZERO; LANES],
            angle: [[0.0; LANES]; 3],
            valid: [false; LANES],
        };
        for (j, v) in corners.iter().enumerate() {
            let n = (v[1] - v[0]).cross(v[2] - v[0]);
            let len2 = n.length_squared();
            w.valid[j] = has_area(len2);
            w.normal[j] = n / len2.sqrt();
            // Each edge normalized once: corner k's edges are u[k] and -u[k + 2], the
            // same bits as normalizing v[k + 1] - v[k] and v[k + 2] - v[k].
            let u = [v[1] - v[0], v[2] - v[1], v[0] - v[2]].map(Vec3::normalize_or_zero);
            for k in 0..3 {
                w.angle[k][j] = unit_angle(u[k], -u[(k + 2) % 3]);
            }
        }
        w
    }
}

/// The angle between unit vectors, accurate near 0 and π (Mitsuba's `unit_angle`):
/// 2 asin(|a - b| / 2), or π - 2 asin(|a + b| / 2) where they are more than π/2 apart.
/// Branch-free, so that [`CornerWeights`] vectorizes.
fn unit_angle(a: Vec3, b: Vec3) -> f32 {
    let obtuse = a.dot(b) < 0.0;
    let half = if obtuse { a + b } else { a - b }.length() * 0.5;
    let angle = 2.0 * asin_unit(half);
    if obtuse {
        std::f32::consts::PI - angle
    } else {
        angle
    }
}

/// asin(min(x, 1)) for x >= 0, within 2 ulp of the correctly rounded value (tested):
/// Cephes' `asinf`, the odd polynomial of Moshier's minimax fit on [0, 1/2] and
/// asin(x) = π/2 - 2 asin(sqrt((1 - x) / 2)) above, evaluated once on the chosen
/// argument. Vertex normals take one per triangle corner, where the C library's
/// asinf took half of a PLY file's load.
fn asin_unit(x: f32) -> f32 {
    let x = x.min(1.0);
    let upper = x > 0.5;
    let z = if upper { 0.5 * (1.0 - x) } else { x * x };
    let s = if upper { z.sqrt() } else { x };
    let poly = (((4.216_32e-2 * z + 2.418_131e-2) * z + 4.547_002_6e-2) * z + 7.495_300_3e-2) * z
        + 1.666_675_2e-1;
    let r = s + s * z * poly;
    if upper {
        std::f32::consts::FRAC_PI_2 - 2.0 * r
    } else {
        r
    }
}

/// Whether a triangle whose edge cross product has squared length `cross2` has a
/// positive, finite area. |cross|^2 is 0 or infinite exactly where |cross| is (glam's
/// length is the square root of it). The one test of both [`drop_degenerate`] and the
/// vertex normals' pass, so that a mesh the latter finds valid has nothing to drop.
fn has_area(cross2: f32) -> bool {
    cross2 > 0.0 && cross2.is_finite()
}

/// Drops triangles of zero area (repeated or collinear vertices) and normals that are
/// zero or not finite (then the mesh keeps no normals at all). Returns how many
/// triangles were dropped.
pub fn drop_degenerate(mesh: &mut Mesh) -> usize {
    if mesh
        .normals
        .par_iter()
        .any(|n| !n.is_finite() || n.length_squared() == 0.0)
    {
        mesh.normals.clear();
    }
    let positions = &mesh.positions;
    let degenerate = |&[a, b, c]: &[u32; 3]| {
        let (p0, p1, p2) = (
            positions[a as usize],
            positions[b as usize],
            positions[c as usize],
        );
        !has_area((p1 - p0).cross(p2 - p0).length_squared())
    };
    // Looked for in parallel (a large mesh rarely has any), removed in one pass.
    if !mesh
        .indices
        .par_chunks(1 << 14)
        .any(|block| block.iter().any(degenerate))
    {
        return 0;
    }
    let before = mesh.indices.len();
    // Face attributes lose the same triangles.
    if mesh.attributes.iter().any(|a| a.is_face()) {
        let keep: Vec<bool> = mesh.indices.iter().map(|t| !degenerate(t)).collect();
        for a in mesh.attributes.iter_mut().filter(|a| a.is_face()) {
            let d = a.dim as usize;
            a.values = a
                .values
                .chunks_exact(d)
                .zip(&keep)
                .filter(|(_, &k)| k)
                .flat_map(|(c, _)| c.iter().copied())
                .collect();
        }
    }
    mesh.indices.retain(|t| !degenerate(t));
    before - mesh.indices.len()
}

impl Mesh {
    /// Area of each triangle, in index order.
    pub fn triangle_areas(&self) -> impl Iterator<Item = f32> + '_ {
        self.indices.iter().map(|&[a, b, c]| {
            let p0 = self.positions[a as usize];
            0.5 * (self.positions[b as usize] - p0)
                .cross(self.positions[c as usize] - p0)
                .length()
        })
    }

    /// Total surface area (sum of triangle areas).
    pub fn area(&self) -> f32 {
        self.triangle_areas().sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geometric_normal(m: &Mesh, t: usize) -> Vec3 {
        let [a, b, c] = m.indices[t];
        let p = &m.positions;
        (p[b as usize] - p[a as usize])
            .cross(p[c as usize] - p[a as usize])
            .normalize()
    }

    #[test]
    fn rectangle_geometry() {
        let m = rectangle();
        assert_eq!(m.area(), 4.0);
        for t in 0..2 {
            assert_eq!(geometric_normal(&m, t), Vec3::Z);
        }
        // uv (0, 0) at (-1, -1), u along +x, v along +y.
        for (p, uv) in m.positions.iter().zip(&m.uvs) {
            assert_eq!(Vec2::new(p.x, p.y), *uv * 2.0 - Vec2::ONE);
        }
    }

    #[test]
    fn cube_is_closed_outward_and_flat() {
        let m = cube();
        assert_eq!(m.positions.len(), 24);
        assert_eq!(m.indices.len(), 12);
        assert!((m.area() - 24.0).abs() < 1e-5);
        for t in 0..12 {
            let g = geometric_normal(&m, t);
            let [a, b, c] = m.indices[t];
            for i in [a, b, c] {
                assert!((m.normals[i as usize] - g).length() < 1e-6);
            }
            // Outward: the face centre lies along the normal.
            let centre = (m.positions[a as usize] + m.positions[c as usize]) * 0.5;
            assert!(centre.dot(g) > 0.9);
        }
    }

    #[test]
    fn vertex_normals_weigh_faces_by_angle() {
        // A corner of the cube made of three quads: the normal is the diagonal.
        let mut m = Mesh {
            positions: vec![
                Vec3::ZERO,
                Vec3::X,
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::Y,
                Vec3::new(0.0, 1.0, 1.0),
                Vec3::Z,
                Vec3::new(1.0, 0.0, 1.0),
            ],
            // -z face (two triangles, angles 45 + 45 at the corner), -x and -y faces.
            indices: vec![
                [0, 2, 1],
                [0, 3, 2],
                [0, 4, 3],
                [0, 5, 4],
                [0, 1, 6],
                [0, 6, 5],
            ],
            ..Mesh::default()
        };
        compute_vertex_normals(&mut m);
        let d = -Vec3::ONE.normalize();
        assert!((m.normals[0] - d).length() < 1e-6, "{}", m.normals[0]);
        // Vertex 1 has a right angle in one triangle of the -z and of the -y face.
        assert!((m.normals[1] - Vec3::new(0.0, -0.70710677, -0.70710677)).length() < 1e-6);
    }

    /// The corner angles' asin is within 2 ulp of asin computed in f64 over [0, 1]
    /// (every 64th float, about 16 million), and clamps above 1 as `min(1.0).asin()`.
    #[test]
    fn asin_unit_within_two_ulp() {
        let mut worst = 0u32;
        for bits in (0..=1.0f32.to_bits()).step_by(64) {
            let x = f32::from_bits(bits);
            let exact = (x as f64).asin() as f32;
            let ulps = asin_unit(x).to_bits().abs_diff(exact.to_bits());
            worst = worst.max(ulps);
        }
        assert!(worst <= 2, "asin_unit is {worst} ulp off");
        assert_eq!(asin_unit(1.0), std::f32::consts::FRAC_PI_2);
        assert_eq!(asin_unit(1.5), asin_unit(1.0));
        assert_eq!(asin_unit(0.0), 0.0);
    }

    /// Vertex normals computed over any number of vertex ranges are the same bits.
    #[test]
    fn vertex_normals_alike_in_any_ranges() {
        let n = 30u32;
        let mut m = Mesh::default();
        for i in 0..n * n {
            let (x, y) = ((i % n) as f32, (i / n) as f32);
            m.positions
                .push(Vec3::new(x, y, (0.7 * x).sin() * (0.3 * y).cos()));
        }
        // Triangles in a scrambled order, some spanning far-apart vertices.
        for k in 0..(n - 1) * (n - 1) {
            let v = (k * 37) % ((n - 1) * (n - 1));
            let v = v / (n - 1) * n + v % (n - 1);
            m.indices.push([v, v + 1, v + n + 1]);
            m.indices.push([v, v + n + 1, (v * 7 + 3) % (n * n)]);
        }
        let valid = vertex_normals_in_ranges(&mut m, 1);
        let want = m.normals.clone();
        for ranges in [2, 3, 7, 5000] {
            assert_eq!(vertex_normals_in_ranges(&mut m, ranges), valid);
            assert_eq!(m.normals, want, "{ranges} ranges");
        }
        // The returned flag says whether drop_degenerate has work, in any ranges: here
        // a triangle with a repeated corner, far from the first block.
        assert_eq!(valid, drop_degenerate(&mut m.clone()) == 0);
        m.indices.push([n * n - 1, 5, n * n - 1]);
        for ranges in [1, 2, 3, 7, 5000] {
            assert!(!vertex_normals_in_ranges(&mut m, ranges), "{ranges} ranges");
        }
        assert!(drop_degenerate(&mut m) >= 1);
        assert!(vertex_normals_in_ranges(&mut m, 3));
    }

    #[test]
    fn transform_uses_inverse_transpose() {
        let mut m = rectangle();
        // A shear: normals must follow the inverse transpose, not the matrix.
        let shear = Mat4::from_cols_array(&[
            1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ]);
        let rot = Mat4::from_rotation_x(0.5) * shear;
        transform(&mut m, rot);
        let g = geometric_normal(&m, 0);
        assert!(
            (m.normals[0] - g).length() < 1e-5,
            "{} vs {g}",
            m.normals[0]
        );
    }

    #[test]
    fn degenerate_triangles_are_dropped() {
        let mut m = rectangle();
        m.indices.push([0, 0, 1]);
        m.positions.push(Vec3::new(3.0, -1.0, 0.0));
        m.normals.push(Vec3::Z);
        m.uvs.push(Vec2::ZERO);
        m.indices.push([0, 1, 4]); // collinear
        assert_eq!(drop_degenerate(&mut m), 2);
        assert_eq!(m.indices.len(), 2);
    }
}
