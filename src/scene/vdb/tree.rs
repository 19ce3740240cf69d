//! An OpenVDB tree of scalar values: the standard 5-4-3 configuration (a root table
//! of 4096³-voxel internal nodes of 32³ children, each a 128³-voxel internal node of
//! 16³ children, each an 8³-voxel leaf), read as OpenVDB's `Tree::readTopology` and
//! `readBuffers` do (`tree/RootNode.h`, `InternalNode.h`, `LeafNode.h`,
//! `io/Compression.h`).
//!
//! Topology: an i32 buffer count; the root's background value, tile count and child
//! count (u32s), its tiles (i32 origin, value, active byte) and its children (i32
//! origin, then the node). An internal node: child mask, value mask (bit n of a mask is
//! bit n % 64 of u64 word n / 64; child n sits at local (x, y, z) with n = (x · dim +
//! y) · dim + z), then its values (tiles where the child bit is off), then its
//! children in order of n. A leaf's topology is its value mask. Buffers follow: for
//! every leaf in tree order (root children sorted by origin: x, then y, then z), its
//! value mask again and its 512 values.
//!
//! Values are "compressed values" (`io::readCompressedValues`): a byte telling how
//! inactive values are stored (0: as the background, 1: as minus the background, 2: as
//! one value stored here, 3-5: a selection mask chooses between two of those, 6: all
//! values stored), then the values, where mask compression is on (compression flag 2)
//! only the active ones, in a chunk: raw, zlib (flag 1) or blosc (flag 4), each behind
//! an i64 size that is negative (minus the byte count) for data stored raw. Grids
//! saved as half floats store chunk values as 16-bit floats; the background, tile and
//! inactive values stay full width.

use super::blosc;
use super::file::{Input, Scalar};

/// log2 of the voxels along a side of: a leaf, a level-1 node, a level-2 node.
const LEAF_LOG2: u32 = 3;
const NODE1_LOG2: u32 = LEAF_LOG2 + 4;
const NODE2_LOG2: u32 = NODE1_LOG2 + 5;

/// Compression flags (`io::COMPRESS_*`).
const COMPRESS_ZIP: u32 = 0x1;
const COMPRESS_ACTIVE_MASK: u32 = 0x2;
const COMPRESS_BLOSC: u32 = 0x4;

/// How a grid's values are stored.
#[derive(Debug, Clone, Copy)]
pub struct Encoding {
    pub compression: u32,
    /// The tree's value type (background, tiles, inactive values).
    pub scalar: Scalar,
    /// Chunk values stored as 16-bit floats.
    pub half: bool,
}

/// A block of constant value: `1 << log2` voxels along each side from `origin`.
#[derive(Debug, Clone, Copy)]
pub struct Tile {
    pub origin: [i64; 3],
    pub log2: u32,
    pub value: f32,
    pub active: bool,
}

/// A leaf: its origin and value mask.
#[derive(Debug, Clone)]
pub struct Leaf {
    pub origin: [i64; 3],
    pub mask: [u64; 8],
}

impl Leaf {
    /// The index-space bounds (inclusive) of the active voxels, if any.
    pub fn active_bounds(&self) -> Option<([i64; 3], [i64; 3])> {
        let mut b: Option<([i64; 3], [i64; 3])> = None;
        for n in ones(&self.mask) {
            let p = self.voxel(n);
            b = Some(match b {
                None => (p, p),
                Some((lo, hi)) => (
                    std::array::from_fn(|k| lo[k].min(p[k])),
                    std::array::from_fn(|k| hi[k].max(p[k])),
                ),
            });
        }
        b
    }

    /// Index coordinates of voxel `n` (n = (x · 8 + y) · 8 + z).
    pub fn voxel(&self, n: usize) -> [i64; 3] {
        let n = n as i64;
        [
            self.origin[0] + (n >> 6),
            self.origin[1] + ((n >> 3) & 7),
            self.origin[2] + (n & 7),
        ]
    }
}

/// Bit positions set in `mask`, ascending.
fn ones(mask: &[u64]) -> impl Iterator<Item = usize> + '_ {
    mask.iter().enumerate().flat_map(|(w, &bits)| {
        let mut b = bits;
        std::iter::from_fn(move || {
            if b == 0 {
                return None;
            }
            let t = b.trailing_zeros() as usize;
            b &= b - 1;
            Some(w * 64 + t)
        })
    })
}

fn bit(mask: &[u64], n: usize) -> bool {
    mask[n / 64] >> (n % 64) & 1 == 1
}

/// What a topology pass found.
pub struct Topology {
    pub background: f32,
    /// In buffer order; empty when leaves were not asked for.
    pub leaves: Vec<Leaf>,
}

/// Reads a tree's topology, calling `tile` for every tile that is active or differs
/// from the background, and collecting the leaves when `collect` is set. Leaves the
/// input at the tree's buffers.
pub fn read_topology(
    inp: &mut Input,
    enc: Encoding,
    collect: bool,
    tile: &mut dyn FnMut(Tile),
) -> Result<Topology, String> {
    inp.i32("the tree's buffer count")?;
    let vsize = enc.scalar.size();
    let background = value(inp, enc.scalar, "the background value")?;
    let tiles = inp.u32("the root's tile count")? as u64;
    let children = inp.u32("the root's child count")? as u64;
    // A root tile is 13 + value bytes; a child at least 12 + two 4 KiB masks.
    let least = tiles * (13 + vsize as u64) + children * (12 + 8192);
    if least > inp.remaining() {
        return Err(inp.err(format!(
            "truncated: the root's {tiles} tiles and {children} children need at least \
             {least} bytes, {} remain",
            inp.remaining()
        )));
    }
    // Root entries sit on the 4096-voxel lattice, one per key (OpenVDB's root table
    // is a map from aligned origin): so tiles and children never overlap, and no tile
    // is filled twice.
    let mut keys = std::collections::HashSet::new();
    let mut key = |inp: &Input, origin: [i64; 3], what: &str| -> Result<(), String> {
        let align = (1i64 << NODE2_LOG2) - 1;
        if origin.iter().any(|c| c & align != 0) {
            return Err(inp.err(format!(
                "{what} at {origin:?}, not on the 4096-voxel lattice"
            )));
        }
        if !keys.insert(origin) {
            return Err(inp.err(format!("two root entries at {origin:?}")));
        }
        Ok(())
    };
    for _ in 0..tiles {
        let origin = coord(inp, "a root tile")?;
        key(inp, origin, "a root tile")?;
        let v = value(inp, enc.scalar, "a root tile")?;
        let active = inp.u8("a root tile")? != 0;
        if active || v != background {
            tile(Tile {
                origin,
                log2: NODE2_LOG2,
                value: v,
                active,
            });
        }
    }
    let mut nodes: Vec<([i64; 3], Vec<Leaf>)> = Vec::new();
    let mut ctx = Ctx {
        enc,
        background,
        leaves: Vec::new(),
        collect,
    };
    for _ in 0..children {
        let origin = coord(inp, "a root child's origin")?;
        key(inp, origin, "a root child")?;
        internal(inp, &mut ctx, origin, 5, tile)?;
        nodes.push((origin, std::mem::take(&mut ctx.leaves)));
    }
    // Buffers come in the root table's order (a map sorted by origin).
    nodes.sort_by_key(|n| n.0);
    Ok(Topology {
        background,
        leaves: nodes.into_iter().flat_map(|n| n.1).collect(),
    })
}

struct Ctx {
    enc: Encoding,
    background: f32,
    leaves: Vec<Leaf>,
    collect: bool,
}

/// An internal node of `log2` children per side (5: level 2, 4: level 1) at `origin`.
fn internal(
    inp: &mut Input,
    ctx: &mut Ctx,
    origin: [i64; 3],
    log2: u32,
    tile: &mut dyn FnMut(Tile),
) -> Result<(), String> {
    let (n, child_log2, what) = if log2 == 5 {
        (1usize << 15, NODE1_LOG2, "a level-2 node")
    } else {
        (1usize << 12, LEAF_LOG2, "a level-1 node")
    };
    let child_mask = mask(inp, n / 64, what)?;
    let value_mask = mask(inp, n / 64, what)?;
    let mut values = vec![0.0f32; n];
    read_values(inp, ctx.enc, ctx.background, &mut values, &value_mask, what)?;
    let local = |i: usize| -> [i64; 3] {
        let d = log2 as usize;
        let i = i as i64;
        let m = (1i64 << d) - 1;
        [
            origin[0] + ((i >> (2 * d)) << child_log2),
            origin[1] + (((i >> d) & m) << child_log2),
            origin[2] + ((i & m) << child_log2),
        ]
    };
    for (i, &v) in values.iter().enumerate() {
        if bit(&child_mask, i) {
            continue;
        }
        let active = bit(&value_mask, i);
        if active || v != ctx.background {
            tile(Tile {
                origin: local(i),
                log2: child_log2,
                value: v,
                active,
            });
        }
    }
    for i in ones(&child_mask) {
        if log2 == 5 {
            internal(inp, ctx, local(i), 4, tile)?;
        } else {
            let m = mask(inp, 8, "a leaf's value mask")?;
            if ctx.collect {
                ctx.leaves.push(Leaf {
                    origin: local(i),
                    mask: m.try_into().expect("8 words"),
                });
            }
        }
    }
    Ok(())
}

/// Reads the buffers of `leaves` (in buffer order), calling `visit` with each leaf
/// and its 512 values.
pub fn read_buffers(
    inp: &mut Input,
    enc: Encoding,
    background: f32,
    leaves: &[Leaf],
    visit: &mut dyn FnMut(&Leaf, &[f32]),
) -> Result<(), String> {
    let mut values = vec![0.0f32; 512];
    for leaf in leaves {
        // The mask again: OpenVDB reads files by seeking past it and keeping the
        // topology's.
        inp.skip(64, "a leaf's value mask")?;
        read_values(inp, enc, background, &mut values, &leaf.mask, "a leaf")?;
        visit(leaf, &values);
    }
    Ok(())
}

fn coord(inp: &mut Input, what: &str) -> Result<[i64; 3], String> {
    Ok([
        inp.i32(what)? as i64,
        inp.i32(what)? as i64,
        inp.i32(what)? as i64,
    ])
}

fn value(inp: &mut Input, s: Scalar, what: &str) -> Result<f32, String> {
    let mut b = [0u8; 8];
    inp.fill(&mut b[..s.size()], what)?;
    Ok(s.decode(&b))
}

fn mask(inp: &mut Input, words: usize, what: &str) -> Result<Vec<u64>, String> {
    let b = inp.bytes(8 * words as u64, what)?;
    Ok(b.chunks_exact(8)
        .map(|c| u64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect())
}

/// `io::readCompressedValues`: fills `out` (one value per bit of `mask`).
fn read_values(
    inp: &mut Input,
    enc: Encoding,
    background: f32,
    out: &mut [f32],
    mask: &[u64],
    what: &str,
) -> Result<(), String> {
    let meta = inp.u8(what)?;
    if meta > 6 {
        return Err(inp.err(format!(
            "{what}: value-storage code {meta} (OpenVDB writes 0-6)"
        )));
    }
    let mut inactive1 = background;
    let mut inactive0 = if meta == 0 { background } else { -background };
    if matches!(meta, 2 | 4 | 5) {
        inactive0 = value(inp, enc.scalar, what)?;
        if meta == 5 {
            inactive1 = value(inp, enc.scalar, what)?;
        }
    }
    let selection = if matches!(meta, 3..=5) {
        Some(self::mask(inp, mask.len(), what)?)
    } else {
        None
    };
    let n = out.len();
    let count = if enc.compression & COMPRESS_ACTIVE_MASK != 0 && meta != 6 {
        mask.iter().map(|w| w.count_ones() as usize).sum()
    } else {
        n
    };
    let stored = if enc.half { Scalar::Half } else { enc.scalar };
    // OpenVDB's half reader reads nothing at all for no values.
    let bytes = if enc.half && count == 0 {
        Vec::new()
    } else {
        chunk(inp, enc.compression, count * stored.size(), what)?
    };
    let read = bytes.chunks_exact(stored.size()).map(|b| stored.decode(b));
    if count == n {
        for (o, v) in out.iter_mut().zip(read) {
            *o = v;
        }
    } else {
        let mut read = read;
        for (i, o) in out.iter_mut().enumerate() {
            *o = if bit(mask, i) {
                read.next().unwrap_or(background)
            } else if selection.as_deref().is_some_and(|s| bit(s, i)) {
                inactive1
            } else {
                inactive0
            };
        }
    }
    Ok(())
}

/// `io::readData`: `bytes` bytes of values, raw or in a zlib or blosc chunk.
fn chunk(inp: &mut Input, compression: u32, bytes: usize, what: &str) -> Result<Vec<u8>, String> {
    if compression & (COMPRESS_BLOSC | COMPRESS_ZIP) == 0 {
        return inp.bytes(bytes as u64, what);
    }
    let size = inp.i64(what)?;
    if size <= 0 {
        if size.unsigned_abs() != bytes as u64 {
            return Err(inp.err(format!(
                "{what}: an uncompressed chunk of {} bytes where {bytes} are expected",
                size.unsigned_abs()
            )));
        }
        return inp.bytes(bytes as u64, what);
    }
    let data = inp.bytes(size as u64, what)?;
    let decoded = if compression & COMPRESS_BLOSC != 0 {
        blosc::decompress(&data, bytes)
    } else {
        unzip(&data, bytes)
    };
    decoded.map_err(|e| inp.err(format!("{what}: {e}")))
}

/// A zlib stream that must inflate to exactly `bytes` bytes.
fn unzip(data: &[u8], bytes: usize) -> Result<Vec<u8>, String> {
    use std::io::Read;
    let mut out = Vec::with_capacity(bytes);
    let mut z = flate2::read::ZlibDecoder::new(data).take(bytes as u64 + 1);
    z.read_to_end(&mut out)
        .map_err(|e| format!("a zip chunk does not inflate: {e}"))?;
    if out.len() != bytes {
        return Err(format!(
            "a zip chunk inflates to {}{} bytes where {bytes} are expected",
            if out.len() > bytes { "more than " } else { "" },
            out.len().min(bytes)
        ));
    }
    Ok(out)
}
