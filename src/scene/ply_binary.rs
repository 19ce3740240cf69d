//! Binary PLY (little and big endian) read straight from the file's bytes: the format
//! large meshes come in, at close to the speed of reading the file.
//!
//! `ply-rs` builds a map of named properties per vertex and per face, which took 16 s
//! and 5 GB for an 8 M-triangle height field (160 MB). Here the header is parsed into
//! elements and typed properties; vertex records, of fixed size, are decoded in
//! parallel from the offsets of the properties wanted; faces are walked once, with a
//! fast path for the usual `list uchar int` (or `uint`) triangles. Any element layout
//! of scalar and list properties of the PLY types is read; other elements are skipped.
//! ASCII files go to `ply-rs` ([`super::ply`]).
//!
//! What is read is what [`super::ply`] documents: element `vertex` with `x`, `y`, `z`,
//! optional normals `nx`, `ny`, `nz` and uvs (`u`/`v`, `s`/`t`, `texture_u`/`texture_v`
//! or `texture_s`/`texture_t`); element `face` with a list `vertex_indices` (or
//! `vertex_index`), polygons fan-triangulated. Errors name the file, the element and
//! the entry.

use std::path::Path;

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::{Error, Mesh};

/// A scalar type of the PLY format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }

    /// The value at the start of `b` (at least `size()` bytes).
    #[inline]
    fn read(self, b: &[u8], big: bool) -> f64 {
        macro_rules! get {
            ($t:ty, $n:expr) => {{
                let a: [u8; $n] = b[..$n].try_into().expect("bounds checked by the caller");
                if big {
                    <$t>::from_be_bytes(a)
                } else {
                    <$t>::from_le_bytes(a)
                }
            }};
        }
        match self {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => get!(i16, 2) as f64,
            Scalar::U16 => get!(u16, 2) as f64,
            Scalar::I32 => get!(i32, 4) as f64,
            Scalar::U32 => get!(u32, 4) as f64,
            Scalar::F32 => get!(f32, 4) as f64,
            Scalar::F64 => get!(f64, 8),
        }
    }

    /// An integer value at the start of `b`, for list counts and indices.
    #[inline]
    fn read_int(self, b: &[u8], big: bool) -> i64 {
        self.read(b, big) as i64
    }
}

/// A property: a scalar, or a list of `item`s preceded by a `count`.
#[derive(Clone, Debug)]
enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

#[derive(Clone, Debug)]
struct Property {
    name: String,
    kind: Kind,
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

impl Element {
    /// Bytes per entry if every property is a scalar.
    fn fixed_size(&self) -> Option<usize> {
        self.properties
            .iter()
            .map(|p| match p.kind {
                Kind::Scalar(s) => Some(s.size()),
                Kind::List { .. } => None,
            })
            .sum()
    }

    /// Byte offset and type of scalar property `name` in a fixed-size entry.
    fn scalar(&self, name: &str) -> Option<(usize, Scalar)> {
        let mut offset = 0;
        for p in &self.properties {
            match p.kind {
                Kind::Scalar(s) if p.name == name => return Some((offset, s)),
                Kind::Scalar(s) => offset += s.size(),
                Kind::List { .. } => return None,
            }
        }
        None
    }
}

/// Reads a binary PLY file whose bytes are `bytes`; `None` for an ASCII file.
pub fn load(path: &Path, bytes: &[u8]) -> Result<Option<Mesh>, Error> {
    let (big, elements, body) = match header(path, bytes)? {
        Some(h) => h,
        None => return Ok(None),
    };
    let mut mesh = Mesh {
        name: path.display().to_string(),
        ..Mesh::default()
    };
    let vertices = elements
        .iter()
        .find(|e| e.name == "vertex")
        .ok_or_else(|| Error::file(path, "PLY file has no 'vertex' element"))?;
    let vertex_count = vertices.count;
    let mut at = body;
    for e in &elements {
        let data = &bytes[at..];
        let used = match e.name.as_str() {
            "vertex" => {
                let used = read_vertices(path, e, data, big, &mut mesh)?;
                read_vertex_attributes(path, e, &data[..used], big, &mut mesh)?;
                used
            }
            "face" => {
                let used = read_faces(path, e, data, big, vertex_count, &mut mesh.indices)?;
                read_face_attributes(path, e, &data[..used], big, &mut mesh)?;
                used
            }
            _ => skip(path, e, data, big)?,
        };
        at += used;
    }
    Ok(Some(mesh))
}

/// The first element of a binary PLY file, for [`super::ply::first_element`] (which
/// documents `entry` and `pick`); `None` for an ASCII file.
pub fn first_element(
    path: &Path,
    bytes: &[u8],
    entry: &str,
    pick: &mut super::ply::Pick,
) -> Result<Option<super::ply::ScalarElement>, Error> {
    let Some((big, elements, body)) = header(path, bytes)? else {
        return Ok(None);
    };
    let e = elements
        .first()
        .ok_or_else(|| Error::file(path, "the PLY file has no element"))?;
    let Some(size) = e.fixed_size() else {
        return Err(Error::file(
            path,
            format!(
                "PLY element '{}' has a list property, where scalars are read",
                e.name
            ),
        ));
    };
    let names: Vec<String> = e.properties.iter().map(|p| p.name.clone()).collect();
    let wanted = pick(&names).map_err(|m| Error::file(path, m))?;
    let columns: Vec<(usize, Scalar)> = wanted
        .iter()
        .map(|&j| e.scalar(&names[j]).expect("a scalar of the element"))
        .collect();
    let data = &bytes[body..];
    let mut values = Vec::with_capacity(e.count.min(data.len() / size.max(1)) * wanted.len());
    for k in 0..e.count {
        let record = data.get(k * size..(k + 1) * size).ok_or_else(|| {
            Error::file(
                path,
                format!("the file ends inside {entry} {k} of {}", e.count),
            )
        })?;
        for (&j, &(offset, s)) in wanted.iter().zip(&columns) {
            let v = s.read(&record[offset..], big) as f32;
            if !v.is_finite() {
                return Err(Error::file(
                    path,
                    format!("{entry} {k}: '{}' is not finite ({v})", names[j]),
                ));
            }
            values.push(v);
        }
    }
    Ok(Some(super::ply::ScalarElement {
        columns: wanted.len(),
        values,
        first_line: None,
    }))
}

/// Parses the header: (big endian, elements, offset of the body), or `None` if the
/// file is ASCII.
fn header(path: &Path, bytes: &[u8]) -> Result<Option<(bool, Vec<Element>, usize)>, Error> {
    let end = bytes
        .windows(10)
        .position(|w| w == b"end_header")
        .ok_or_else(|| Error::file(path, "not a PLY file (no end_header)"))?;
    // The body starts after the line break that ends "end_header".
    let mut body = end + 10;
    if bytes.get(body) == Some(&b'\r') {
        body += 1;
    }
    if bytes.get(body) != Some(&b'\n') {
        return Err(Error::file(
            path,
            "malformed PLY header: 'end_header' must end its line",
        ));
    }
    body += 1;
    let text = String::from_utf8_lossy(&bytes[..end]);
    let mut big = None;
    let mut elements: Vec<Element> = Vec::new();
    for line in text.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        let bad = || Error::file(path, format!("malformed PLY header line \"{line}\""));
        match w.first().copied() {
            Some("format") => {
                big = match w.get(1).copied() {
                    Some("ascii") => return Ok(None),
                    Some("binary_little_endian") => Some(false),
                    Some("binary_big_endian") => Some(true),
                    _ => return Err(bad()),
                }
            }
            Some("element") => {
                let (Some(name), Some(count)) = (w.get(1), w.get(2)) else {
                    return Err(bad());
                };
                let count = count.parse::<usize>().map_err(|_| bad())?;
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    properties: Vec::new(),
                });
            }
            Some("property") => {
                let element = elements.last_mut().ok_or_else(bad)?;
                let type_of = |t: &str| {
                    Scalar::parse(t).ok_or_else(|| {
                        Error::file(
                            path,
                            format!(
                                "PLY element '{}': unknown property type '{t}'",
                                element.name
                            ),
                        )
                    })
                };
                let (kind, name) = if w.get(1) == Some(&"list") {
                    let (Some(c), Some(i), Some(n)) = (w.get(2), w.get(3), w.get(4)) else {
                        return Err(bad());
                    };
                    let (count, item) = (type_of(c)?, type_of(i)?);
                    if !count.is_integer() {
                        return Err(Error::file(
                            path,
                            format!(
                                "PLY element '{}': list '{n}' has a non-integer count type",
                                element.name
                            ),
                        ));
                    }
                    (Kind::List { count, item }, n)
                } else {
                    let (Some(t), Some(n)) = (w.get(1), w.get(2)) else {
                        return Err(bad());
                    };
                    (Kind::Scalar(type_of(t)?), n)
                };
                element.properties.push(Property {
                    name: name.to_string(),
                    kind,
                });
            }
            _ => {}
        }
    }
    let big = big.ok_or_else(|| Error::file(path, "malformed PLY header: no 'format' line"))?;
    Ok(Some((big, elements, body)))
}

fn truncated(path: &Path, e: &Element, entry: usize) -> Error {
    Error::file(
        path,
        format!(
            "malformed PLY: the file ends inside element '{}' (entry {entry} of {})",
            e.name, e.count
        ),
    )
}

/// Bytes of entries of `e` with list properties, walked one by one; calls
/// `visit(entry, property, list_bytes, count)` for each list.
fn walk(
    path: &Path,
    e: &Element,
    data: &[u8],
    big: bool,
    mut visit: impl FnMut(usize, usize, &[u8], usize) -> Result<(), Error>,
) -> Result<usize, Error> {
    let mut at = 0;
    for entry in 0..e.count {
        for (k, p) in e.properties.iter().enumerate() {
            match p.kind {
                Kind::Scalar(s) => at += s.size(),
                Kind::List { count, item } => {
                    let c = data
                        .get(at..at + count.size())
                        .ok_or_else(|| truncated(path, e, entry))?;
                    let n = count.read_int(c, big);
                    if n < 0 {
                        return Err(Error::file(
                            path,
                            format!(
                                "PLY element '{}' entry {entry}: list '{}' has {n} items",
                                e.name, p.name
                            ),
                        ));
                    }
                    at += count.size();
                    let len = n as usize * item.size();
                    let items = data
                        .get(at..at + len)
                        .ok_or_else(|| truncated(path, e, entry))?;
                    visit(entry, k, items, n as usize)?;
                    at += len;
                }
            }
        }
        if at > data.len() {
            return Err(truncated(path, e, entry));
        }
    }
    Ok(at)
}

/// Skips element `e`; returns its size in bytes.
fn skip(path: &Path, e: &Element, data: &[u8], big: bool) -> Result<usize, Error> {
    match e.fixed_size() {
        Some(size) => {
            let len = size * e.count;
            if len > data.len() {
                return Err(truncated(path, e, data.len() / size.max(1)));
            }
            Ok(len)
        }
        None => walk(path, e, data, big, |_, _, _, _| Ok(())),
    }
}

/// Reads the vertex element into `mesh` (positions, and normals and uvs where
/// present); returns its size in bytes.
fn read_vertices(
    path: &Path,
    e: &Element,
    data: &[u8],
    big: bool,
    mesh: &mut Mesh,
) -> Result<usize, Error> {
    let Some(size) = e.fixed_size() else {
        return Err(Error::file(
            path,
            "PLY element 'vertex' has a list property; only scalar vertex properties are read",
        ));
    };
    let len = size * e.count;
    let data = data
        .get(..len)
        .ok_or_else(|| truncated(path, e, data.len() / size.max(1)))?;
    let prop = |name: &str| {
        e.scalar(name).ok_or_else(|| {
            Error::file(
                path,
                format!("PLY element 'vertex' has no numeric property '{name}'"),
            )
        })
    };
    let position = [prop("x")?, prop("y")?, prop("z")?];
    let normal = ["nx", "ny", "nz"].map(|n| e.scalar(n));
    let normal = normal
        .iter()
        .all(Option::is_some)
        .then(|| normal.map(|n| n.expect("all present")));
    let uv = [
        ("u", "v"),
        ("s", "t"),
        ("texture_u", "texture_v"),
        ("texture_s", "texture_t"),
    ]
    .iter()
    .find_map(|(a, b)| Some([e.scalar(a)?, e.scalar(b)?]));
    let names = |which: &[(usize, Scalar)]| -> Vec<String> {
        which
            .iter()
            .map(|(o, _)| {
                e.properties
                    .iter()
                    .scan(0, |at, p| {
                        let here = *at;
                        if let Kind::Scalar(s) = p.kind {
                            *at += s.size();
                        }
                        Some((here, p.name.clone()))
                    })
                    .find(|(at, _)| at == o)
                    .map(|(_, n)| n)
                    .unwrap_or_default()
            })
            .collect()
    };
    // Decodes N properties of every vertex; the first non-finite value is an error.
    fn decode<const N: usize>(
        data: &[u8],
        size: usize,
        big: bool,
        props: [(usize, Scalar); N],
    ) -> Result<Vec<[f32; N]>, (usize, usize, f64)> {
        let f32s = props.iter().all(|p| p.1 == Scalar::F32);
        let mut values = vec![[0.0f32; N]; data.len() / size];
        in_blocks(&mut values, data, size, |first, out, records| {
            for (j, (v, r)) in out.iter_mut().zip(records.chunks_exact(size)).enumerate() {
                *v = props.map(|(o, s)| {
                    if f32s {
                        // The usual case, without a type switch per value.
                        let b: [u8; 4] = r[o..o + 4].try_into().expect("4 bytes");
                        if big {
                            f32::from_be_bytes(b)
                        } else {
                            f32::from_le_bytes(b)
                        }
                    } else {
                        s.read(&r[o..], big) as f32
                    }
                });
                if let Some(k) = v.iter().position(|x| !x.is_finite()) {
                    return Err((first + j, k, props[k].1.read(&r[props[k].0..], big)));
                }
            }
            Ok(())
        })?;
        Ok(values)
    }
    let not_finite = |which: &[(usize, Scalar)], (i, k, v): (usize, usize, f64)| {
        Error::file(
            path,
            format!("vertex {i}: '{}' is not finite ({v})", names(which)[k]),
        )
    };
    mesh.positions = decode(data, size, big, position)
        .map_err(|f| not_finite(&position, f))?
        .into_iter()
        .map(Vec3::from_array)
        .collect();
    if let Some(normal) = normal {
        mesh.normals = decode(data, size, big, normal)
            .map_err(|f| not_finite(&normal, f))?
            .into_iter()
            .map(Vec3::from_array)
            .collect();
    }
    if let Some(uv) = uv {
        mesh.uvs = decode(data, size, big, uv)
            .map_err(|f| not_finite(&uv, f))?
            .into_iter()
            .map(Vec2::from_array)
            .collect();
    }
    Ok(len)
}

/// The names of the scalar properties of `e`, in order.
fn scalar_names(e: &Element) -> Vec<&str> {
    e.properties
        .iter()
        .filter(|p| matches!(p.kind, Kind::Scalar(_)))
        .map(|p| p.name.as_str())
        .collect()
}

/// The vertex attributes Mitsuba makes of the vertex element's other properties
/// (`mesh_attribute::ply_attributes`); `data` is the element's bytes.
fn read_vertex_attributes(
    path: &Path,
    e: &Element,
    data: &[u8],
    big: bool,
    mesh: &mut Mesh,
) -> Result<(), Error> {
    use super::texture::mesh_attribute::{ply_attributes, MeshAttribute};
    let Some(size) = e.fixed_size() else {
        return Ok(());
    };
    for (name, fields) in ply_attributes("vertex", &scalar_names(e)) {
        let props: Vec<(usize, Scalar)> = fields.iter().filter_map(|f| e.scalar(f)).collect();
        let mut values = Vec::with_capacity(props.len() * e.count);
        for (i, r) in data.chunks_exact(size.max(1)).enumerate() {
            for (k, &(o, s)) in props.iter().enumerate() {
                let v = s.read(&r[o..], big) as f32;
                if !v.is_finite() {
                    return Err(Error::file(
                        path,
                        format!("vertex {i}: '{}' is not finite", fields[k]),
                    ));
                }
                values.push(v);
            }
        }
        mesh.attributes.push(MeshAttribute {
            name,
            dim: props.len() as u32,
            values,
        });
    }
    Ok(())
}

/// The face attributes Mitsuba makes of the face element's scalar properties, one
/// value per triangle of each face's fan; `data` is the element's bytes.
fn read_face_attributes(
    path: &Path,
    e: &Element,
    data: &[u8],
    big: bool,
    mesh: &mut Mesh,
) -> Result<(), Error> {
    use super::texture::mesh_attribute::{ply_attributes, MeshAttribute};
    let specs = ply_attributes("face", &scalar_names(e));
    if specs.is_empty() {
        return Ok(());
    }
    let index_of = |f: &str| e.properties.iter().position(|p| p.name == f);
    let fields: Vec<Vec<usize>> = specs
        .iter()
        .map(|(_, fs)| fs.iter().filter_map(|f| index_of(f)).collect())
        .collect();
    let mut out: Vec<MeshAttribute> = specs
        .iter()
        .zip(&fields)
        .map(|((name, _), f)| MeshAttribute {
            name: name.clone(),
            dim: f.len() as u32,
            values: Vec::new(),
        })
        .collect();
    let mut values = vec![0.0f32; e.properties.len()];
    let mut at = 0;
    for entry in 0..e.count {
        let mut triangles = 0;
        for (k, p) in e.properties.iter().enumerate() {
            match p.kind {
                Kind::Scalar(s) => {
                    let b = data
                        .get(at..at + s.size())
                        .ok_or_else(|| truncated(path, e, entry))?;
                    values[k] = s.read(b, big) as f32;
                    at += s.size();
                }
                Kind::List { count, item } => {
                    let c = data
                        .get(at..at + count.size())
                        .ok_or_else(|| truncated(path, e, entry))?;
                    let n = count.read_int(c, big).max(0) as usize;
                    if p.name == "vertex_indices" || p.name == "vertex_index" {
                        triangles = n.saturating_sub(2);
                    }
                    at += count.size() + n * item.size();
                }
            }
        }
        for (a, f) in out.iter_mut().zip(&fields) {
            if let Some(&bad) = f.iter().find(|&&k| !values[k].is_finite()) {
                return Err(Error::file(
                    path,
                    format!("face {entry}: '{}' is not finite", e.properties[bad].name),
                ));
            }
            for _ in 0..triangles {
                a.values.extend(f.iter().map(|&k| values[k]));
            }
        }
    }
    mesh.attributes.extend(out);
    Ok(())
}

/// Entries decoded per parallel task.
const BLOCK: usize = 1 << 14;

/// Runs `decode(first entry, entries, their records)` over blocks of [`BLOCK`] entries
/// of `size` bytes in parallel; returns the error of the first block that fails.
fn in_blocks<T: Send, E: Send>(
    out: &mut [T],
    data: &[u8],
    size: usize,
    decode: impl Fn(usize, &mut [T], &[u8]) -> Result<(), E> + Sync,
) -> Result<(), E> {
    let results: Vec<Result<(), E>> = out
        .par_chunks_mut(BLOCK)
        .zip(data.par_chunks(size * BLOCK))
        .enumerate()
        .map(|(b, (out, records))| decode(b * BLOCK, out, records))
        .collect();
    results.into_iter().collect()
}

/// Reads the face element's vertex lists as fan-triangulated triangles; returns the
/// element's size in bytes.
fn read_faces(
    path: &Path,
    e: &Element,
    data: &[u8],
    big: bool,
    vertex_count: usize,
    indices: &mut Vec<[u32; 3]>,
) -> Result<usize, Error> {
    let list = e
        .properties
        .iter()
        .position(|p| {
            matches!(p.kind, Kind::List { .. })
                && (p.name == "vertex_indices" || p.name == "vertex_index")
        })
        .ok_or_else(|| {
            Error::file(
                path,
                "PLY element 'face' has no 'vertex_indices' list".to_string(),
            )
        })?;
    let Kind::List { count, item } = e.properties[list].kind else {
        unreachable!("found as a list")
    };
    if !item.is_integer() {
        return Err(Error::file(
            path,
            "PLY element 'face': 'vertex_indices' is not an integer list",
        ));
    }
    let out_of_range = |f: usize, i: i64| {
        Error::file(
            path,
            format!("face {f}: vertex index {i} out of range ({vertex_count} vertices)"),
        )
    };
    indices.reserve(e.count);
    let n = vertex_count as i64;
    // The usual layout: the list alone, a one-byte count and 4-byte indices, mostly
    // triangles.
    if e.properties.len() == 1 && count.size() == 1 && item.size() == 4 {
        let signed = item == Scalar::I32;
        let index = |b: &[u8]| -> i64 {
            let a: [u8; 4] = b[..4].try_into().expect("4 bytes");
            let u = if big {
                u32::from_be_bytes(a)
            } else {
                u32::from_le_bytes(a)
            };
            if signed {
                u as i32 as i64
            } else {
                u as i64
            }
        };
        // All triangles (records of 13 bytes), decoded in parallel; anything else
        // (and every error, to be named in order) takes the walk below.
        if let Some(faces) = data.get(..13 * e.count) {
            let mut triangles = vec![[0u32; 3]; e.count];
            let fast = in_blocks(&mut triangles, faces, 13, |_, out, records| {
                for (t, r) in out.iter_mut().zip(records.chunks_exact(13)) {
                    let i = [1, 5, 9].map(|at| index(&r[at..]));
                    if r[0] != 3 || i.iter().any(|&i| i < 0 || i >= n) {
                        return Err(());
                    }
                    *t = i.map(|i| i as u32);
                }
                Ok(())
            });
            if fast.is_ok() {
                if indices.is_empty() {
                    *indices = triangles;
                } else {
                    indices.extend_from_slice(&triangles);
                }
                return Ok(13 * e.count);
            }
        }
        let mut at = 0;
        for f in 0..e.count {
            let k = *data.get(at).ok_or_else(|| truncated(path, e, f))? as usize;
            let r = data
                .get(at + 1..at + 1 + 4 * k)
                .ok_or_else(|| truncated(path, e, f))?;
            at += 1 + 4 * k;
            if k < 3 {
                return Err(Error::file(
                    path,
                    format!("face {f} has {k} vertices (at least 3 needed)"),
                ));
            }
            let i0 = index(r);
            let mut prev = index(&r[4..]);
            for idx in [i0, prev] {
                if idx < 0 || idx >= n {
                    return Err(out_of_range(f, idx));
                }
            }
            for j in 2..k {
                let next = index(&r[4 * j..]);
                if next < 0 || next >= n {
                    return Err(out_of_range(f, next));
                }
                indices.push([i0 as u32, prev as u32, next as u32]);
                prev = next;
            }
        }
        return Ok(at);
    }
    let mut polygon: Vec<i64> = Vec::new();
    walk(path, e, data, big, |f, k, items, len| {
        if k != list {
            return Ok(());
        }
        if len < 3 {
            return Err(Error::file(
                path,
                format!("face {f} has {len} vertices (at least 3 needed)"),
            ));
        }
        polygon.clear();
        polygon.extend(
            items
                .chunks_exact(item.size())
                .map(|b| item.read_int(b, big)),
        );
        if let Some(&bad) = polygon.iter().find(|&&i| i < 0 || i >= n) {
            return Err(out_of_range(f, bad));
        }
        for j in 1..len - 1 {
            indices.push([polygon[0] as u32, polygon[j] as u32, polygon[j + 1] as u32]);
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use super::super::ply;
    use crate::scene::testutil::temp_dir;

    /// A property of a test file: name and type, or a list (count type, item type).
    enum P {
        S(&'static str, &'static str),
        L(&'static str, &'static str, &'static str),
    }

    /// An element of a test file: name, properties, and each entry's values (a list
    /// property takes the remaining values of its entry).
    type TestElement = (&'static str, Vec<P>, Vec<Vec<f64>>);

    /// Writes a PLY file of `elements` in `format`; returns its path.
    fn write(name: &str, format: &str, elements: &[TestElement]) -> PathBuf {
        let mut head = format!("ply\nformat {format} 1.0\ncomment test\n");
        for (e, props, entries) in elements {
            head += &format!("element {e} {}\n", entries.len());
            for p in props {
                head += &match p {
                    P::S(n, t) => format!("property {t} {n}\n"),
                    P::L(n, c, t) => format!("property list {c} {t} {n}\n"),
                };
            }
        }
        head += "end_header\n";
        let mut bytes = head.into_bytes();
        let big = format == "binary_big_endian";
        let put = |bytes: &mut Vec<u8>, t: &str, v: f64| {
            macro_rules! b {
                ($x:expr) => {
                    if big {
                        bytes.extend_from_slice(&$x.to_be_bytes())
                    } else {
                        bytes.extend_from_slice(&$x.to_le_bytes())
                    }
                };
            }
            match t {
                "char" => b!(v as i8),
                "uchar" => b!(v as u8),
                "short" => b!(v as i16),
                "ushort" => b!(v as u16),
                "int" => b!(v as i32),
                "uint" => b!(v as u32),
                "float" => b!(v as f32),
                "double" => b!(v),
                _ => unreachable!(),
            }
        };
        for (_, props, entries) in elements {
            for entry in entries {
                let mut at = 0;
                let mut line = Vec::new();
                for p in props {
                    match p {
                        P::S(_, t) => {
                            if format == "ascii" {
                                line.push(entry[at].to_string());
                            } else {
                                put(&mut bytes, t, entry[at]);
                            }
                            at += 1;
                        }
                        P::L(_, c, t) => {
                            let items = &entry[at..];
                            if format == "ascii" {
                                line.push(items.len().to_string());
                                line.extend(items.iter().map(|v| v.to_string()));
                            } else {
                                put(&mut bytes, c, items.len() as f64);
                                for &v in items {
                                    put(&mut bytes, t, v);
                                }
                            }
                            at = entry.len();
                        }
                    }
                }
                if format == "ascii" {
                    bytes.extend_from_slice(line.join(" ").as_bytes());
                    bytes.push(b'\n');
                }
            }
        }
        let path = temp_dir("ply_binary").join(format!("{name}.ply"));
        std::fs::write(&path, bytes).unwrap();
        path
    }

    fn vertex_props(extra: bool) -> Vec<P> {
        let mut p = vec![P::S("x", "float"), P::S("y", "double"), P::S("z", "float")];
        if extra {
            p.insert(1, P::S("confidence", "uchar"));
            p.extend([
                P::S("nx", "float"),
                P::S("ny", "float"),
                P::S("nz", "short"),
                P::S("s", "float"),
                P::S("t", "float"),
            ]);
        }
        p
    }

    fn vertices(extra: bool) -> Vec<Vec<f64>> {
        (0..6)
            .map(|i| {
                let f = i as f64;
                let mut v = vec![f * 0.5, -f, 2.0 * f + 0.25];
                if extra {
                    v.insert(1, 200.0);
                    v.extend([0.0, 0.6, 1.0, f / 5.0, 1.0 - f / 5.0]);
                }
                v
            })
            .collect()
    }

    /// Binary files of many layouts read as the same data in ASCII reads through
    /// ply-rs: every scalar type, normals and uvs between other properties, extra
    /// elements before and after, quads and pentagons, both endians, signed and
    /// unsigned indices, and the general face path (a face with two lists and a
    /// scalar).
    #[test]
    fn binary_layouts_read_as_their_ascii_twins() {
        let faces = vec![
            vec![0.0, 1.0, 2.0],
            vec![1.0, 2.0, 3.0, 4.0],
            vec![0.0, 2.0, 4.0, 5.0, 3.0],
        ];
        let general_faces: Vec<Vec<f64>> = faces
            .iter()
            .map(|f| {
                let mut e = vec![7.0];
                e.extend(f);
                e
            })
            .collect();
        let layouts: Vec<(&str, Vec<TestElement>)> = vec![
            (
                "plain",
                vec![
                    ("vertex", vertex_props(false), vertices(false)),
                    (
                        "face",
                        vec![P::L("vertex_indices", "uchar", "int")],
                        faces.clone(),
                    ),
                ],
            ),
            (
                "attributes",
                vec![
                    (
                        "material",
                        vec![P::S("r", "uchar"), P::S("g", "float")],
                        vec![vec![1.0, 2.0]],
                    ),
                    ("vertex", vertex_props(true), vertices(true)),
                    (
                        "face",
                        vec![P::L("vertex_index", "uchar", "uint")],
                        faces.clone(),
                    ),
                    (
                        "edge",
                        vec![P::S("a", "int"), P::L("l", "ushort", "char")],
                        vec![vec![1.0, 2.0, 3.0]],
                    ),
                ],
            ),
            (
                "general",
                vec![
                    ("vertex", vertex_props(false), vertices(false)),
                    (
                        "face",
                        vec![
                            P::S("flags", "ushort"),
                            P::L("vertex_indices", "int", "ushort"),
                        ],
                        general_faces,
                    ),
                ],
            ),
        ];
        for (name, elements) in &layouts {
            let want = ply::load(&write(&format!("{name}_a"), "ascii", elements)).unwrap();
            for format in ["binary_little_endian", "binary_big_endian"] {
                let path = write(&format!("{name}_{format}"), format, elements);
                let got = ply::load(&path).unwrap();
                assert_eq!(got.positions, want.positions, "{name} {format}");
                assert_eq!(got.normals, want.normals, "{name} {format}");
                assert_eq!(got.uvs, want.uvs, "{name} {format}");
                assert_eq!(got.indices, want.indices, "{name} {format}");
                assert_eq!(got.indices.len(), 1 + 2 + 3);
            }
        }
    }

    /// Meshes larger than a block of the parallel decoders, in the layout large files
    /// come in (float x, y, z; triangles of `uchar int` lists: the fast paths), read as
    /// their ASCII twins, and errors past the first block name their entry.
    #[test]
    fn large_meshes_decode_in_blocks() {
        let n = 2 * super::BLOCK + 100;
        let props = || vec![P::S("x", "float"), P::S("y", "float"), P::S("z", "float")];
        let vertices = |bad: Option<usize>| -> Vec<Vec<f64>> {
            (0..n)
                .map(|i| {
                    let f = i as f64;
                    let y = if Some(i) == bad {
                        f64::NAN
                    } else {
                        (0.37 * f).sin()
                    };
                    vec![0.25 * f, y, -f]
                })
                .collect()
        };
        let faces = |bad: Option<usize>| -> Vec<Vec<f64>> {
            (0..n - 2)
                .map(|i| {
                    let last = if Some(i) == bad { n + 5 } else { i + 2 };
                    vec![i as f64, (i + 1) as f64, last as f64]
                })
                .collect()
        };
        let mesh = |v: Option<usize>, f: Option<usize>| -> Vec<TestElement> {
            vec![
                ("vertex", props(), vertices(v)),
                (
                    "face",
                    vec![P::L("vertex_indices", "uchar", "int")],
                    faces(f),
                ),
            ]
        };
        let want = ply::load(&write("large_a", "ascii", &mesh(None, None))).unwrap();
        assert_eq!(want.indices.len(), n - 2);
        for format in ["binary_little_endian", "binary_big_endian"] {
            let got = ply::load(&write(
                &format!("large_{format}"),
                format,
                &mesh(None, None),
            ))
            .unwrap();
            assert_eq!(got.positions, want.positions, "{format}");
            assert_eq!(got.indices, want.indices, "{format}");
            let bad = |name: &str, v, f| {
                let path = write(&format!("large_{name}_{format}"), format, &mesh(v, f));
                ply::load(&path).unwrap_err().to_string()
            };
            let e = bad("nan", Some(n - 50), None);
            assert!(
                e.contains(&format!("vertex {}: 'y' is not finite", n - 50)),
                "{e}"
            );
            let e = bad("range", None, Some(n - 60));
            let msg = format!("face {}: vertex index {} out of range", n - 60, n + 5);
            assert!(e.contains(&msg), "{e}");
        }
    }

    /// Malformed binary files: each error names the file and the element or entry.
    #[test]
    fn malformed_binary_files_say_where() {
        let tri = |i: f64| vec![0.0, 1.0, i];
        let good = |faces: Vec<Vec<f64>>, count: &'static str| {
            vec![
                ("vertex", vertex_props(false), vertices(false)),
                ("face", vec![P::L("vertex_indices", count, "int")], faces),
            ]
        };
        let cases: Vec<(&str, Vec<u8>, &str)> = vec![
            (
                "range",
                std::fs::read(write("range", "binary_little_endian", &good(vec![tri(6.0)], "uchar"))).unwrap(),
                "face 0: vertex index 6 out of range (6 vertices)",
            ),
            (
                "negative",
                std::fs::read(write("negative", "binary_big_endian", &good(vec![tri(1.0), tri(-2.0)], "uchar"))).unwrap(),
                "face 1: vertex index -2 out of range",
            ),
            (
                "general_range",
                std::fs::read(write("general_range", "binary_little_endian", &good(vec![tri(9.0)], "int"))).unwrap(),
                "face 0: vertex index 9 out of range",
            ),
            (
                "two",
                std::fs::read(write("two", "binary_little_endian", &good(vec![vec![0.0, 1.0]], "uchar"))).unwrap(),
                "face 0 has 2 vertices (at least 3 needed)",
            ),
            (
                "truncated",
                {
                    let b = std::fs::read(write("trunc", "binary_little_endian", &good(vec![tri(1.0), tri(2.0)], "uchar"))).unwrap();
                    b[..b.len() - 3].to_vec()
                },
                "ends inside element 'face' (entry 1 of 2)",
            ),
            (
                "truncated_vertices",
                {
                    let b = std::fs::read(write("trunc_v", "binary_little_endian", &good(vec![], "uchar"))).unwrap();
                    b[..b.len() - 30].to_vec()
                },
                "ends inside element 'vertex'",
            ),
            (
                "nan",
                {
                    let mut v = vertices(false);
                    v[4][2] = f64::NAN;
                    let e = vec![("vertex", vertex_props(false), v)];
                    std::fs::read(write("nan", "binary_little_endian", &e)).unwrap()
                },
                "vertex 4: 'z' is not finite",
            ),
            (
                "no_x",
                b"ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float y\nproperty float z\nend_header\n\0\0\0\0\0\0\0\0".to_vec(),
                "PLY element 'vertex' has no numeric property 'x'",
            ),
            (
                "type",
                b"ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty half x\nend_header\n\0\0".to_vec(),
                "PLY element 'vertex': unknown property type 'half'",
            ),
            (
                "float_list",
                b"ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar float vertex_indices\nend_header\n\x03\0\0\0\0\0\0\0\0\0\0\0\0".to_vec(),
                "'vertex_indices' is not an integer list",
            ),
        ];
        for (name, bytes, msg) in cases {
            let path = temp_dir("ply_binary").join(format!("bad_{name}.ply"));
            std::fs::write(&path, &bytes).unwrap();
            let e = ply::load(&path).unwrap_err().to_string();
            assert!(
                e.contains(msg) && e.contains(&format!("bad_{name}.ply")),
                "{name}: {e}\n  wanted: {msg}"
            );
        }
    }
}
