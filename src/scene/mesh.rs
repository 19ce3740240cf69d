//! Building and preparing triangle meshes: Mitsuba's built-in `rectangle`, `cube` and
//! `disk`, and the steps every mesh goes through on its way to world space
//! (`to_world`, `flip_normals`, dropping degenerate triangles).

use glam::{Mat3, Mat4, Vec2, Vec3};
use rayon::prelude::*;

use super::Mesh;

/// Segments around the tessellated `disk` (Mitsuba's disk is analytic; ours is a
/// 256-gon, whose area is 0.99990 of the disk's).
pub const DISK_SEGMENTS: u32 = 256;

/// Mitsuba `rectangle`: [-1, 1]² in the z = 0 plane, normal +z, uv (0,0) at (-1,-1).
pub fn rectangle() -> Mesh {
    Mesh {
        name: "rectangle".into(),
        positions: vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ],
        normals: vec![Vec3::Z; 4],
        uvs: vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
        ],
        indices: vec![[0, 1, 2], [2, 3, 0]],
        ..Mesh::default()
    }
}

/// Mitsuba `cube`: [-1, 1]³, 24 vertices (4 per face) with flat outward normals and
/// per-face uvs over [0, 1]².
pub fn cube() -> Mesh {
    let mut m = Mesh {
        name: "cube".into(),
        ..Mesh::default()
    };
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let mut n = Vec3::ZERO;
            n[axis] = sign;
            // Two tangents with (t1 x t2) = n, so the winding faces outwards.
            let mut t1 = Vec3::ZERO;
            t1[(axis + 1) % 3] = 1.0;
            let t2 = n.cross(t1);
            let base = m.positions.len() as u32;
            for (u, v) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
                let p = n + t1 * (2.0 * u - 1.0) + t2 * (2.0 * v - 1.0);
                m.positions.push(p);
                m.normals.push(n);
                m.uvs.push(Vec2::new(u, v));
            }
            m.indices.push([base, base + 1, base + 2]);
            m.indices.push([base + 2, base + 3, base]);
        }
    }
    m
}

/// Mitsuba `disk`: the unit disk in z = 0 with normal +z, tessellated into
/// [`DISK_SEGMENTS`] triangles around a centre vertex. uv = (r, φ / 2π) as in
/// Mitsuba; the seam vertex is duplicated so v runs from 0 to 1.
pub fn disk(segments: u32) -> Mesh {
    let mut m = Mesh {
        name: "disk".into(),
        ..Mesh::default()
    };
    m.positions.push(Vec3::ZERO);
    m.normals.push(Vec3::Z);
    m.uvs.push(Vec2::ZERO);
    for i in 0..=segments {
        let t = i as f32 / segments as f32;
        let phi = t * std::f32::consts::TAU;
        m.positions.push(Vec3::new(phi.cos(), phi.sin(), 0.0));
        m.normals.push(Vec3::Z);
        m.uvs.push(Vec2::new(1.0, t));
    }
    for i in 0..segments {
        m.indices.push([0, i + 1, i + 2]);
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

/// Mitsuba's `flip_normals`: reverses every triangle's winding (so the geometric
/// normal cross(p1 - p0, p2 - p0) flips) and negates the vertex normals.
pub fn flip(mesh: &mut Mesh) {
    for t in &mut mesh.indices {
        t.swap(1, 2);
    }
    for n in &mut mesh.normals {
        *n = -*n;
    }
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
        // |cross|^2 is 0 or infinite exactly where |cross| is (glam's length is
        // the square root of it).
        let area2 = (p1 - p0).cross(p2 - p0).length_squared();
        !(area2 > 0.0 && area2.is_finite())
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
    fn disk_geometry() {
        let m = disk(DISK_SEGMENTS);
        assert_eq!(m.indices.len(), DISK_SEGMENTS as usize);
        let n = DISK_SEGMENTS as f32;
        let expected = 0.5 * n * (std::f32::consts::TAU / n).sin();
        assert!((m.area() - expected).abs() < 1e-4);
        assert!((m.area() - std::f32::consts::PI).abs() < 1e-3);
        assert_eq!(geometric_normal(&m, 7), Vec3::Z);
    }

    #[test]
    fn transform_uses_inverse_transpose_and_flip_reverses() {
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
        flip(&mut m);
        assert!((geometric_normal(&m, 0) + g).length() < 1e-5);
        assert!((m.normals[0] + g).length() < 1e-5);
    }

    #[test]
    fn degenerate_triangles_are_dropped() {
        let mut m = rectangle();
        m.indices.push([0, 0, 1]);
        m.positions.push(Vec3::new(2.0, -1.0, 0.0));
        m.normals.push(Vec3::Z);
        m.uvs.push(Vec2::ZERO);
        m.indices.push([0, 1, 4]); // collinear
        assert_eq!(drop_degenerate(&mut m), 2);
        assert_eq!(m.indices.len(), 2);
    }
}
