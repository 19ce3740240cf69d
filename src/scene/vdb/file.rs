//! The outer structure of an OpenVDB file: header, metadata, grid descriptors and
//! each grid's transform (OpenVDB `io/Archive.cc`, `io/File.cc`,
//! `io/GridDescriptor.cc`, `math/Maps.h`; file format versions 222-225, written by
//! OpenVDB 3.0 and later).
//!
//! All values are little-endian. Header: the magic `0x56444220` as an i64, the
//! format version (u32), the library's major and minor version (u32 each), a byte
//! saying whether grids carry offsets, a 36-character UUID, the file's metadata, the
//! grid count (i32) and one descriptor per grid: unique name, type name (suffixed
//! `_HalfFloat` when values are stored as 16-bit floats), instance parent name
//! (strings are a u32 length and bytes), and the i64 offsets of the grid, of its
//! value buffers and of its end. At a grid's offset: compression flags (u32), the
//! grid's metadata, its transform (a map type name and the map's f64s), then the
//! tree ([`super::tree`]).

use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use glam::{DMat4, DVec3, DVec4};

/// `OPENVDB_MAGIC`.
const MAGIC: i64 = 0x5644_4220;
/// The oldest format read: 222 (`FILE_VERSION_NODE_MASK_COMPRESSION`, OpenVDB 3.0)
/// moved compression flags into each grid and changed node layouts.
pub const OLDEST_VERSION: u32 = 222;

/// A file being read: position and length known, every read checked against what
/// remains, so that no size read from the file allocates more than the file holds.
pub struct Input {
    r: BufReader<File>,
    pos: u64,
    len: u64,
    /// For messages.
    pub path: String,
}

impl Input {
    pub fn open(path: &Path) -> Result<Input, String> {
        let shown = path.display().to_string();
        let f = File::open(path).map_err(|e| format!("cannot read {shown}: {e}"))?;
        let len = f
            .metadata()
            .map_err(|e| format!("cannot read {shown}: {e}"))?
            .len();
        Ok(Input {
            r: BufReader::with_capacity(1 << 16, f),
            pos: 0,
            len,
            path: shown,
        })
    }

    /// An error at the current position.
    pub fn err(&self, msg: impl std::fmt::Display) -> String {
        format!("{}: OpenVDB file, byte {}: {msg}", self.path, self.pos)
    }

    pub fn pos(&self) -> u64 {
        self.pos
    }

    pub fn remaining(&self) -> u64 {
        self.len - self.pos
    }

    pub fn seek(&mut self, pos: u64, what: &str) -> Result<(), String> {
        if pos > self.len {
            return Err(self.err(format!(
                "{what} is at byte {pos}, past the end of the {}-byte file (truncated?)",
                self.len
            )));
        }
        self.r.seek(SeekFrom::Start(pos)).map_err(|e| self.err(e))?;
        self.pos = pos;
        Ok(())
    }

    /// Fails unless `n` more bytes remain.
    pub fn need(&self, n: u64, what: &str) -> Result<(), String> {
        if n > self.remaining() {
            return Err(self.err(format!(
                "truncated: {what} needs {n} bytes, {} remain",
                self.remaining()
            )));
        }
        Ok(())
    }

    pub fn fill(&mut self, buf: &mut [u8], what: &str) -> Result<(), String> {
        self.need(buf.len() as u64, what)?;
        self.r
            .read_exact(buf)
            .map_err(|e| self.err(format!("{what}: {e}")))?;
        self.pos += buf.len() as u64;
        Ok(())
    }

    /// `n` bytes, allocated only once they are known to be in the file.
    pub fn bytes(&mut self, n: u64, what: &str) -> Result<Vec<u8>, String> {
        self.need(n, what)?;
        let mut v = vec![0u8; n as usize];
        self.fill(&mut v, what)?;
        Ok(v)
    }

    pub fn skip(&mut self, n: u64, what: &str) -> Result<(), String> {
        self.need(n, what)?;
        self.r
            .seek_relative(n as i64)
            .map_err(|e| self.err(format!("{what}: {e}")))?;
        self.pos += n;
        Ok(())
    }

    fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N], String> {
        let mut b = [0u8; N];
        self.fill(&mut b, what)?;
        Ok(b)
    }

    pub fn u8(&mut self, what: &str) -> Result<u8, String> {
        Ok(self.array::<1>(what)?[0])
    }

    pub fn u32(&mut self, what: &str) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.array(what)?))
    }

    pub fn i32(&mut self, what: &str) -> Result<i32, String> {
        Ok(i32::from_le_bytes(self.array(what)?))
    }

    pub fn i64(&mut self, what: &str) -> Result<i64, String> {
        Ok(i64::from_le_bytes(self.array(what)?))
    }

    pub fn f64(&mut self, what: &str) -> Result<f64, String> {
        Ok(f64::from_le_bytes(self.array(what)?))
    }

    /// A u32 length and that many bytes.
    pub fn string(&mut self, what: &str) -> Result<String, String> {
        let n = self.u32(what)?;
        let b = self.bytes(n as u64, what)?;
        Ok(String::from_utf8_lossy(&b).into_owned())
    }
}

/// One grid's entry in the file's table.
#[derive(Debug, Clone)]
pub struct Descriptor {
    /// The grid's name (the unique name less OpenVDB's `\x1e`-number suffix).
    pub name: String,
    pub unique_name: String,
    /// The tree type, `Tree_float_5_4_3` for a float grid, less `_HalfFloat`.
    pub type_name: String,
    /// Values stored as 16-bit floats.
    pub half: bool,
    /// Non-empty: the grid shares the tree of this grid (by unique name).
    pub instance_parent: String,
    pub grid_pos: u64,
}

/// The value type of a grid whose tree wavetrace reads (the standard 5-4-3 tree of
/// scalar reals), with its size in bytes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Scalar {
    Half,
    Float,
    Double,
}

impl Scalar {
    pub fn size(self) -> usize {
        match self {
            Scalar::Half => 2,
            Scalar::Float => 4,
            Scalar::Double => 8,
        }
    }

    /// The value at the start of `b` (at least `size` bytes).
    pub fn decode(self, b: &[u8]) -> f32 {
        match self {
            Scalar::Half => half::f16::from_le_bytes([b[0], b[1]]).to_f32(),
            Scalar::Float => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            Scalar::Double => {
                f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]) as f32
            }
        }
    }
}

impl Descriptor {
    /// The scalar type of a `Tree_<type>_5_4_3` tree, or None for other grids
    /// (vectors, integers, masks, points, other node sizes).
    pub fn scalar(&self) -> Option<Scalar> {
        match self.type_name.as_str() {
            "Tree_float_5_4_3" => Some(Scalar::Float),
            "Tree_double_5_4_3" => Some(Scalar::Double),
            "Tree_half_5_4_3" => Some(Scalar::Half),
            _ => None,
        }
    }

    /// How messages name the grid and its type.
    pub fn summary(&self) -> String {
        let t = self
            .type_name
            .strip_prefix("Tree_")
            .and_then(|t| t.strip_suffix("_5_4_3"))
            .unwrap_or(&self.type_name);
        format!("'{}' ({t})", self.name)
    }
}

/// The grid table of a file.
pub struct Header {
    pub grids: Vec<Descriptor>,
}

/// Reads the header, the file's metadata and every grid descriptor.
pub fn read_header(inp: &mut Input) -> Result<Header, String> {
    if inp.remaining() < 8 {
        return Err(inp.err(format!(
            "not an OpenVDB file: {} bytes, shorter than its header",
            inp.remaining()
        )));
    }
    let magic = inp.i64("the magic number")?;
    if magic != MAGIC {
        return Err(format!(
            "{}: not an OpenVDB file (its first 8 bytes are not the VDB magic number)",
            inp.path
        ));
    }
    let version = inp.u32("the format version")?;
    if version < OLDEST_VERSION {
        return Err(inp.err(format!(
            "file format version {version}: written by OpenVDB older than 3.0; wavetrace \
             reads versions {OLDEST_VERSION} and later (re-save it with a current OpenVDB)"
        )));
    }
    inp.u32("the library major version")?;
    inp.u32("the library minor version")?;
    let offsets = inp.u8("the grid-offsets flag")?;
    if offsets == 0 {
        return Err(inp.err(
            "the file was written as a stream, without grid offsets; wavetrace reads VDB \
             files written with offsets (openvdb.write, vdb_tool, Houdini, Blender)",
        ));
    }
    inp.skip(36, "the file's UUID")?;
    skip_metadata(inp, "the file's metadata")?;
    let count = inp.i32("the grid count")?;
    // A descriptor takes at least 3 strings and 3 offsets: 36 bytes.
    if count < 0 || count as u64 * 36 > inp.remaining() {
        return Err(inp.err(format!(
            "a grid count of {count} that the file's {} remaining bytes cannot hold",
            inp.remaining()
        )));
    }
    let mut grids = Vec::with_capacity(count as usize);
    for i in 0..count {
        let unique_name = inp.string("a grid name")?;
        let mut type_name = inp.string("a grid type")?;
        let half = type_name.ends_with("_HalfFloat");
        if half {
            type_name.truncate(type_name.len() - "_HalfFloat".len());
        }
        let instance_parent = inp.string("a grid's instance parent")?;
        let mut pos = [0u64; 3];
        for (k, what) in ["grid", "buffer", "end"].iter().enumerate() {
            let p = inp.i64("a grid offset")?;
            if p < 0 || p as u64 > inp.len {
                return Err(inp.err(format!(
                    "grid {i} ('{unique_name}'): its {what} offset {p} lies outside the \
                     {}-byte file (truncated?)",
                    inp.len
                )));
            }
            pos[k] = p as u64;
        }
        let [grid_pos, _, end_pos] = pos;
        if end_pos < grid_pos || end_pos < inp.pos() {
            return Err(inp.err(format!(
                "grid {i} ('{unique_name}'): offsets {grid_pos}..{end_pos} out of order"
            )));
        }
        let name = match unique_name.find('\u{1e}') {
            Some(k) => unique_name[..k].to_string(),
            None => unique_name.clone(),
        };
        grids.push(Descriptor {
            name,
            unique_name,
            type_name,
            half,
            instance_parent,
            grid_pos,
        });
        // The next descriptor follows this grid's data.
        inp.seek(end_pos, "the next grid descriptor")?;
    }
    Ok(Header { grids })
}

/// Skips a metadata table (a u32 count; per entry a name, a type name, a u32 size and
/// that many bytes); returns the string entries.
pub fn skip_metadata(inp: &mut Input, what: &str) -> Result<Vec<(String, String)>, String> {
    let count = inp.u32(what)?;
    // An entry takes at least 12 bytes.
    if count as u64 * 12 > inp.remaining() {
        return Err(inp.err(format!(
            "{what}: {count} entries that the remaining {} bytes cannot hold",
            inp.remaining()
        )));
    }
    let mut strings = Vec::new();
    for _ in 0..count {
        let name = inp.string(what)?;
        let type_name = inp.string(what)?;
        let size = inp.u32(what)? as u64;
        if type_name == "string" && size <= 4096 {
            let b = inp.bytes(size, what)?;
            strings.push((name, String::from_utf8_lossy(&b).into_owned()));
        } else {
            inp.skip(size, what)?;
        }
    }
    Ok(strings)
}

/// Reads a grid's transform: the index-to-world matrix acting on column vectors
/// (OpenVDB's matrices act on row vectors, `world = index * M`, so this is Mᵀ).
pub fn read_transform(inp: &mut Input, grid: &str) -> Result<DMat4, String> {
    let kind = inp.string("the grid's transform type")?;
    let vec3 = |inp: &mut Input| -> Result<DVec3, String> {
        Ok(DVec3::new(
            inp.f64("the transform")?,
            inp.f64("the transform")?,
            inp.f64("the transform")?,
        ))
    };
    let m = match kind.as_str() {
        // mScaleValues, mVoxelSize, mScaleValuesInverse, mInvScaleSqr, mInvTwiceScale
        "ScaleMap" | "UniformScaleMap" => {
            let scale = vec3(inp)?;
            inp.skip(4 * 24, "the transform")?;
            DMat4::from_scale(scale)
        }
        // mTranslation, then as ScaleMap.
        "ScaleTranslateMap" | "UniformScaleTranslateMap" => {
            let t = vec3(inp)?;
            let scale = vec3(inp)?;
            inp.skip(4 * 24, "the transform")?;
            DMat4::from_translation(t) * DMat4::from_scale(scale)
        }
        "TranslationMap" => DMat4::from_translation(vec3(inp)?),
        // A 4x4 f64 matrix, row-major, acting on row vectors.
        "AffineMap" | "UnitaryMap" => {
            let mut rows = [DVec4::ZERO; 4];
            for r in &mut rows {
                *r = DVec4::new(
                    inp.f64("the transform")?,
                    inp.f64("the transform")?,
                    inp.f64("the transform")?,
                    inp.f64("the transform")?,
                );
            }
            // Row r of OpenVDB's matrix is column r of ours.
            let m = DMat4::from_cols(rows[0], rows[1], rows[2], rows[3]);
            if m.row(3) != DVec4::W {
                return Err(inp.err(format!(
                    "grid {grid}: its {kind} is not affine (last column {:?})",
                    m.row(3)
                )));
            }
            m
        }
        "NonlinearFrustumMap" => {
            return Err(inp.err(format!(
                "grid {grid} has a frustum transform (NonlinearFrustumMap); wavetrace reads \
                 grids with linear transforms (resample it to a linear one)"
            )))
        }
        other => return Err(inp.err(format!("grid {grid}: unknown transform type '{other}'"))),
    };
    if !m.is_finite() || m.determinant().abs() < 1e-300 {
        return Err(inp.err(format!(
            "grid {grid}: its {kind} transform is not finite and invertible"
        )));
    }
    Ok(m)
}
