//! `ellipsoidsmesh`: the ellipsoids of an `ellipsoids` file ([`super::ellipsoids`]:
//! the same PLY layout and parameters) as the triangle mesh Mitsuba 3.9 makes of them
//! (src/shapes/ellipsoidsmesh.cpp): every ellipsoid a copy of a shell polyhedron, its
//! vertices first scaled so that every vertex and every triangle's centroid lies at
//! least 1 from the origin, then stretched by the semi-axes, rotated and moved to the
//! centre. Flat shaded (the shell has no vertex normals); uv as any mesh without uvs.
//!
//! Shells: `ico_sphere` (the default, 20 triangles) and `box` (12 triangles; Mitsuba's
//! cube table, whose scaling leaves its faces inside the unit sphere). Mitsuba's
//! `uv_sphere` and a nested shell mesh are not supported yet.
//!
//! One difference: Mitsuba culls the shells' back faces (in 3.9.1's scalar_rgb a ray
//! from an ellipsoid's centre misses its shell); here the shells are ordinary
//! two-sided triangles. Rays from outside meet the front faces first either way:
//! tests/ellipsoids_hits_vs_mitsuba.rs compares points, normals and uv with Mitsuba's
//! on rays that start outside every shell (tools/mitsuba_ellipsoidsmesh.py).
//!
//! ```xml
//! <shape type="ellipsoidsmesh"><string name="filename" value="primitives.ply"/></shape>
//! ```

use glam::{Mat3, Vec3};

use super::{ellipsoids, Geometry, Mesh};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::{Dialect, Element};
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Shape,
    Dialect::Mitsuba,
    "ellipsoidsmesh",
    "The ellipsoids of an `ellipsoids` PLY file as Mitsuba's triangle shells (an icosahedron or a box per ellipsoid, flat shaded). Only the `filename` form; shells `ico_sphere` and `box` (not `uv_sphere` or a nested mesh yet); back faces are not culled as Mitsuba culls them.",
    &[
        ellipsoids::FILENAME,
        ellipsoids::EXTENT,
        ellipsoids::SCALE_FACTOR,
        Param::new(
            "shell",
            "string",
            "ico_sphere",
            "the polyhedron each ellipsoid becomes: `ico_sphere` (or `default`) or `box`",
        ),
        ellipsoids::ELLIPSOIDS_TO_WORLD,
    ],
);

/// Mitsuba's icosahedron shell (ellipsoidsmesh.cpp, `ico_sphere_20`): vertices and
/// triangles in its order, so triangle k of ellipsoid i is Mitsuba's 20 i + k.
#[rustfmt::skip]
const ICO_VERTICES: [[f32; 3]; 12] = [
    [0.0, -1.0, 0.0], [0.7236, -0.447215, 0.52572], [-0.276385, -0.447215, 0.85064],
    [-0.894425, -0.447215, 0.0], [-0.276385, -0.447215, -0.85064], [0.7236, -0.447215, -0.52572],
    [0.276385, 0.447215, 0.85064], [-0.7236, 0.447215, 0.52572], [-0.7236, 0.447215, -0.52572],
    [0.276385, 0.447215, -0.85064], [0.894425, 0.447215, 0.0], [0.0, 1.0, 0.0],
];
#[rustfmt::skip]
const ICO_FACES: [[u32; 3]; 20] = [
    [0, 1, 2], [1, 0, 5], [0, 2, 3], [0, 3, 4], [0, 4, 5],
    [1, 5, 10], [2, 1, 6], [3, 2, 7], [4, 3, 8], [5, 4, 9],
    [1, 10, 6], [2, 6, 7], [3, 7, 8], [4, 8, 9], [5, 9, 10],
    [6, 10, 11], [7, 6, 11], [8, 7, 11], [9, 8, 11], [10, 9, 11],
];

/// The shell polyhedron named `shell`, scaled as Mitsuba scales it: divided by the
/// least distance from the origin of its vertices and triangle centroids.
pub fn shell(name: &str) -> Option<(Vec<Vec3>, Vec<[u32; 3]>)> {
    let (vertices, faces) = match name {
        "default" | "ico_sphere" => (
            ICO_VERTICES.iter().map(|&v| Vec3::from(v)).collect(),
            ICO_FACES.to_vec(),
        ),
        "box" => {
            // Mitsuba's box table is its cube's.
            let cube = crate::scene::mesh::cube();
            (cube.positions, cube.indices)
        }
        _ => return None,
    };
    let mut least = f32::MAX;
    for f in &faces {
        let [a, b, c] = f.map(|i| vertices[i as usize]);
        least = least
            .min(a.length())
            .min(b.length())
            .min(c.length())
            .min(((a + b + c) / 3.0).length());
    }
    Some((vertices.iter().map(|v| *v / least).collect(), faces))
}

/// A Mitsuba `ellipsoidsmesh`: the shells in world space.
pub fn mitsuba(el: &Element, props: &Properties) -> Result<Geometry, Error> {
    let name = props.string("shell", "ico_sphere")?;
    let (vertices, faces) = match shell(&name) {
        Some(s) => s,
        None if name == "uv_sphere" => {
            return Err(props.error(
                "shell",
                "ellipsoidsmesh's 'uv_sphere' shell is not supported yet (use 'ico_sphere' or 'box')",
            ))
        }
        None => {
            return Err(props.error(
                "shell",
                format!("unknown shell '{name}': Mitsuba's are 'default', 'ico_sphere', 'box' and 'uv_sphere'"),
            ))
        }
    };
    let (path, ellipsoids) = ellipsoids::world(el, props)?;
    let mut mesh = Mesh {
        name: path.display().to_string(),
        ..Mesh::default()
    };
    for e in &ellipsoids {
        let base = mesh.positions.len() as u32;
        let m = Mat3::from_quat(e.rotation) * Mat3::from_diagonal(e.scale);
        mesh.positions
            .extend(vertices.iter().map(|&v| e.center + m * v));
        mesh.indices
            .extend(faces.iter().map(|f| f.map(|i| base + i)));
    }
    if !mesh.positions.iter().all(|p| p.is_finite()) {
        return Err(Error::file(
            &path,
            "the ellipsoids' shells are not finite in world space",
        ));
    }
    Ok(Geometry::Mesh {
        mesh,
        to_world: glam::Mat4::IDENTITY,
        // Mitsuba computes no vertex normals for the shells (it skips the mesh's
        // initialization): flat shading.
        face_normals: true,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shells_enclose_the_unit_sphere_as_mitsuba_scales_them() {
        let (v, f) = shell("ico_sphere").unwrap();
        assert_eq!((v.len(), f.len()), (12, 20));
        // The icosahedron's centroids are the nearest points: at distance 1.
        let least = f
            .iter()
            .map(|t| (t.iter().map(|&i| v[i as usize]).sum::<Vec3>() / 3.0).length())
            .fold(f32::MAX, f32::min);
        assert!((least - 1.0).abs() < 1e-6, "{least}");
        let (v, f) = shell("box").unwrap();
        assert_eq!((v.len(), f.len()), (24, 12));
        // The box's corners are at sqrt(3) / |(1/3, 1, 1/3)|.
        assert!((v[0].length() - 3f32.sqrt() / (11f32 / 9.0).sqrt()).abs() < 1e-5);
        assert!(shell("uv_sphere").is_none());
    }
}
