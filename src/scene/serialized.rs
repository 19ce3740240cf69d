//! Mitsuba's `.serialized` meshes (Mitsuba 3.9, src/shapes/serialized.cpp; the format
//! of Mitsuba 0.5 and 0.6).
//!
//! A file holds one or more meshes one after another. Each starts with the format id
//! `0x041C` and the version (3 or 4) as little-endian `u16`s, followed by a zlib
//! stream of: `u32` flags (0x1 vertex normals, 0x2 uvs, 0x8 vertex colours, 0x1000
//! single or 0x2000 double precision), the mesh name as a NUL-terminated string
//! (version 4 only), the vertex and triangle counts as `u64`, positions, normals, uvs
//! and colours as arrays of `f32` (or `f64`), and the triangles as `u32` triples. The
//! file ends with the offset of each mesh (`u64`; `u32` in version 3) and their count
//! (`u32`), which is how `shape_index` finds mesh k > 0.
//!
//! Vertex colours are skipped (as Mitsuba does). Counts come from the file, so nothing
//! is allocated from them up front: arrays grow as the decompressed data arrives, and
//! a count the data does not back ends in an error naming what is missing.

use std::io::Read;
use std::path::Path;

use flate2::read::ZlibDecoder;
use glam::{Vec2, Vec3};

use super::{Error, Mesh};

const FORMAT_ID: u16 = 0x041C;
const HAS_NORMALS: u32 = 0x0001;
const HAS_UVS: u32 = 0x0002;
const HAS_COLORS: u32 = 0x0008;
const DOUBLE_PRECISION: u32 = 0x2000;

/// Loads mesh `shape_index` of a `.serialized` file.
pub fn load(path: &Path, shape_index: u32) -> Result<Mesh, Error> {
    let bytes = std::fs::read(path).map_err(|e| Error::file(path, format!("cannot read: {e}")))?;
    let fail = |msg: String| Error::file(path, msg);
    let version = header(&bytes, 0).map_err(|m| fail(m.into()))?;
    let start = if shape_index == 0 {
        0
    } else {
        mesh_offset(&bytes, version, shape_index).map_err(fail)?
    };
    if start != 0 {
        let v = header(&bytes, start).map_err(|m| fail(format!("mesh {shape_index}: {m}")))?;
        if v != version {
            return Err(fail(format!(
                "mesh {shape_index} has version {v}, the file's first mesh {version}"
            )));
        }
    }
    let mut z = Stream {
        inner: ZlibDecoder::new(&bytes[start + 4..]),
    };
    read_mesh(&mut z, version, path).map_err(|m| fail(format!("mesh {shape_index}: {m}")))
}

/// Checks the `u16` format id and version at `at`; returns the version.
fn header(bytes: &[u8], at: usize) -> Result<u16, &'static str> {
    let word = |k: usize| {
        bytes
            .get(at + k..at + k + 2)
            .map(|b| u16::from_le_bytes([b[0], b[1]]))
    };
    match (word(0), word(2)) {
        (Some(FORMAT_ID), Some(v @ (3 | 4))) => Ok(v),
        (Some(FORMAT_ID), Some(_)) => Err("unsupported .serialized version (3 and 4 are read)"),
        _ => Err("not a Mitsuba .serialized mesh (no 0x041C header)"),
    }
}

/// Where mesh `index` (> 0) starts, from the dictionary at the end of the file.
fn mesh_offset(bytes: &[u8], version: u16, index: u32) -> Result<usize, String> {
    let n = bytes.len();
    let count = n
        .checked_sub(4)
        .map(|at| u32::from_le_bytes(bytes[at..].try_into().expect("4 bytes")))
        .ok_or("file too short for its mesh dictionary")?;
    if index >= count {
        return Err(format!(
            "shape_index {index} is out of range: the file holds {count} mesh(es)"
        ));
    }
    let width = if version == 4 { 8 } else { 4 };
    let back = (count - index) as usize * width + 4;
    let at = n
        .checked_sub(back)
        .ok_or("the mesh dictionary runs past the start of the file")?;
    let offset = if width == 8 {
        u64::from_le_bytes(bytes[at..at + 8].try_into().expect("8 bytes"))
    } else {
        u32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes")) as u64
    };
    if offset > usize::MAX as u64 || offset as usize >= at {
        return Err(format!(
            "mesh {index} starts at byte {offset}, past the mesh data"
        ));
    }
    Ok(offset as usize)
}

/// The decompressed stream of one mesh.
struct Stream<'a> {
    inner: ZlibDecoder<&'a [u8]>,
}

impl Stream<'_> {
    /// Exactly `n` bytes, grown as they arrive (never allocated from `n` up front).
    fn bytes(&mut self, n: u64, what: &str) -> Result<Vec<u8>, String> {
        let mut out = Vec::new();
        let got = (&mut self.inner)
            .take(n)
            .read_to_end(&mut out)
            .map_err(|e| match e.kind() {
                std::io::ErrorKind::UnexpectedEof => {
                    format!("the data ends inside {what} (the compressed stream is cut short)")
                }
                _ => format!("corrupt compressed data while reading {what}: {e}"),
            })?;
        if (got as u64) < n {
            return Err(format!(
                "the data ends inside {what} ({got} of {n} bytes present)"
            ));
        }
        Ok(out)
    }

    fn u32(&mut self, what: &str) -> Result<u32, String> {
        Ok(u32::from_le_bytes(
            self.bytes(4, what)?.try_into().expect("4 bytes"),
        ))
    }

    fn u64(&mut self, what: &str) -> Result<u64, String> {
        Ok(u64::from_le_bytes(
            self.bytes(8, what)?.try_into().expect("8 bytes"),
        ))
    }

    /// `count` × `dim` floats of the stored precision, as f32.
    fn floats(
        &mut self,
        count: u64,
        dim: u64,
        double: bool,
        what: &str,
    ) -> Result<Vec<f32>, String> {
        let width = if double { 8 } else { 4 };
        let raw = self.bytes(count * dim * width, what)?;
        Ok(if double {
            raw.chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")) as f32)
                .collect()
        } else {
            raw.chunks_exact(4)
                .map(|c| f32::from_le_bytes(c.try_into().expect("4 bytes")))
                .collect()
        })
    }
}

fn read_mesh(z: &mut Stream, version: u16, path: &Path) -> Result<Mesh, String> {
    let flags = z.u32("the flags")?;
    let mut name = Vec::new();
    if version == 4 {
        loop {
            let c = z.bytes(1, "the mesh name")?[0];
            if c == 0 {
                break;
            }
            if name.len() >= 4096 {
                return Err("the mesh name has no end (over 4096 bytes)".into());
            }
            name.push(c);
        }
    }
    let vertices = z.u64("the vertex count")?;
    let triangles = z.u64("the triangle count")?;
    // Mitsuba indexes vertices with u32; wavetrace numbers triangles with u32 too.
    if vertices > u32::MAX as u64 || triangles > u32::MAX as u64 {
        return Err(format!(
            "{vertices} vertices and {triangles} triangles: more than 2^32 - 1 of either is not supported"
        ));
    }
    let double = flags & DOUBLE_PRECISION != 0;
    let positions = z.floats(vertices, 3, double, "the vertex positions")?;
    let normals = if flags & HAS_NORMALS != 0 {
        z.floats(vertices, 3, double, "the vertex normals")?
    } else {
        Vec::new()
    };
    let uvs = if flags & HAS_UVS != 0 {
        z.floats(vertices, 2, double, "the texture coordinates")?
    } else {
        Vec::new()
    };
    if flags & HAS_COLORS != 0 {
        z.floats(vertices, 3, double, "the vertex colours")?;
    }
    let raw = z.bytes(triangles * 12, "the triangles")?;
    let mut mesh = Mesh {
        name: if name.is_empty() {
            path.display().to_string()
        } else {
            format!("{} ({})", path.display(), String::from_utf8_lossy(&name))
        },
        positions: positions
            .chunks_exact(3)
            .map(|p| Vec3::new(p[0], p[1], p[2]))
            .collect(),
        normals: normals
            .chunks_exact(3)
            .map(|p| Vec3::new(p[0], p[1], p[2]))
            .collect(),
        uvs: uvs.chunks_exact(2).map(|p| Vec2::new(p[0], p[1])).collect(),
        ..Mesh::default()
    };
    if let Some(i) = mesh.positions.iter().position(|p| !p.is_finite()) {
        return Err(format!("vertex {i}'s position is not finite"));
    }
    mesh.indices = raw
        .chunks_exact(12)
        .map(|c| {
            let w = |k: usize| u32::from_le_bytes(c[4 * k..4 * k + 4].try_into().expect("4 bytes"));
            [w(0), w(1), w(2)]
        })
        .collect();
    if let Some((t, bad)) = mesh
        .indices
        .iter()
        .enumerate()
        .find_map(|(t, ix)| ix.iter().find(|&&i| i as u64 >= vertices).map(|&i| (t, i)))
    {
        return Err(format!(
            "triangle {t} names vertex {bad}, past the {vertices} vertices"
        ));
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::testutil::temp_dir;
    use flate2::write::ZlibEncoder;
    use std::io::Write;

    /// One mesh's bytes: header and the zlib stream.
    fn mesh_bytes(
        version: u16,
        flags: u32,
        name: &str,
        pos: &[f32],
        uv: &[f32],
        tris: &[u32],
    ) -> Vec<u8> {
        let mut raw = Vec::new();
        raw.extend(flags.to_le_bytes());
        if version == 4 {
            raw.extend(name.as_bytes());
            raw.push(0);
        }
        raw.extend(((pos.len() / 3) as u64).to_le_bytes());
        raw.extend(((tris.len() / 3) as u64).to_le_bytes());
        for v in pos.iter().chain(uv) {
            if flags & DOUBLE_PRECISION != 0 {
                raw.extend((*v as f64).to_le_bytes());
            } else {
                raw.extend(v.to_le_bytes());
            }
        }
        for t in tris {
            raw.extend(t.to_le_bytes());
        }
        let mut z = ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        z.write_all(&raw).unwrap();
        let mut out = FORMAT_ID.to_le_bytes().to_vec();
        out.extend(version.to_le_bytes());
        out.extend(z.finish().unwrap());
        out
    }

    const TRI: [f32; 9] = [0., 0., 0., 1., 0., 0., 0., 1., 0.];

    #[test]
    fn reads_meshes_by_index_in_both_versions() {
        let dir = temp_dir("serialized");
        for version in [3u16, 4] {
            let a = mesh_bytes(
                version,
                0x1000 | HAS_UVS,
                "a",
                &TRI,
                &[0., 0., 1., 0., 0., 1.],
                &[0, 1, 2],
            );
            let quad = [0., 0., 1., 2., 0., 1., 2., 2., 1., 0., 2., 1.];
            let b = mesh_bytes(
                version,
                DOUBLE_PRECISION,
                "b",
                &quad,
                &[],
                &[0, 1, 2, 0, 2, 3],
            );
            let mut file = a.clone();
            file.extend(&b);
            if version == 4 {
                file.extend(0u64.to_le_bytes());
                file.extend((a.len() as u64).to_le_bytes());
            } else {
                file.extend(0u32.to_le_bytes());
                file.extend((a.len() as u32).to_le_bytes());
            }
            file.extend(2u32.to_le_bytes());
            let path = dir.join(format!("two_v{version}.serialized"));
            std::fs::write(&path, &file).unwrap();
            let m0 = load(&path, 0).unwrap();
            assert_eq!(
                (m0.positions.len(), m0.indices.len(), m0.uvs.len()),
                (3, 1, 3)
            );
            assert_eq!(m0.uvs[1], Vec2::new(1.0, 0.0));
            let m1 = load(&path, 1).unwrap();
            assert_eq!((m1.positions.len(), m1.indices.len()), (4, 2));
            assert_eq!(m1.positions[2], Vec3::new(2.0, 2.0, 1.0));
            assert!(m1.normals.is_empty() && m1.uvs.is_empty());
            let e = load(&path, 2).unwrap_err().to_string();
            assert!(e.contains("out of range: the file holds 2"), "{e}");
        }
    }

    #[test]
    fn hostile_files_are_refused() {
        let dir = temp_dir("serialized-bad");
        let check = |name: &str, bytes: &[u8], want: &str| {
            let path = dir.join(name);
            std::fs::write(&path, bytes).unwrap();
            let e = load(&path, 0).unwrap_err().to_string();
            assert!(e.contains(want) && e.contains(name), "{name}: {e}");
        };
        check("empty.serialized", b"", "no 0x041C header");
        check(
            "v9.serialized",
            &[0x1C, 0x04, 9, 0],
            "unsupported .serialized version",
        );
        let good = mesh_bytes(4, 0, "", &TRI, &[], &[0, 1, 2]);
        check(
            "cut.serialized",
            &good[..good.len() - 6],
            "the data ends inside",
        );
        check(
            "bad_index.serialized",
            &mesh_bytes(4, 0, "", &TRI, &[], &[0, 1, 7]),
            "names vertex 7",
        );
        check(
            "nan.serialized",
            &mesh_bytes(4, 0, "", &[f32::NAN; 9], &[], &[0, 1, 2]),
            "not finite",
        );
        // A header claiming 10^12 vertices is refused before anything is allocated.
        let mut raw = 0u32.to_le_bytes().to_vec();
        raw.push(0);
        raw.extend(1_000_000_000_000u64.to_le_bytes());
        raw.extend(1u64.to_le_bytes());
        let mut z = ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        z.write_all(&raw).unwrap();
        let mut huge = vec![0x1C, 0x04, 4, 0];
        huge.extend(z.finish().unwrap());
        check("huge.serialized", &huge, "more than 2^32 - 1");
        // A count the data does not back.
        let mut raw = 0u32.to_le_bytes().to_vec();
        raw.push(0);
        raw.extend(4_000_000_000u64.to_le_bytes());
        raw.extend(1u64.to_le_bytes());
        let mut z = ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        z.write_all(&raw).unwrap();
        let mut big = vec![0x1C, 0x04, 4, 0];
        big.extend(z.finish().unwrap());
        check(
            "big.serialized",
            &big,
            "the data ends inside the vertex positions",
        );
        let mut garbage = vec![0x1C, 0x04, 4, 0];
        garbage.extend([0x78, 0x9c, 0xff, 0xff, 0xff, 0xff, 0x00]);
        check("garbage.serialized", &garbage, "corrupt compressed data");
    }
}
