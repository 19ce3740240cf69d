//! `bsplinecurve`: hair and fur as smooth tubes, as Mitsuba 3.9 makes them
//! (src/shapes/bsplinecurve.cpp, traced by Embree's round B-spline curves): each four
//! consecutive control points of a curve make a segment, the uniform cubic B-spline of
//! their centres and radii, and the tube is swept by the circle of that radius normal
//! to the curve (no end caps: a curve of n points has n - 3 segments and starts and
//! ends open, a little inside its first and last points). Rays are met from outside
//! only: Mitsuba and Embree cull the tube's back faces.
//!
//! The file is a `linearcurve`'s: one control point a line, `x y z radius`, an empty
//! line between curves; each curve needs four control points or more. `to_world` moves
//! the control points and leaves the radii as they are (Mitsuba's rule).
//!
//! At a hit, as Mitsuba 3.9.1 reports it (measured against it, tests/bspline_hits_vs_mitsuba.rs):
//! the normal is the surface's own, (|c'|² - q.c'') q - r r' c' normalized (q from the
//! circle's centre c to the hit, ' the derivatives along the segment: the
//! curvature-corrected normal), geometric and shading alike; uv = (the angle around the
//! curve / 2π, from Mitsuba's frame about the tangent with +z as its guide, (the
//! segment's parameter + the segment's number) / the shape's segment count); the
//! shading tangent is the direction around the curve.
//!
//! On the GPU a segment's primitive holds its box and the offset of its four control
//! points in the grid buffer, where each shape's control points follow the sdfgrids
//! (x y z radius each; [`place`], [`pack`]): the side table that records too small for
//! 16 numbers use.
//!
//! ```xml
//! <shape type="bsplinecurve"><string name="filename" value="hair.txt"/></shape>
//! ```

use std::path::Path;

use glam::{Vec3, Vec4};

use super::{Geometry, Mesh, TO_WORLD};
use crate::scene::builder;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::{Dialect, Element};
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Shape,
    Dialect::Mitsuba,
    "bsplinecurve",
    "Smooth curves (hair, fur): cubic B-spline tubes swept by a circle of varying radius, from a text file of `x y z radius` lines, an empty line between curves, four or more points a curve; no end caps; no area emitters or media on them yet.",
    &[
        Param::new(
            "filename",
            "string",
            "",
            "the control point file (required)",
        ),
        Param::new(
            "to_world",
            TO_WORLD.ty,
            TO_WORLD.default,
            "object to world, applied to the control points (the radii stay as written)",
        ),
    ],
);

/// A Mitsuba `bsplinecurve`: the curves in object space and their `to_world`.
pub fn mitsuba(el: &Element, props: &Properties) -> Result<Geometry, Error> {
    if props.has("flip_normals") {
        return Err(props.error(
            "flip_normals",
            "a bsplinecurve has no 'flip_normals' (Mitsuba leaves it unreferenced)",
        ));
    }
    let path = builder::mesh_path(el, props, "filename")?;
    let to_world = props.transform("to_world")?;
    let bytes = std::fs::read(&path).map_err(|e| Error::file(&path, format!("{e}")))?;
    Ok(Geometry::Curves {
        mesh: parse(&path, &bytes)?,
        to_world,
    })
}

/// The B-spline curves of a control point file (its text `bytes`; `path` for
/// messages): segments `[first control point, 3, 0]` until [`place`]d.
pub fn parse(path: &Path, bytes: &[u8]) -> Result<Mesh, Error> {
    super::linearcurve::parse_curves(path, bytes, 3)
}

/// Gives each B-spline shape of `meshes` its place in the grid buffer, from word
/// `base` on (after the sdfgrids): every segment's third entry becomes the offset of
/// its first control point. Errs where the buffer would grow past 2^31 words.
pub fn place(meshes: &mut [Mesh], base: usize) -> Result<(), String> {
    let mut at = base as u64;
    for m in meshes.iter_mut().filter(|m| m.is_bspline()) {
        let end = at + 4 * m.positions.len() as u64;
        if end >= 1 << 31 {
            return Err(format!(
                "the scene's curves are too large: '{}' ends past 2^31 words of the grid buffer",
                m.name
            ));
        }
        for s in &mut m.indices {
            s[2] = (at + 4 * s[0] as u64) as u32;
        }
        at = end;
    }
    Ok(())
}

/// Appends the control points of `meshes`' B-spline shapes to the grid buffer `words`
/// where [`place`] put them (which must be `words.len()` on).
pub fn pack(meshes: &[Mesh], words: &mut Vec<f32>) {
    for m in meshes.iter().filter(|m| m.is_bspline()) {
        assert_eq!(
            words.len() as u64,
            m.indices[0][2] as u64 - 4 * m.indices[0][0] as u64,
            "B-spline control points follow the sdfgrids in the grid buffer"
        );
        for (p, r) in m.positions.iter().zip(&m.radii) {
            words.extend_from_slice(&[p.x, p.y, p.z, *r]);
        }
    }
}

/// The control points of segment `k` of the B-spline shape `m` (x y z radius).
pub fn segment_points(m: &Mesh, k: usize) -> [Vec4; 4] {
    let i = m.indices[k][0] as usize;
    std::array::from_fn(|j| m.positions[i + j].extend(m.radii[i + j]))
}

/// The box of segment `k` of `m`: the control points' (which hold the curve), grown
/// by their largest radius (which bounds the radius along it).
pub fn segment_box(m: &Mesh, k: usize) -> (Vec3, Vec3) {
    let cp = segment_points(m, k);
    let r = cp.iter().fold(0.0f32, |a, p| a.max(p.w));
    let lo = cp.iter().fold(Vec3::INFINITY, |a, p| a.min(p.truncate()));
    let hi = cp
        .iter()
        .fold(Vec3::NEG_INFINITY, |a, p| a.max(p.truncate()));
    (lo - Vec3::splat(r), hi + Vec3::splat(r))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Mesh, Error> {
        parse(Path::new("hair.txt"), text.as_bytes())
    }

    #[test]
    fn segments_of_four_points() {
        let m = read(
            "0 0 0 1\n1 0 0 1\n2 0 0 1\n3 0 0 1\n4 0 0 1\n\n0 1 0 1\n1 1 0 1\n2 1 0 1\n3 1 0 1\n",
        )
        .unwrap();
        assert_eq!(m.indices, [[0, 3, 0], [1, 3, 0], [5, 3, 0]]);
        assert!(m.is_bspline());
        let mut meshes = [m];
        place(&mut meshes, 100).unwrap();
        let offsets: Vec<u32> = meshes[0].indices.iter().map(|s| s[2]).collect();
        assert_eq!(offsets, [100, 104, 120]);
        let mut words = vec![0.0; 100];
        pack(&meshes, &mut words);
        assert_eq!(words.len(), 100 + 4 * 9);
        assert_eq!(&words[120..124], &[0.0, 1.0, 0.0, 1.0]);
        let (lo, hi) = segment_box(&meshes[0], 1);
        assert_eq!(
            (lo, hi),
            (Vec3::new(0.0, -1.0, -1.0), Vec3::new(5.0, 1.0, 1.0))
        );
    }

    #[test]
    fn malformed_files_name_the_line() {
        let cases = [
            (
                "0 0 0 1\n1 1 1 1\n2 2 2 1\n",
                1,
                "at least four control points",
            ),
            (
                "0 0 0 1\n1 1 1 1\n2 2 2 1\n3 3 3 1\n\n4 4 4 1\n5 5 5 1\n6 6 6 1\n",
                6,
                "at least four control points",
            ),
            ("0 0 0 1\n1 NaN 1 1\n", 2, "not finite"),
            ("0 0 0 1\n1 1 1 nan\n", 2, "radius must be finite"),
            ("0 0 0 1\n1 1 1\n", 2, "'x y z radius'"),
        ];
        super::super::linearcurve::tests::assert_errors_at_lines(read, &cases);
    }

    fn scene(shape_body: &str, curves: &str) -> Result<crate::scene::Scene, Error> {
        let xml = format!(
            "<scene version=\"3.0.0\">\n<shape type=\"bsplinecurve\">\n<string name=\"filename\" value=\"c.txt\"/>\n{shape_body}</shape>\n<sensor type=\"perspective\"/>\n</scene>\n"
        );
        crate::scene::testutil::load(&[("s.xml", &xml), ("c.txt", curves)], &[])
    }

    #[test]
    fn to_world_moves_points_not_radii() {
        let s = scene(
            "<transform name=\"to_world\"><scale value=\"2\"/><translate x=\"1\"/></transform>\n",
            "0 0 0 0.1\n1 0 0 0.2\n2 0 0 0.2\n3 0 0 0.3\n",
        )
        .unwrap();
        let m = &s.meshes[0];
        assert_eq!(m.positions[1], Vec3::new(3.0, 0.0, 0.0));
        assert_eq!(m.radii, [0.1, 0.2, 0.2, 0.3]);
        assert_eq!(m.indices, [[0, 3, 0]]);
        assert!(s.features().contains(&"bspline curves"));
        assert!(!s.features().contains(&"linear curves"));
        assert!(!s.features().contains(&"triangles"));
    }

    #[test]
    fn scene_errors_name_file_and_line() {
        let e =
            crate::scene::testutil::error_at(scene("", "0 0 0 1\n1 1 1 1\n2 2 2 1\n"), "c.txt", 1);
        assert!(e.contains("at least four control points"), "{e}");
        let e = crate::scene::testutil::error_at(
            scene(
                "<boolean name=\"flip_normals\" value=\"true\"/>\n",
                "0 0 0 1\n1 1 1 1\n2 2 2 1\n3 3 3 1\n",
            ),
            "s.xml",
            4,
        );
        assert!(e.contains("no 'flip_normals'"), "{e}");
        let e = crate::scene::testutil::error_at(
            crate::scene::testutil::load(
                &[(
                    "s.xml",
                    "<scene version=\"3.0.0\">\n<shape type=\"bsplinecurve\">\n<string name=\"filename\" value=\"none.txt\"/>\n</shape>\n</scene>\n",
                )],
                &[],
            ),
            "s.xml",
            3,
        );
        assert!(e.contains("not found"), "{e}");
    }
}
