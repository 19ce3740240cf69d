//! OpenVDB `.vdb` grids, read into the dense [`Grid`] a `gridvolume` gives the GPU.
//!
//! A file's grid is chosen by name (`gridvolume`'s `grid` parameter), by default the
//! first scalar grid named `density`, else the first scalar grid. Scalar grids are
//! the standard 5-4-3 trees of `float`, `double` or `half` values, stored raw, zip or
//! blosc (LZ4, zlib) compressed, with or without mask compression, full or half
//! precision: whatever OpenVDB 3.0 and later writes. The reader is our own
//! ([`file`], [`tree`], [`blosc`]): the Rust crate `vdb-rs` panics, `todo!()`s and
//! allocates whatever a header claims on damaged files, and builds C blosc.
//!
//! Conversion: OpenVDB keeps a voxel's value at its integer index coordinate, and
//! the grid's transform maps index space to world space. The dense grid covers the
//! bounding box of the active voxels and tiles, grown by one voxel on every side so
//! that trilinear interpolation falls off to the values around the active region as
//! OpenVDB's own box sampler does (those voxels hold the tree's values there: the
//! background, or inactive values). Every voxel in the box takes the tree's value,
//! active or not. The box is refused before anything is allocated for it when it
//! holds more than [`super::medium::MAX_GRID_VALUES`] voxels; the tree itself is read
//! in memory proportional to its size in the file, so no claim in a damaged file
//! allocates more than the file holds.

mod blosc;
mod file;
mod tree;

use std::path::Path;

use glam::{DMat4, DVec3, Mat4};

use super::medium::{Grid, MAX_GRID_VALUES};
use file::{Descriptor, Input};
use tree::{Encoding, Tile};

/// Reads the scalar grid `name` (default: the first scalar grid named `density`,
/// else the first scalar grid) of the OpenVDB file `path`. The returned grid's
/// `to_world` maps its unit cube to where the file's transform puts its voxels.
pub fn read_vdb(path: &Path, name: Option<&str>) -> Result<Grid, String> {
    let mut inp = Input::open(path)?;
    let header = file::read_header(&mut inp)?;
    let d = select(&header.grids, name, &inp.path)?;
    let grid = d.summary();
    let (enc, class, index_to_world) = open_grid(&mut inp, &header.grids, d, &grid)?;

    // First pass: the leaves and the active bounding box.
    let tree_pos = inp.pos();
    let (topo, lo, hi) = active_box(&mut inp, enc, &grid)?;
    let res: [i64; 3] = std::array::from_fn(|k| hi[k] - lo[k] + 1);
    let count = res.iter().map(|&r| r as u128).product::<u128>();
    if count > MAX_GRID_VALUES as u128 {
        return Err(format!(
            "{}: grid {grid} spans {} x {} x {} = {count} voxels over its active bounding \
             box (index {:?} to {:?}, with one voxel around it), more than wavetrace's \
             limit of {MAX_GRID_VALUES} voxels (one 128 MiB GPU buffer): crop or resample \
             the grid",
            inp.path,
            res[0],
            res[1],
            res[2],
            lo.map(|c| c + 1),
            hi.map(|c| c - 1),
        ));
    }

    // Second pass: tiles into the dense box, then the leaves' values.
    let background = topo.background;
    let mut data = vec![background; count as usize];
    let index = |p: [i64; 3]| -> Option<usize> {
        let q: [i64; 3] = std::array::from_fn(|k| p[k] - lo[k]);
        let inside = (0..3).all(|k| q[k] >= 0 && q[k] < res[k]);
        inside.then(|| ((q[2] * res[1] + q[1]) * res[0] + q[0]) as usize)
    };
    inp.seek(tree_pos, "the tree")?;
    tree::read_topology(&mut inp, enc, false, &mut |t: Tile| {
        let side = 1i64 << t.log2;
        let from: [i64; 3] = std::array::from_fn(|k| t.origin[k].max(lo[k]));
        let to: [i64; 3] = std::array::from_fn(|k| (t.origin[k] + side - 1).min(hi[k]));
        for z in from[2]..=to[2] {
            for y in from[1]..=to[1] {
                for x in from[0]..=to[0] {
                    if let Some(i) = index([x, y, z]) {
                        data[i] = t.value;
                    }
                }
            }
        }
    })?;
    tree::read_buffers(
        &mut inp,
        enc,
        background,
        &topo.leaves,
        &mut |leaf: &tree::Leaf, values: &[f32]| {
            for (n, &v) in values.iter().enumerate() {
                if let Some(i) = index(leaf.voxel(n)) {
                    data[i] = v;
                }
            }
        },
    )?;
    check_densities(&data, lo, res, &class, &grid, &inp.path)?;

    // Unit cube -> index space (voxel i's centre at (i + 0.5) / res is index lo + i)
    // -> world space.
    let unit_to_index = DMat4::from_translation(DVec3::from(lo.map(|c| c as f64)) - 0.5)
        * DMat4::from_scale(DVec3::from(res.map(|r| r as f64)));
    let to_world: Mat4 = (index_to_world * unit_to_index).as_mat4();
    if !to_world.is_finite() || to_world.determinant().abs() < 1e-30 {
        return Err(format!(
            "{}: grid {grid}'s placement ({res:?} voxels under its transform) is not \
             finite and invertible in single precision",
            inp.path
        ));
    }
    Ok(Grid {
        res: res.map(|r| r as u32),
        channels: 1,
        data,
        to_world,
    })
}

/// Reads grid `d`'s own header (compression, metadata, transform), and where it shares
/// the tree of another grid, that grid's: how its tree is encoded, its `class` and
/// its index-to-world transform. Leaves `inp` at the start of the tree.
fn open_grid(
    inp: &mut Input,
    grids: &[Descriptor],
    d: &Descriptor,
    grid: &str,
) -> Result<(Encoding, String, DMat4), String> {
    let scalar = d.scalar().expect("select returns scalar grids");
    inp.seek(d.grid_pos, "the grid")?;
    let mut compression = inp.u32("the grid's compression flags")?;
    let meta = file::skip_metadata(inp, "the grid's metadata")?;
    let class = meta
        .iter()
        .find(|(k, _)| k == "class")
        .map(|(_, v)| v.clone())
        .unwrap_or_else(|| "unknown".to_string());
    let index_to_world = file::read_transform(inp, grid)?;
    let mut half = d.half;
    if !d.instance_parent.is_empty() {
        // The tree is the parent's, after the parent's own header.
        let parent = grids
            .iter()
            .find(|g| g.unique_name == d.instance_parent && g.instance_parent.is_empty())
            .ok_or_else(|| {
                inp.err(format!(
                    "grid {grid} shares the tree of grid '{}', which the file does not hold",
                    d.instance_parent
                ))
            })?;
        if parent.scalar() != Some(scalar) {
            return Err(inp.err(format!(
                "grid {grid} shares the tree of grid {}, of another type",
                parent.summary()
            )));
        }
        inp.seek(parent.grid_pos, "the parent grid")?;
        compression = inp.u32("the grid's compression flags")?;
        file::skip_metadata(inp, "the grid's metadata")?;
        file::read_transform(inp, grid)?;
        half = parent.half;
    }
    let enc = Encoding {
        compression,
        scalar,
        half,
    };
    Ok((enc, class, index_to_world))
}

/// The tree's topology and the box of its active voxels and tiles, grown by one
/// voxel on every side (index space, inclusive).
fn active_box(
    inp: &mut Input,
    enc: Encoding,
    grid: &str,
) -> Result<(tree::Topology, [i64; 3], [i64; 3]), String> {
    let mut bounds = Bounds::default();
    let topo = tree::read_topology(inp, enc, true, &mut |t: Tile| {
        if t.active {
            let side = (1i64 << t.log2) - 1;
            bounds.add(t.origin, t.origin.map(|c| c + side));
        }
    })?;
    for leaf in &topo.leaves {
        if let Some((lo, hi)) = leaf.active_bounds() {
            bounds.add(lo, hi);
        }
    }
    let Some((lo, hi)) = bounds.0 else {
        return Err(format!("{}: grid {grid} has no active voxels", inp.path));
    };
    // One voxel around the active box.
    Ok((topo, lo.map(|c| c - 1), hi.map(|c| c + 1)))
}

/// Every value of a density grid is finite and >= 0.
fn check_densities(
    data: &[f32],
    lo: [i64; 3],
    res: [i64; 3],
    class: &str,
    grid: &str,
    path: &str,
) -> Result<(), String> {
    let Some(i) = data.iter().position(|v| !(v.is_finite() && *v >= 0.0)) else {
        return Ok(());
    };
    let i = i as i64;
    let p = [
        lo[0] + i % res[0],
        lo[1] + (i / res[0]) % res[1],
        lo[2] + i / (res[0] * res[1]),
    ];
    let hint = if class == "level set" {
        " (it is a level set, signed distances, not a density: convert it to a fog \
         volume first)"
    } else {
        ""
    };
    Err(format!(
        "{path}: grid {grid} has the value {} at index {p:?}; a density must be finite and \
         >= 0{hint}",
        data[i as usize]
    ))
}

/// The grid that `name` (or the default rule) picks.
fn select<'a>(
    grids: &'a [Descriptor],
    name: Option<&str>,
    path: &str,
) -> Result<&'a Descriptor, String> {
    let listing = || {
        if grids.is_empty() {
            "it holds no grids".to_string()
        } else {
            let names: Vec<String> = grids.iter().map(|g| g.summary()).collect();
            format!("its grids: {}", names.join(", "))
        }
    };
    let d = match name {
        Some(n) => grids
            .iter()
            .find(|g| g.name == n)
            .or_else(|| grids.iter().find(|g| g.unique_name == n))
            .ok_or_else(|| format!("{path}: no grid named '{n}'; {}", listing()))?,
        None => grids
            .iter()
            .find(|g| g.name == "density" && g.scalar().is_some())
            .or_else(|| grids.iter().find(|g| g.scalar().is_some()))
            .ok_or_else(|| format!("{path}: no scalar (float) grid; {}", listing()))?,
    };
    if d.scalar().is_none() {
        return Err(format!(
            "{path}: grid {} is not a scalar grid (tree type {}); a gridvolume reads \
             float, double or half grids",
            d.summary(),
            d.type_name
        ));
    }
    Ok(d)
}

/// A running bounding box in index space (inclusive).
#[derive(Default)]
struct Bounds(Option<([i64; 3], [i64; 3])>);

impl Bounds {
    fn add(&mut self, lo: [i64; 3], hi: [i64; 3]) {
        self.0 = Some(match self.0 {
            None => (lo, hi),
            Some((a, b)) => (
                std::array::from_fn(|k| a[k].min(lo[k])),
                std::array::from_fn(|k| b[k].max(hi[k])),
            ),
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::medium::read_vol;
    use glam::Vec3;

    fn media(name: &str) -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes/media")
            .join(name)
    }

    /// World position of voxel `i`'s centre.
    fn centre(g: &Grid, i: [u32; 3]) -> Vec3 {
        let u = (Vec3::from(i.map(|c| c as f32)) + 0.5) / Vec3::from(g.res.map(|r| r as f32));
        g.to_world.transform_point3(u)
    }

    fn at(g: &Grid, i: [u32; 3]) -> f32 {
        g.data[((i[2] * g.res[1] + i[1]) * g.res[0] + i[0]) as usize]
    }

    fn voxels(g: &Grid) -> impl Iterator<Item = [u32; 3]> + '_ {
        let r = g.res;
        (0..r[2]).flat_map(move |z| (0..r[1]).flat_map(move |y| (0..r[0]).map(move |x| [x, y, z])))
    }

    /// smoke.vdb (tools/make_vdb.py) holds smoke_border.vol's values on its voxel
    /// lattice: every voxel of the dense grid sits on a .vol voxel centre (to 1e-5 of a
    /// voxel) with the same value, and every non-zero .vol voxel is inside the grid,
    /// whose border voxels (the padding) are 0. So the two grids are the same function
    /// under trilinear interpolation, which the GPU render test confirms.
    #[test]
    fn smoke_vdb_is_the_vol_grid() {
        let vdb = read_vdb(&media("smoke.vdb"), None).unwrap();
        let vol = read_vol(&media("smoke_border.vol")).unwrap();
        assert_eq!(vdb.channels, 1);
        // Active voxels span x 6..=30, y 1..=30, z 1..=25 (OpenVDB's file_bbox), plus one
        // voxel around.
        assert_eq!(vdb.res, [27, 32, 27]);
        let mut seen = 0;
        for i in voxels(&vdb) {
            let p = centre(&vdb, i) * 32.0 - 0.5;
            let j = p.round();
            assert!((p - j).abs().max_element() < 1e-4, "voxel {i:?} at {p}");
            assert!(
                j.min_element() >= 0.0 && j.max_element() < 32.0,
                "voxel {i:?} at {j}"
            );
            let v = at(&vol, j.to_array().map(|c| c as u32));
            assert_eq!(at(&vdb, i), v, "voxel {i:?} = .vol voxel {j}");
            seen += (v > 0.0) as usize;
        }
        let nonzero = vol.data.iter().filter(|&&v| v > 0.0).count();
        assert_eq!(
            seen, nonzero,
            "every non-zero .vol voxel is in the .vdb grid"
        );
        let r = vdb.res;
        for i in voxels(&vdb) {
            if (0..3).any(|k| i[k] == 0 || i[k] == r[k] - 1) {
                assert_eq!(at(&vdb, i), 0.0, "padding voxel {i:?}");
            }
        }
    }

    /// smoke_grids.vdb: the default is the grid named density although temperature
    /// comes first; density is saved as half floats (values within half precision,
    /// 2^-11 relative); temperature is placed by an affine transform that turns it,
    /// read here back to its index coordinates.
    #[test]
    fn grids_are_chosen_by_name() {
        let path = media("smoke_grids.vdb");
        let smoke = read_vdb(&media("smoke.vdb"), None).unwrap();
        let density = read_vdb(&path, None).unwrap();
        assert_eq!(density.res, smoke.res);
        assert!(density.to_world.abs_diff_eq(smoke.to_world, 1e-6));
        for (a, b) in density.data.iter().zip(&smoke.data) {
            assert!((a - b).abs() <= b * 4.9e-4 + 6e-8, "half {a} vs {b}");
        }
        assert_eq!(read_vdb(&path, Some("density")).unwrap(), density);

        let t = read_vdb(&path, Some("temperature")).unwrap();
        assert_eq!(t.res, smoke.res);
        // Index (i, j, k) -> world (-j, i, k) / 16 + (1, 2, 3).
        for i in voxels(&t) {
            let w = centre(&t, i);
            let index = Vec3::new(w.y - 2.0, -(w.x - 1.0), w.z - 3.0) * 16.0;
            let s = centre(&smoke, i) * 32.0 - 0.5;
            assert!(
                (index - s).abs().max_element() < 1e-3,
                "voxel {i:?}: {index} vs {s}"
            );
            let d = at(&smoke, i);
            let want = if d > 0.0 { 2.0 - d } else { 0.0 };
            assert!((at(&t, i) - want).abs() < 1e-6);
        }
    }

    #[test]
    fn tiles_fill_their_voxels() {
        let g = read_vdb(&media("smoke_grids.vdb"), Some("tiles")).unwrap();
        // Active: 0..=15 (tiles), 16..=23 (a tile), 30 (a voxel) in x; 0..=15 in y, z.
        assert_eq!(g.res, [33, 18, 18]);
        for i in voxels(&g) {
            let [x, y, z] = i.map(|c| c as i64 - 1);
            let want = if (0..16).contains(&x) && (0..16).contains(&y) && (0..16).contains(&z) {
                0.5
            } else if (16..24).contains(&x) && (0..8).contains(&y) && (0..8).contains(&z) {
                2.0
            } else if [x, y, z] == [30, 3, 3] {
                1.0
            } else {
                0.0
            };
            assert_eq!(at(&g, i), want, "index {:?}", [x, y, z]);
        }
    }

    #[test]
    fn wrong_choices_are_clear_errors() {
        let path = media("smoke_grids.vdb");
        let e = read_vdb(&path, Some("smoke")).unwrap_err();
        assert!(
            e.contains("smoke_grids.vdb")
                && e.contains("no grid named 'smoke'")
                && e.contains(
                    "'temperature' (float), 'density' (float), 'velocity' (vec3s), \
                     'tiles' (float), 'huge' (float)"
                ),
            "{e}"
        );
        let e = read_vdb(&path, Some("velocity")).unwrap_err();
        assert!(e.contains("'velocity' (vec3s) is not a scalar grid"), "{e}");
        // Refused before allocating 4098³ floats.
        let e = read_vdb(&path, Some("huge")).unwrap_err();
        assert!(
            e.contains("grid 'huge' (float) spans 4098 x 4098 x 4098 = 68820189192 voxels")
                && e.contains(&MAX_GRID_VALUES.to_string()),
            "{e}"
        );
    }

    /// A minimal VDB file written by hand: one float grid, uncompressed with mask
    /// compression, a UniformScaleMap of voxel size 0.5, the root `tiles` (origin,
    /// value, active) and one root child holding one leaf whose only active voxel is
    /// (1, 2, 3) = `value`; `class` as grid metadata.
    fn tiny_vdb(tiles: &[([i32; 3], f32, bool)], value: f32, class: Option<&str>) -> Vec<u8> {
        tiny_vdb_with(Tiny::default(), tiles, value, class)
    }

    /// How [`tiny_vdb_with`] stores values: zip chunks, a double tree, half-float
    /// chunks.
    #[derive(Clone, Copy, Default, Debug)]
    struct Tiny {
        zip: bool,
        double: bool,
        half: bool,
    }

    fn tiny_vdb_with(
        opt: Tiny,
        tiles: &[([i32; 3], f32, bool)],
        value: f32,
        class: Option<&str>,
    ) -> Vec<u8> {
        // A value of the tree's type (background, tiles).
        let full = |v: f32| -> Vec<u8> {
            if opt.double {
                (v as f64).to_le_bytes().to_vec()
            } else {
                v.to_le_bytes().to_vec()
            }
        };
        // A chunk of values: raw, or a zip chunk behind its i64 size; nothing at all
        // for no half values (as OpenVDB's half writer).
        let chunk = |b: &mut Vec<u8>, values: &[f32]| {
            if opt.half && values.is_empty() {
                return;
            }
            let raw: Vec<u8> = values
                .iter()
                .flat_map(|&v| {
                    if opt.half {
                        half::f16::from_f32(v).to_le_bytes().to_vec()
                    } else {
                        full(v)
                    }
                })
                .collect();
            if opt.zip && raw.is_empty() {
                b.extend_from_slice(&0i64.to_le_bytes());
            } else if opt.zip {
                use std::io::Write;
                let mut z = flate2::write::ZlibEncoder::new(Vec::new(), Default::default());
                z.write_all(&raw).unwrap();
                let z = z.finish().unwrap();
                b.extend_from_slice(&(z.len() as i64).to_le_bytes());
                b.extend_from_slice(&z);
            } else {
                b.extend_from_slice(&raw);
            }
        };
        fn string(b: &mut Vec<u8>, s: &str) {
            b.extend_from_slice(&(s.len() as u32).to_le_bytes());
            b.extend_from_slice(s.as_bytes());
        }
        let mut b = Vec::new();
        b.extend_from_slice(&0x5644_4220i64.to_le_bytes());
        for v in [224u32, 10, 0] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b.push(1);
        b.extend_from_slice(b"00000000-0000-0000-0000-000000000000");
        b.extend_from_slice(&0u32.to_le_bytes()); // file metadata
        b.extend_from_slice(&1i32.to_le_bytes());
        string(&mut b, "density");
        let tree = if opt.double {
            "Tree_double_5_4_3"
        } else {
            "Tree_float_5_4_3"
        };
        string(
            &mut b,
            &format!("{tree}{}", if opt.half { "_HalfFloat" } else { "" }),
        );
        string(&mut b, "");
        let offsets = b.len();
        b.extend_from_slice(&[0u8; 24]);
        let grid_pos = b.len() as i64;
        // COMPRESS_ACTIVE_MASK, COMPRESS_ZIP
        b.extend_from_slice(&(2u32 | opt.zip as u32).to_le_bytes());
        match class {
            Some(c) => {
                b.extend_from_slice(&1u32.to_le_bytes());
                string(&mut b, "class");
                string(&mut b, "string");
                string(&mut b, c);
            }
            None => b.extend_from_slice(&0u32.to_le_bytes()),
        }
        string(&mut b, "UniformScaleMap");
        for v in [0.5f64, 0.5, 0.5].iter().chain(&[0.0; 12]) {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b.extend_from_slice(&1i32.to_le_bytes()); // buffer count
        b.extend_from_slice(&full(0.0)); // background
        b.extend_from_slice(&(tiles.len() as u32).to_le_bytes());
        b.extend_from_slice(&1u32.to_le_bytes());
        for (o, v, active) in tiles {
            for c in o {
                b.extend_from_slice(&c.to_le_bytes());
            }
            b.extend_from_slice(&full(*v));
            b.push(*active as u8);
        }
        b.extend_from_slice(&[0u8; 12]); // the child at the origin
        let mask = |b: &mut Vec<u8>, bytes: usize, bit: usize| {
            let mut m = vec![0u8; bytes];
            m[bit / 8] |= 1 << (bit % 8);
            b.extend_from_slice(&m);
        };
        // Level 2: child 0, no tiles active, inactive values the background (code 0).
        mask(&mut b, 4096, 0);
        b.extend_from_slice(&[0u8; 4096]);
        b.push(0);
        chunk(&mut b, &[]);
        mask(&mut b, 512, 0);
        b.extend_from_slice(&[0u8; 512]);
        b.push(0);
        chunk(&mut b, &[]);
        let voxel = (1 << 6) + (2 << 3) + 3;
        mask(&mut b, 64, voxel);
        // The leaf's buffer: its mask, code 0, its one active value.
        mask(&mut b, 64, voxel);
        b.push(0);
        chunk(&mut b, &[value]);
        let end = b.len() as i64;
        for (k, v) in [grid_pos, grid_pos, end].iter().enumerate() {
            b[offsets + 8 * k..offsets + 8 * k + 8].copy_from_slice(&v.to_le_bytes());
        }
        b
    }

    /// Hand-written files: the uncompressed, mask-compressed path and a scale map;
    /// root entries that overlap or leave the 4096-voxel lattice (which could make
    /// tile filling quadratic), a tile count the file cannot hold, negative values.
    #[test]
    fn hand_written_files() {
        let dir = crate::scene::testutil::temp_dir("vdb_tiny");
        let p = dir.join("tiny.vdb");
        let read = |bytes: Vec<u8>| {
            std::fs::write(&p, bytes).unwrap();
            read_vdb(&p, None)
        };
        let g = read(tiny_vdb(&[], 0.5, None)).unwrap();
        assert_eq!(g.res, [3, 3, 3]);
        assert_eq!(g.data.iter().sum::<f32>(), 0.5);
        assert_eq!(at(&g, [1, 1, 1]), 0.5);
        // Voxel (1, 2, 3) at world (1, 2, 3) / 2.
        assert!(centre(&g, [1, 1, 1]).abs_diff_eq(Vec3::new(0.5, 1.0, 1.5), 1e-6));
        // An inactive root tile of another value far away changes nothing.
        let far = read(tiny_vdb(&[([8192, 0, 0], 3.0, false)], 0.5, None)).unwrap();
        assert_eq!(far, g);
        let inactive = ([4096, 0, 0], 1.0, false);
        for (tiles, want) in [
            (vec![inactive, inactive], "two root entries at [4096, 0, 0]"),
            (
                vec![([0, 0, 0], 1.0, false)],
                "two root entries at [0, 0, 0]",
            ),
            (
                vec![([4095, 0, 0], 1.0, false)],
                "not on the 4096-voxel lattice",
            ),
        ] {
            let e = read(tiny_vdb(&tiles, 0.5, None)).unwrap_err();
            assert!(e.contains(want), "{e}");
        }
        let mut absurd = tiny_vdb(&[], 0.5, None);
        let at_count = absurd.len() - (12 + 4096 * 2 + 1 + 512 * 2 + 1 + 64 * 2 + 1 + 4) - 8;
        absurd[at_count..at_count + 4].copy_from_slice(&1_000_000_000u32.to_le_bytes());
        let e = read(absurd).unwrap_err();
        assert!(
            e.contains("truncated") && e.contains("1000000000 tiles"),
            "{e}"
        );
        // Zip chunks, double trees, half-float chunks: the same grid.
        for opt in [
            Tiny {
                zip: true,
                ..Tiny::default()
            },
            Tiny {
                double: true,
                ..Tiny::default()
            },
            Tiny {
                half: true,
                ..Tiny::default()
            },
            Tiny {
                zip: true,
                double: true,
                half: true,
            },
        ] {
            let bytes = tiny_vdb_with(opt, &[([8192, 0, 0], 3.0, false)], 0.5, None);
            assert_eq!(read(bytes.clone()).unwrap(), g, "{opt:?}");
            if opt.zip {
                // The leaf's zip stream, damaged.
                let mut bad = bytes;
                let n = bad.len();
                bad[n - 3] ^= 0x55;
                let e = read(bad).unwrap_err();
                assert!(e.contains("zip chunk"), "{e}");
            }
        }
        let e = read(tiny_vdb(&[], -0.5, None)).unwrap_err();
        assert!(
            e.contains("-0.5 at index [1, 2, 3]") && !e.contains("level set"),
            "{e}"
        );
        let e = read(tiny_vdb(&[], -0.5, Some("level set"))).unwrap_err();
        assert!(e.contains("it is a level set"), "{e}");
    }

    /// Truncated and corrupted files: the first 400 cuts and every 211th after them,
    /// and 600 random flips of 1-3 bits, give a clear error or a grid, never a panic (nor, by construction, an allocation
    /// larger than the file or the grid limit).
    #[test]
    fn damaged_files_are_clear_errors() {
        let bytes = std::fs::read(media("smoke_grids.vdb")).unwrap();
        let dir = crate::scene::testutil::temp_dir("vdb_damaged");
        let p = dir.join("bad.vdb");
        let mut cuts: Vec<usize> = (0..400).collect();
        cuts.extend((400..bytes.len()).step_by(211));
        for cut in cuts {
            std::fs::write(&p, &bytes[..cut]).unwrap();
            let e = read_vdb(&p, None).unwrap_err();
            assert!(e.contains("bad.vdb"), "cut at {cut}: {e}");
        }
        let e = {
            std::fs::write(&p, &bytes[..30_000]).unwrap();
            read_vdb(&p, None).unwrap_err()
        };
        assert!(e.contains("truncated"), "{e}");
        let mut magic = bytes.clone();
        magic[1] = b'X';
        std::fs::write(&p, &magic).unwrap();
        assert!(read_vdb(&p, None)
            .unwrap_err()
            .contains("not an OpenVDB file"));
        let mut old = bytes.clone();
        old[8] = 221;
        std::fs::write(&p, &old).unwrap();
        assert!(read_vdb(&p, None).unwrap_err().contains("older than 3.0"));
        // Byte flips, from a fixed-seed generator, over the header, the density grid
        // and the rest.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for _ in 0..600 {
            let mut bad = bytes.clone();
            for _ in 0..1 + next() % 3 {
                let i = (next() % bad.len() as u64) as usize;
                bad[i] ^= 1 << (next() % 8);
            }
            std::fs::write(&p, &bad).unwrap();
            for name in [None, Some("tiles")] {
                if let Ok(g) = read_vdb(&p, name) {
                    assert!(g.data.len() as u64 <= MAX_GRID_VALUES);
                }
            }
        }
    }
}
