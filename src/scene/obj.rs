//! Wavefront OBJ meshes (through `tobj`, after our own line-by-line check).
//!
//! tobj does the loading (polygons fan-triangulated, one index shared by position,
//! normal and uv). Before it runs we scan the text ourselves so that a bad number or an
//! out-of-range index is reported with its line: non-finite `v`/`vn`/`vt` values,
//! index 0, relative (negative) indices reaching before the first vertex, positive
//! indices past the last one, and faces with fewer than three vertices. Materials
//! (`mtllib`) are not read.

use std::path::Path;

use glam::{Vec2, Vec3};

use super::{Error, Mesh};

/// Loads an OBJ file. `flip_tex_coords` replaces v by 1 - v (Mitsuba's default).
pub fn load(path: &Path, flip_tex_coords: bool) -> Result<Mesh, Error> {
    let bytes = std::fs::read(path).map_err(|e| Error::file(path, format!("cannot read: {e}")))?;
    let text = String::from_utf8(bytes).map_err(|e| {
        Error::file(
            path,
            format!(
                "not a text OBJ file (invalid UTF-8 at byte {})",
                e.utf8_error().valid_up_to()
            ),
        )
    })?;
    check(path, &text)?;

    #[allow(clippy::needless_update)] // tobj's optional features add fields
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let (models, _materials) = tobj::load_obj_buf(&mut text.as_bytes(), &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| Error::file(path, format!("malformed OBJ: {e}")))?;

    let mut mesh = Mesh {
        name: path.display().to_string(),
        ..Mesh::default()
    };
    let mut all_normals = true;
    let mut all_uvs = true;
    for model in &models {
        let m = &model.mesh;
        let n = m.positions.len() / 3;
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(
            m.positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2])),
        );
        if m.normals.len() == 3 * n {
            mesh.normals.extend(
                m.normals
                    .chunks_exact(3)
                    .map(|p| Vec3::new(p[0], p[1], p[2])),
            );
        } else {
            all_normals = false;
        }
        if m.texcoords.len() == 2 * n {
            mesh.uvs.extend(
                m.texcoords
                    .chunks_exact(2)
                    .map(|t| Vec2::new(t[0], if flip_tex_coords { 1.0 - t[1] } else { t[1] })),
            );
        } else {
            all_uvs = false;
        }
        for t in m.indices.chunks_exact(3) {
            if t.iter().any(|&i| i as usize >= n) {
                return Err(Error::file(
                    path,
                    format!("face index out of range in object '{}'", model.name),
                ));
            }
            mesh.indices.push([base + t[0], base + t[1], base + t[2]]);
        }
    }
    if !all_normals {
        mesh.normals.clear();
    }
    if !all_uvs {
        mesh.uvs.clear();
    }
    if mesh.positions.iter().any(|p| !p.is_finite()) {
        return Err(Error::file(path, "a vertex position is not finite"));
    }
    Ok(mesh)
}

/// Line-by-line validation; see the module comment.
fn check(path: &Path, text: &str) -> Result<(), Error> {
    let mut counts = [0i64; 3]; // v, vt, vn
    let mut pending: Vec<(u32, usize, i64)> = Vec::new(); // (line, kind, index) checked at the end
    const KIND: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    for (i, raw) in text.lines().enumerate() {
        let line = (i + 1) as u32;
        let content = raw.split('#').next().unwrap_or("");
        let mut words = content.split_whitespace();
        let Some(key) = words.next() else { continue };
        let (kind, min) = match key {
            "v" => (0, 3),
            "vt" => (1, 1),
            "vn" => (2, 3),
            "f" => {
                let verts: Vec<&str> = words.collect();
                if verts.len() < 3 {
                    return Err(Error::at(
                        path,
                        line,
                        format!("face with {} vertices (at least 3 needed)", verts.len()),
                    ));
                }
                for v in verts {
                    for (k, part) in v.split('/').enumerate().take(3) {
                        if part.is_empty() {
                            if k == 0 {
                                return Err(Error::at(
                                    path,
                                    line,
                                    format!("face vertex \"{v}\" has no position index"),
                                ));
                            }
                            continue;
                        }
                        let idx: i64 = part.parse().map_err(|_| {
                            Error::at(path, line, format!("could not parse face index \"{v}\""))
                        })?;
                        if idx == 0 {
                            return Err(Error::at(
                                path,
                                line,
                                format!("{} index 0 in \"{v}\" (OBJ indices start at 1)", KIND[k]),
                            ));
                        }
                        if idx < 0 && -idx > counts[k] {
                            return Err(Error::at(
                                path,
                                line,
                                format!(
                                    "relative {} index {idx} reaches before the first one ({} defined so far)",
                                    KIND[k], counts[k]
                                ),
                            ));
                        }
                        if idx > counts[k] {
                            pending.push((line, k, idx));
                        }
                    }
                }
                continue;
            }
            _ => continue,
        };
        let values: Vec<&str> = words.collect();
        if values.len() < min {
            return Err(Error::at(
                path,
                line,
                format!("'{key}' needs {min} numbers, found {}", values.len()),
            ));
        }
        for s in values.iter().take(if kind == 1 { 2 } else { 3 }) {
            match s.parse::<f32>() {
                Ok(v) if v.is_finite() => {}
                Ok(_) => {
                    return Err(Error::at(
                        path,
                        line,
                        format!("'{key}' has a value that is not finite: \"{s}\""),
                    ))
                }
                Err(_) => {
                    return Err(Error::at(
                        path,
                        line,
                        format!("could not parse \"{s}\" as a number in '{key}'"),
                    ))
                }
            }
        }
        counts[kind] += 1;
    }
    for (line, k, idx) in pending {
        if idx > counts[k] {
            return Err(Error::at(
                path,
                line,
                format!(
                    "{} index {idx} out of range (the file has {})",
                    KIND[k], counts[k]
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::testutil::temp_dir;

    fn obj(text: &str) -> Result<Mesh, Error> {
        let p = temp_dir("obj").join("m.obj");
        std::fs::write(&p, text).unwrap();
        load(&p, true)
    }

    fn err_line(r: Result<Mesh, Error>) -> (u32, String) {
        match r {
            Err(e @ Error::At { line, .. }) => (line, e.to_string()),
            Err(e) => panic!("no line: {e}"),
            Ok(_) => panic!("expected an error"),
        }
    }

    #[test]
    fn quads_relative_indices_and_groups() {
        let m = obj("# quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4 -3 -2 -1\no second\nv 5 5 5\nv 6 5 5\nv 5 6 5\nf 5 6 7\n").unwrap();
        assert_eq!(m.positions.len(), 7);
        assert_eq!(m.indices.len(), 3);
        assert!(m.normals.is_empty() && m.uvs.is_empty());
        assert!((m.area() - 1.5).abs() < 1e-6);
    }

    #[test]
    fn bad_numbers_and_indices_name_the_line() {
        let cases = [
            ("v 0 0 0\nv 1 nan 0\n", 2, "not finite"),
            ("v 0 0 0\nv 1 inf 0\n", 2, "not finite"),
            ("v 0 0 0\nv 1 x 0\n", 2, "could not parse"),
            ("v 0 0\n", 1, "needs 3 numbers"),
            ("vn 0 0 1e999\n", 1, "not finite"),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
                4,
                "index 4 out of range",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n",
                4,
                "reaches before the first",
            ),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, "index 0"),
            ("v 0 0 0\nv 1 0 0\nf 1 2\n", 3, "at least 3"),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/5 2/5 3/5\n",
                4,
                "texture coordinate index 5",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n",
                4,
                "could not parse face index",
            ),
        ];
        for (text, line, msg) in cases {
            let (l, e) = err_line(obj(text));
            assert_eq!(l, line, "{e}");
            assert!(
                e.contains(msg) && e.contains("m.obj"),
                "{e}\n  wanted: {msg}"
            );
        }
        assert!(matches!(obj("\u{0}\u{ff}"), Ok(_) | Err(_)));
        let e = load(Path::new("/nonexistent/x.obj"), true).unwrap_err();
        assert!(e.to_string().contains("/nonexistent/x.obj"), "{e}");
    }
}
