//! `linearcurve`: hair and fur as Mitsuba 3.9 makes them (src/shapes/linearcurve.cpp,
//! traced by Embree's round linear curves): each segment between two control points is
//! the union of the spheres whose centre and radius run linearly from one control
//! point's to the next (a cone touching both end spheres, capped by them), and the
//! segments of a curve join at those spheres. Rays are met from outside only: Mitsuba
//! and Embree cull the curve's back faces, so a ray leaving the inside passes out.
//!
//! The file holds one control point a line, `x y z radius` (numbers after the fourth
//! ignored, as Mitsuba's reader does); an empty line ends a curve, and each curve needs
//! two control points or more. `to_world` moves the control points and leaves the radii
//! as they are (Mitsuba's rule).
//!
//! At a hit, as Mitsuba reports it: the normal points from the centre of the touching
//! sphere to the hit (geometric and shading normal alike); uv = (the angle around the
//! segment / 2π, measured from Mitsuba's frame about the axis with +z as its guide,
//! (the segment's own parameter + the segment's number) / the shape's segment count);
//! the shading frame is Mitsuba 3.9's `coordinate_system` of the normal.
//!
//! ```xml
//! <shape type="linearcurve"><string name="filename" value="hair.txt"/></shape>
//! ```

use std::path::Path;

use glam::Vec3;

use super::{Geometry, Mesh, TO_WORLD};
use crate::scene::builder;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::{Dialect, Element};
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Shape,
    Dialect::Mitsuba,
    "linearcurve",
    "Curves of round cone segments joined by spheres (hair, fur), from a text file of `x y z radius` lines, an empty line between curves; no area emitters or media on them yet.",
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

/// A Mitsuba `linearcurve`: the curves in object space and their `to_world`.
pub fn mitsuba(el: &Element, props: &Properties) -> Result<Geometry, Error> {
    if props.has("flip_normals") {
        return Err(props.error(
            "flip_normals",
            "a linearcurve has no 'flip_normals' (Mitsuba leaves it unreferenced)",
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

/// The curves of a control point file (its text `bytes`; `path` for messages).
pub fn parse(path: &Path, bytes: &[u8]) -> Result<Mesh, Error> {
    parse_curves(path, bytes, 1)
}

/// The curves of a control point file of polynomial `degree` (1: `linearcurve`, a
/// segment between each two neighbours; 3: `bsplinecurve`, a segment per four, its
/// entries `[first control point, 3, 0]`).
pub fn parse_curves(path: &Path, bytes: &[u8], degree: u32) -> Result<Mesh, Error> {
    let text = std::str::from_utf8(bytes)
        .map_err(|e| Error::file(path, format!("a curve file must be text: {e}")))?;
    let mut positions = Vec::new();
    let mut radii = Vec::new();
    let mut indices = Vec::new();
    // The current curve's first control point and the line it is on.
    let mut first: Option<(usize, u32)> = None;
    let mut finish = |first: &mut Option<(usize, u32)>, end: usize| -> Result<(), Error> {
        if let Some((start, line)) = first.take() {
            let needs = degree as usize + 1;
            if end - start < needs {
                return Err(Error::at(
                    path,
                    line,
                    format!(
                        "a curve needs at least {} control points (one line each, an empty line between curves)",
                        ["two", "four"][(degree == 3) as usize]
                    ),
                ));
            }
            let marker = if degree == 3 { 3 } else { 0 };
            indices.extend((start..=end - needs).map(|i| [i as u32, marker, 0]));
        }
        Ok(())
    };
    for (k, line) in text.split('\n').enumerate() {
        let number = k as u32 + 1;
        let line = line.trim_matches([' ', '\t', '\r']);
        if line.is_empty() {
            finish(&mut first, positions.len())?;
            continue;
        }
        let values: Vec<f32> = line
            .split_whitespace()
            .take(4)
            .map_while(|w| w.parse::<f32>().ok())
            .collect();
        if values.len() < 4 {
            return Err(Error::at(
                path,
                number,
                format!("could not read a control point from '{line}': expected 'x y z radius'"),
            ));
        }
        let p = Vec3::new(values[0], values[1], values[2]);
        if !p.is_finite() {
            return Err(Error::at(
                path,
                number,
                format!("control point {p} is not finite"),
            ));
        }
        let r = values[3];
        if !(r >= 0.0 && r.is_finite()) {
            return Err(Error::at(
                path,
                number,
                format!("a control point's radius must be finite and >= 0, found {r}"),
            ));
        }
        if first.is_none() {
            first = Some((positions.len(), number));
        }
        positions.push(p);
        radii.push(r);
    }
    finish(&mut first, positions.len())?;
    if positions.is_empty() {
        return Err(Error::file(path, "the curve file holds no control points"));
    }
    if indices.len() > u32::MAX as usize / 2 {
        return Err(Error::file(path, "too many curve segments"));
    }
    Ok(Mesh {
        name: path.display().to_string(),
        positions,
        radii,
        indices,
        ..Mesh::default()
    })
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    fn read(text: &str) -> Result<Mesh, Error> {
        parse(Path::new("hair.txt"), text.as_bytes())
    }

    /// Each case's text, read as `hair.txt` by `read`, fails at its line with a message
    /// containing its words; a file of blank lines is an error of the whole file (the
    /// B-spline parser's test asks the same).
    pub(in crate::scene::shape) fn assert_errors_at_lines(
        read: fn(&str) -> Result<Mesh, Error>,
        cases: &[(&str, u32, &str)],
    ) {
        for &(text, line, what) in cases {
            match read(text) {
                Err(Error::At {
                    line: l,
                    message,
                    file,
                }) => {
                    assert_eq!(
                        (l, file.as_path()),
                        (line, Path::new("hair.txt")),
                        "{text:?}"
                    );
                    assert!(message.contains(what), "{text:?}: {message}");
                }
                other => panic!("{text:?}: {other:?}"),
            }
        }
        assert!(matches!(read("\n\n"), Err(Error::File { .. })));
    }

    #[test]
    fn curves_split_at_empty_lines() {
        let m = read("-1 0.1 0.1 0.5\n 1 1.4 1.2 0.5\n\n \t\r\n-1 5 2.2 1\n-2.3 4 2.3 2 extra\n4 1 2.2 5\r\n4 0 2.3 6\n")
            .unwrap();
        assert_eq!(m.positions.len(), 6);
        assert_eq!(m.radii, [0.5, 0.5, 1.0, 2.0, 5.0, 6.0]);
        assert_eq!(m.indices, [[0, 0, 0], [2, 0, 0], [3, 0, 0], [4, 0, 0]]);
        assert!(m.is_curves());
    }

    #[test]
    fn malformed_files_name_the_line() {
        let cases = [
            (
                "0 0 0 1\n1 2 3\n",
                2,
                "could not read a control point from '1 2 3'",
            ),
            ("0 0 0 1\n1 2 x 1\n", 2, "'x y z radius'"),
            ("# hair\n0 0 0 1\n1 1 1 1\n", 1, "could not read"),
            (
                "0 0 0 1\n1 1 1 1\n\n2 2 2 1\n",
                4,
                "at least two control points",
            ),
            (
                "0 0 0 1\n1 1 1 -1\n",
                2,
                "radius must be finite and >= 0, found -1",
            ),
            ("0 0 0 NaN\n1 1 1 1\n", 1, "radius must be finite"),
            ("0 inf 0 1\n1 1 1 1\n", 1, "not finite"),
        ];
        assert_errors_at_lines(read, &cases);
    }

    fn scene(shape_body: &str, curves: &str) -> Result<crate::scene::Scene, Error> {
        let xml = format!(
            "<scene version=\"3.0.0\">\n<shape type=\"linearcurve\">\n<string name=\"filename\" value=\"c.txt\"/>\n{shape_body}</shape>\n<sensor type=\"perspective\"/>\n</scene>\n"
        );
        crate::scene::testutil::load(&[("s.xml", &xml), ("c.txt", curves)], &[])
    }

    #[test]
    fn to_world_moves_points_not_radii() {
        let s = scene(
            "<transform name=\"to_world\"><scale value=\"2\"/><translate x=\"1\"/></transform>\n",
            "0 0 0 0.1\n1 0 0 0.2\n",
        )
        .unwrap();
        let m = &s.meshes[0];
        assert_eq!(m.positions, [Vec3::X, Vec3::new(3.0, 0.0, 0.0)]);
        assert_eq!(m.radii, [0.1, 0.2]);
        assert!(s.features().contains(&"linear curves"));
        assert!(!s.features().contains(&"triangles"));
    }

    #[test]
    fn scene_errors_name_file_and_line() {
        let e = crate::scene::testutil::error_at(scene("", "0 0 0 1\n1 1 1\n"), "c.txt", 2);
        assert!(e.contains("expected 'x y z radius'"), "{e}");
        let e = crate::scene::testutil::error_at(
            scene(
                "<emitter type=\"area\"><rgb name=\"radiance\" value=\"1\"/></emitter>\n",
                "0 0 0 1\n1 1 1 1\n",
            ),
            "s.xml",
            2,
        );
        assert!(
            e.contains("area emitter on a linearcurve is not supported"),
            "{e}"
        );
        let e = crate::scene::testutil::error_at(
            scene(
                "<boolean name=\"flip_normals\" value=\"true\"/>\n",
                "0 0 0 1\n1 1 1 1\n",
            ),
            "s.xml",
            4,
        );
        assert!(e.contains("no 'flip_normals'"), "{e}");
        let e = crate::scene::testutil::error_at(
            crate::scene::testutil::load(
                &[(
                    "s.xml",
                    "<scene version=\"3.0.0\">\n<shape type=\"linearcurve\">\n<string name=\"filename\" value=\"none.txt\"/>\n</shape>\n</scene>\n",
                )],
                &[],
            ),
            "s.xml",
            3,
        );
        assert!(e.contains("not found"), "{e}");
    }
}
