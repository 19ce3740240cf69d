//! Stanford PLY meshes: binary files (little and big endian) through our own reader
//! ([`super::ply_binary`], fast), ASCII ones through `ply-rs`.
//!
//! Element `vertex` with `x`, `y`, `z`; optional `nx`, `ny`, `nz`; optional texture
//! coordinates `u`/`v`, `s`/`t`, `texture_u`/`texture_v` or `texture_s`/`texture_t`.
//! Element `face` with a list `vertex_indices` (or `vertex_index`); polygons are
//! fan-triangulated. Other elements and properties are ignored.

use std::path::Path;

use glam::{Vec2, Vec3};
use ply_rs::ply::{DefaultElement, Property};

use super::{Error, Mesh};

/// Loads a PLY file.
pub fn load(path: &Path) -> Result<Mesh, Error> {
    let bytes = super::file_bytes::FileBytes::open(path)?;
    check_header(path, &bytes)?;
    if let Some(mesh) = super::ply_binary::load(path, &bytes)? {
        return Ok(mesh);
    }
    let parser = ply_rs::parser::Parser::<DefaultElement>::new();
    let ply = parser
        .read_ply(&mut &bytes[..])
        .map_err(|e| Error::file(path, format!("malformed PLY: {e}")))?;

    let vertices = ply
        .payload
        .get("vertex")
        .ok_or_else(|| Error::file(path, "PLY file has no 'vertex' element"))?;
    let mut mesh = Mesh {
        name: path.display().to_string(),
        ..Mesh::default()
    };
    let uv_names = [
        ("u", "v"),
        ("s", "t"),
        ("texture_u", "texture_v"),
        ("texture_s", "texture_t"),
    ];
    let first = vertices.first();
    let has_normals = first.is_some_and(|v| ["nx", "ny", "nz"].iter().all(|k| v.contains_key(*k)));
    let uv_keys = first.and_then(|v| {
        uv_names
            .iter()
            .find(|(a, b)| v.contains_key(*a) && v.contains_key(*b))
    });
    for (i, v) in vertices.iter().enumerate() {
        let get = |key: &str| -> Result<f32, Error> {
            let value = v.get(key).and_then(scalar).ok_or_else(|| {
                Error::file(path, format!("vertex {i} has no numeric property '{key}'"))
            })?;
            if !value.is_finite() {
                return Err(Error::file(
                    path,
                    format!("vertex {i}: '{key}' is not finite ({value})"),
                ));
            }
            Ok(value as f32)
        };
        mesh.positions
            .push(Vec3::new(get("x")?, get("y")?, get("z")?));
        if has_normals {
            mesh.normals
                .push(Vec3::new(get("nx")?, get("ny")?, get("nz")?));
        }
        if let Some((a, b)) = uv_keys {
            mesh.uvs.push(Vec2::new(get(a)?, get(b)?));
        }
    }

    let n = mesh.positions.len() as i64;
    let faces = ply.payload.get("face").map(Vec::as_slice).unwrap_or(&[]);
    for (f, face) in faces.iter().enumerate() {
        let list = face
            .get("vertex_indices")
            .or_else(|| face.get("vertex_index"))
            .ok_or_else(|| Error::file(path, format!("face {f} has no 'vertex_indices' list")))?;
        let idx = list_indices(list).ok_or_else(|| {
            Error::file(
                path,
                format!("face {f}: 'vertex_indices' is not an integer list"),
            )
        })?;
        if idx.len() < 3 {
            return Err(Error::file(
                path,
                format!("face {f} has {} vertices (at least 3 needed)", idx.len()),
            ));
        }
        if let Some(bad) = idx.iter().find(|&&i| i < 0 || i >= n) {
            return Err(Error::file(
                path,
                format!("face {f}: vertex index {bad} out of range ({n} vertices)"),
            ));
        }
        for k in 1..idx.len() - 1 {
            mesh.indices
                .push([idx[0] as u32, idx[k] as u32, idx[k + 1] as u32]);
        }
    }
    read_attributes(path, &ply, &mut mesh)?;
    Ok(mesh)
}

/// Chooses the wanted properties of an element from their names, in file order: their
/// indices, or why the layout is wrong ([`first_element`]).
pub type Pick<'a> = dyn FnMut(&[String]) -> Result<Vec<usize>, String> + 'a;

/// Chosen scalar properties of a PLY file's first element, for loaders of a layout of
/// their own (Mitsuba's `ellipsoids` reads its first element so): [`first_element`].
#[derive(Debug, Clone, PartialEq)]
pub struct ScalarElement {
    /// Values per entry: the properties chosen, in the order chosen.
    pub columns: usize,
    /// Entry after entry, `columns` values each, every one finite.
    pub values: Vec<f32>,
    /// In an ASCII file, the line of entry 0 (ply-rs reads one entry a line).
    pub first_line: Option<u32>,
}

impl ScalarElement {
    pub fn count(&self) -> usize {
        self.values.len() / self.columns.max(1)
    }

    /// Entry `k`'s values.
    pub fn entry(&self, k: usize) -> &[f32] {
        &self.values[k * self.columns..(k + 1) * self.columns]
    }

    /// An error about entry `k` (whose name `message` says): at its line in an ASCII
    /// file.
    pub fn error_at(&self, path: &Path, k: usize, message: String) -> Error {
        match self.first_line {
            Some(line) => Error::at(path, line + k as u32, message),
            None => Error::file(path, message),
        }
    }
}

/// Reads the first element of the PLY file at `path` as [`load`] reads meshes (binary
/// through [`super::ply_binary`], ASCII through ply-rs). Its properties must be
/// scalars; `pick` is given their names in file order and returns the indices of those
/// wanted (or why the layout is wrong). Errors name the file, the entry as `entry` and
/// its number, and in an ASCII file its line: a file that ends early, a value that is
/// not a number, a chosen value that is not finite.
pub fn first_element(
    path: &Path,
    entry: &str,
    mut pick: impl FnMut(&[String]) -> Result<Vec<usize>, String>,
) -> Result<ScalarElement, Error> {
    use ply_rs::ply::{Addable, ElementDef, PropertyType};
    use std::io::BufRead;
    let bytes = super::file_bytes::FileBytes::open(path)?;
    check_header(path, &bytes)?;
    if let Some(e) = super::ply_binary::first_element(path, &bytes, entry, &mut pick)? {
        return Ok(e);
    }
    // ASCII.
    let parser = ply_rs::parser::Parser::<DefaultElement>::new();
    let mut reader = &bytes[..];
    let header = parser
        .read_header(&mut reader)
        .map_err(|e| Error::file(path, format!("malformed PLY: {e}")))?;
    let def = header
        .elements
        .values()
        .next()
        .ok_or_else(|| Error::file(path, "the PLY file has no element"))?;
    if let Some(p) = def
        .properties
        .values()
        .find(|p| !matches!(p.data_type, PropertyType::Scalar(_)))
    {
        return Err(Error::file(
            path,
            format!(
                "PLY element '{}': '{}' is a list, where scalars are read",
                def.name, p.name
            ),
        ));
    }
    let names: Vec<String> = def.properties.keys().cloned().collect();
    let wanted = pick(&names).map_err(|m| Error::file(path, m))?;
    // The body's first line follows the header's lines.
    let header_lines = bytes[..bytes.len() - reader.len()]
        .iter()
        .filter(|&&b| b == b'\n')
        .count() as u32;
    let mut out = ScalarElement {
        columns: wanted.len(),
        values: Vec::with_capacity(def.count.min(1 << 20) * wanted.len()),
        first_line: Some(header_lines + 1),
    };
    let ends = |k: usize| {
        Error::file(
            path,
            format!("the file ends inside {entry} {k} of {}", def.count),
        )
    };
    let mut line = String::new();
    for k in 0..def.count {
        line.clear();
        reader
            .read_line(&mut line)
            .map_err(|e| out.error_at(path, k, format!("{entry} {k}: {e}")))?;
        if line.is_empty() {
            return Err(ends(k));
        }
        let e = parser.read_ascii_element(&line, def).map_err(|e| {
            // Which word ply-rs refuses, read alone as its property.
            let words: Vec<&str> = line.split_whitespace().collect();
            let why = def.properties.values().enumerate().find_map(|(j, p)| {
                let Some(w) = words.get(j) else {
                    return Some(format!("the line ends before '{}'", p.name));
                };
                let mut one = ElementDef::new(p.name.clone());
                one.properties.add(p.clone());
                parser.read_ascii_element(w, &one).is_err().then(|| {
                    if w.parse::<f64>().is_ok_and(|v| !v.is_finite()) {
                        format!("'{}' is not finite ('{w}')", p.name)
                    } else {
                        format!("'{}' is not a number of its type ('{w}')", p.name)
                    }
                })
            });
            let why = why.unwrap_or_else(|| format!("ply-rs cannot read it: {e}"));
            out.error_at(path, k, format!("{entry} {k}: {why}"))
        })?;
        for &j in &wanted {
            let name = &names[j];
            let v = e.get(name).and_then(scalar).unwrap_or(f64::NAN) as f32;
            if !v.is_finite() {
                return Err(out.error_at(
                    path,
                    k,
                    format!("{entry} {k}: '{name}' is not finite ({v})"),
                ));
            }
            out.values.push(v);
        }
    }
    Ok(out)
}

/// The vertex and face attributes Mitsuba makes of the other scalar properties
/// (`mesh_attribute::ply_attributes`); a face's values repeat for each triangle of
/// its fan.
fn read_attributes(
    path: &Path,
    ply: &ply_rs::ply::Ply<DefaultElement>,
    mesh: &mut Mesh,
) -> Result<(), Error> {
    use super::texture::mesh_attribute::{ply_attributes, MeshAttribute};
    for element in ["vertex", "face"] {
        let (Some(def), Some(entries)) =
            (ply.header.elements.get(element), ply.payload.get(element))
        else {
            continue;
        };
        let names: Vec<&str> = def
            .properties
            .values()
            .filter(|p| matches!(p.data_type, ply_rs::ply::PropertyType::Scalar(_)))
            .map(|p| p.name.as_str())
            .collect();
        for (name, fields) in ply_attributes(element, &names) {
            let mut values = Vec::new();
            for (i, entry) in entries.iter().enumerate() {
                let repeat = if element == "face" {
                    entry
                        .get("vertex_indices")
                        .or_else(|| entry.get("vertex_index"))
                        .and_then(list_indices)
                        .map_or(0, |l| l.len().saturating_sub(2))
                } else {
                    1
                };
                let mut v = Vec::with_capacity(fields.len());
                for f in &fields {
                    let x = entry.get(f).and_then(scalar).unwrap_or(f64::NAN) as f32;
                    if !x.is_finite() {
                        return Err(Error::file(
                            path,
                            format!("{element} {i}: '{f}' is not a finite number"),
                        ));
                    }
                    v.push(x);
                }
                for _ in 0..repeat {
                    values.extend_from_slice(&v);
                }
            }
            mesh.attributes.push(MeshAttribute {
                name,
                dim: fields.len() as u32,
                values,
            });
        }
    }
    Ok(())
}

fn scalar(p: &Property) -> Option<f64> {
    Some(match *p {
        Property::Char(v) => v.into(),
        Property::UChar(v) => v.into(),
        Property::Short(v) => v.into(),
        Property::UShort(v) => v.into(),
        Property::Int(v) => v.into(),
        Property::UInt(v) => v.into(),
        Property::Float(v) => v.into(),
        Property::Double(v) => v,
        _ => return None,
    })
}

fn list_indices(p: &Property) -> Option<Vec<i64>> {
    Some(match p {
        Property::ListChar(v) => v.iter().map(|&i| i.into()).collect(),
        Property::ListUChar(v) => v.iter().map(|&i| i.into()).collect(),
        Property::ListShort(v) => v.iter().map(|&i| i.into()).collect(),
        Property::ListUShort(v) => v.iter().map(|&i| i.into()).collect(),
        Property::ListInt(v) => v.iter().map(|&i| i.into()).collect(),
        Property::ListUInt(v) => v.iter().map(|&i| i.into()).collect(),
        _ => return None,
    })
}

/// Rejects headers that would make the parser loop or allocate without bound: an
/// element with a count but no properties, or more elements than the file has bytes.
fn check_header(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    let end = bytes
        .windows(10)
        .position(|w| w == b"end_header")
        .ok_or_else(|| Error::file(path, "not a PLY file (no end_header)"))?;
    let header = String::from_utf8_lossy(&bytes[..end]);
    if !header.starts_with("ply") {
        return Err(Error::file(
            path,
            "not a PLY file (does not start with 'ply')",
        ));
    }
    let mut current: Option<(String, u64, usize)> = None;
    let check = |e: &Option<(String, u64, usize)>| -> Result<(), Error> {
        if let Some((name, count, props)) = e {
            if *count > 0 && *props == 0 {
                return Err(Error::file(
                    path,
                    format!("PLY element '{name}' has {count} entries but no properties"),
                ));
            }
            if *count > bytes.len() as u64 {
                return Err(Error::file(
                    path,
                    format!(
                        "PLY element '{name}' claims {count} entries, more than the file can hold"
                    ),
                ));
            }
        }
        Ok(())
    };
    for line in header.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        // ply-rs unwraps its parse of the version's numbers: a number past 2^64
        // would panic there.
        if w.first() == Some(&"format") {
            let version = w.get(2).copied().unwrap_or("");
            if version
                .split(|c: char| !c.is_ascii_digit())
                .any(|n| !n.is_empty() && n.parse::<u64>().is_err())
            {
                return Err(Error::file(
                    path,
                    format!("malformed PLY header line \"{line}\": version number out of range"),
                ));
            }
        }
        match w.first() {
            Some(&"element") => {
                check(&current)?;
                let count = w
                    .get(2)
                    .and_then(|c| c.parse::<u64>().ok())
                    .ok_or_else(|| {
                        Error::file(path, format!("malformed PLY header line \"{line}\""))
                    })?;
                current = Some((w.get(1).unwrap_or(&"").to_string(), count, 0));
            }
            Some(&"property") => {
                if let Some(c) = current.as_mut() {
                    c.2 += 1;
                }
            }
            _ => {}
        }
    }
    check(&current)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::testutil::temp_dir;

    fn ply(bytes: &[u8]) -> Result<Mesh, Error> {
        let p = temp_dir("ply").join("m.ply");
        std::fs::write(&p, bytes).unwrap();
        load(&p)
    }

    const ASCII: &str = "ply\nformat ascii 1.0\ncomment quad and triangle\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float s\nproperty float t\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n1 1 0 0 0 1 1 1\n0 1 0 0 0 1 0 1\n2 2 0 0 0 1 0 0\n4 0 1 2 3\n3 1 4 2\n";

    #[test]
    fn ascii_with_normals_uvs_and_quads() {
        let m = ply(ASCII.as_bytes()).unwrap();
        assert_eq!((m.positions.len(), m.normals.len(), m.uvs.len()), (5, 5, 5));
        assert_eq!(m.indices, vec![[0, 1, 2], [0, 2, 3], [1, 4, 2]]);
        assert_eq!(m.uvs[2], Vec2::new(1.0, 1.0));
    }

    fn binary(big: bool, index: i32) -> Vec<u8> {
        let fmt = if big {
            "binary_big_endian"
        } else {
            "binary_little_endian"
        };
        let mut b = format!("ply\nformat {fmt} 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty float u\nproperty float v\nelement face 1\nproperty list uchar int vertex_index\nend_header\n").into_bytes();
        let f32b = |v: f32| {
            if big {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            }
        };
        for p in [
            [0.0, 0.0, 0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0, 1.0, 0.0],
            [0.0, 2.0, 0.0, 0.0, 1.0],
        ] {
            for v in p {
                b.extend(f32b(v));
            }
        }
        b.push(3);
        for i in [0, 1, index] {
            b.extend(if big {
                i.to_be_bytes()
            } else {
                i.to_le_bytes()
            });
        }
        b
    }

    #[test]
    fn binary_both_endians() {
        for big in [false, true] {
            let m = ply(&binary(big, 2)).unwrap();
            assert_eq!(m.positions[1], Vec3::new(2.0, 0.0, 0.0));
            assert_eq!(m.uvs[2], Vec2::new(0.0, 1.0));
            assert!(m.normals.is_empty());
            assert_eq!(m.indices, vec![[0, 1, 2]]);
            assert_eq!(m.area(), 2.0);
        }
    }

    #[test]
    fn errors() {
        for (bytes, msg) in [
            (binary(false, 3), "vertex index 3 out of range"),
            (binary(true, -1), "vertex index -1 out of range"),
            ({ let b = binary(false, 2); b[..b.len() - 5].to_vec() }, "malformed PLY"),
            (b"hello".to_vec(), "not a PLY file"),
            (b"ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n".to_vec(), "no 'vertex' element"),
            (b"ply\nformat ascii 1.0\nelement vertex 4000000000\nend_header\n".to_vec(), "no properties"),
            ({
                // Binary, with vertex 1's x set to NaN (each vertex is 5 floats).
                let mut b = binary(false, 2);
                let h = b.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
                b[h + 20..h + 24].copy_from_slice(&f32::NAN.to_le_bytes());
                b
            }, "not finite"),
        ] {
            let e = ply(&bytes).unwrap_err().to_string();
            assert!(e.contains(msg) && e.contains("m.ply"), "{e}\n  wanted: {msg}");
        }
    }
}
