//! `sdfgrid`: Mitsuba 3's signed-distance grid. A single-channel `.vol` grid of
//! distance samples (the gridvolume file format; its bounding box is ignored, as in
//! Mitsuba) on the unit cube [0, 1]^3, sample (x, y, z) at (x, y, z) / (res - 1), that
//! `to_world` places in the scene. The surface is the zero set of the trilinear
//! interpolant of the samples.
//!
//! As Mitsuba 3.9 (src/shapes/sdfgrid.cpp) computes it: in each voxel the ray meets, the
//! interpolant along the ray is a cubic in t (Hansson-Söderlund, Evans, Akenine-Möller
//! 2022, "Ray Tracing of Signed Distance Function Grids", JCGT 11(3)), whose first root
//! is bracketed at the roots of its derivative and found by Newton's method safeguarded
//! by bisection (Marmitt et al. 2004), to 1e-5 in t. The geometric normal is the
//! interpolant's gradient; the shading normal is that (`normals` = `analytic`) or the
//! blend of the eight voxels' gradients around the nearest grid vertex (`smooth`, the
//! default; Hansson-Söderlund et al. 2022, sec. 5). There is no uv parameterization
//! (uv = 0) and no surface area: an sdfgrid cannot be an area emitter (Mitsuba's
//! documentation says so; wavetrace refuses one at load).
//!
//! On the GPU an sdfgrid is one primitive, the box of its unit cube in world (or group)
//! space, whose test walks the voxels along the ray (3-D DDA) front to back and solves
//! the cubic in each voxel that holds a sign change (`shaders/shape/intersect_sdfgrid.glsl`).
//! Its samples, an occupancy bit per voxel and a header live in the grid buffer beside
//! the media's grids ([`pack`]).
//!
//! ```xml
//! <shape type="sdfgrid">
//!     <string name="filename" value="torus_sdfgrid.vol"/>
//!     <string name="normals" value="smooth"/>
//!     <bsdf type="diffuse"/>
//! </shape>
//! ```

use std::path::Path;

use glam::{Mat4, Vec3};

use super::{Geometry, QuadricKind, TO_WORLD};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::{Dialect, Element};
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Shape,
    Dialect::Mitsuba,
    "sdfgrid",
    "A signed-distance grid (single-channel .vol) on the unit cube; no uvs, no area \
     emitter.",
    &[
        Param::new(
            "filename",
            "string",
            "",
            "the .vol grid of distances, one channel, at least 2 samples per axis (required)",
        ),
        Param::new(
            "normals",
            "string",
            "smooth",
            "shading normals: `smooth` (blended across voxels) or `analytic` (the gradient)",
        ),
        TO_WORLD,
        Param::new(
            "flip_normals",
            "boolean",
            "false",
            "read and without effect, as in Mitsuba's sdfgrid",
        ),
    ],
);

/// Words of the header in front of a grid's samples in the grid buffer: the world (or
/// group) to grid map as three rows of an affine 3x4 matrix, the resolution and the
/// flags, the box of the occupied voxels (see [`pack`]).
pub const HEADER_WORDS: usize = 24;

/// Header flag: smooth shading normals (else analytic).
pub const SDF_SMOOTH: u32 = 1;

/// The distance samples of an `sdfgrid` shape.
#[derive(Debug, Clone, PartialEq)]
pub struct SdfGrid {
    /// Samples per axis, each at least 2.
    pub res: [u32; 3],
    /// Sample (x, y, z) at `values[(z * res[1] + y) * res[0] + x]`.
    pub values: Vec<f32>,
    /// `normals` = `smooth`.
    pub smooth: bool,
    /// Where its header starts in the grid buffer (words; set when the scene adds it,
    /// and held by its quadric, [`QuadricKind::SdfGrid`]).
    pub offset: u32,
}

/// Where an sdfgrid's quadric finds its grid: its words in the grid buffer, and the box
/// of its occupied voxels in voxel coordinates (sample indices `lo` to `hi`), which
/// bounds its primitive and the voxel walk of a ray (the torus of Mitsuba's regression
/// suite fills 15% of its grid's volume).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SdfPlace {
    pub offset: u32,
    pub res: [u32; 3],
    pub lo: [u32; 3],
    pub hi: [u32; 3],
}

impl SdfPlace {
    /// The world (or group) space box of the occupied voxels under `to_world`.
    pub fn bounds(&self, to_world: &Mat4) -> (Vec3, Vec3) {
        let unit = |i: usize, v: u32| v as f32 / (self.res[i] - 1).max(1) as f32;
        let lo = Vec3::new(
            unit(0, self.lo[0]),
            unit(1, self.lo[1]),
            unit(2, self.lo[2]),
        );
        let hi = Vec3::new(
            unit(0, self.hi[0]),
            unit(1, self.hi[1]),
            unit(2, self.hi[2]),
        );
        bounds(&(*to_world * Mat4::from_translation(lo) * Mat4::from_scale(hi - lo)))
    }
}

impl SdfGrid {
    /// Its [`SdfPlace`]: offset, resolution and the box of the occupied voxels.
    pub fn place(&self) -> SdfPlace {
        let [vx, vy, vz] = self.voxels();
        let mut lo = [u32::MAX; 3];
        let mut hi = [0u32; 3];
        for z in 0..vz {
            for y in 0..vy {
                for x in 0..vx {
                    if self.occupied(x, y, z) {
                        for (k, c) in [x, y, z].into_iter().enumerate() {
                            lo[k] = lo[k].min(c);
                            hi[k] = hi[k].max(c + 1);
                        }
                    }
                }
            }
        }
        SdfPlace {
            offset: self.offset,
            res: self.res,
            lo,
            hi,
        }
    }

    /// Voxels per axis (samples minus one).
    pub fn voxels(&self) -> [u32; 3] {
        self.res.map(|r| r - 1)
    }

    /// Words this grid takes in the grid buffer: header, samples, occupancy bits.
    pub fn words(&self) -> usize {
        let [x, y, z] = self.voxels().map(|v| v as usize);
        HEADER_WORDS + self.values.len() + (x * y * z).div_ceil(32)
    }

    /// Whether voxel (x, y, z) holds part of the surface: its corner samples are not
    /// all of one strict sign (Mitsuba's test: some >= 0 and some <= 0).
    pub fn occupied(&self, x: u32, y: u32, z: u32) -> bool {
        let (mut nonneg, mut nonpos) = (false, false);
        for c in 0..8u32 {
            let v = self.value(x + (c & 1), y + ((c >> 1) & 1), z + (c >> 2));
            nonneg |= v >= 0.0;
            nonpos |= v <= 0.0;
        }
        nonneg && nonpos
    }

    fn value(&self, x: u32, y: u32, z: u32) -> f32 {
        self.values[((z * self.res[1] + y) * self.res[0] + x) as usize]
    }
}

/// Reads an `sdfgrid`'s parameters and its grid file.
pub fn mitsuba(el: &Element, props: &Properties) -> Result<Geometry, Error> {
    let to_world = props.transform("to_world")?;
    let smooth = match props.string("normals", "smooth")?.as_str() {
        "smooth" => true,
        "analytic" => false,
        other => {
            return Err(props.error(
                "normals",
                format!("normals \"{other}\" is none of \"analytic\", \"smooth\""),
            ))
        }
    };
    let name = props.string_opt("filename")?.ok_or_else(|| {
        props.object_error("an sdfgrid needs a 'filename' (a single-channel .vol grid)")
    })?;
    let path = el
        .resolve(&name)
        .map_err(|tried| props.error("filename", format!("grid file {tried} not found")))?;
    let (res, values) = read(&path).map_err(|e| props.error("filename", e))?;
    let grid = SdfGrid {
        res,
        values,
        smooth,
        offset: 0,
    };
    let any = (0..res[2] - 1)
        .any(|z| (0..res[1] - 1).any(|y| (0..res[0] - 1).any(|x| grid.occupied(x, y, z))));
    if !any {
        return Err(props.error(
            "filename",
            format!(
                "{}: no voxel of the grid holds a sign change (Mitsuba: \"SDFGrid should at least have one non-empty voxel\")",
                path.display()
            ),
        ));
    }
    if !(to_world.is_finite()
        && to_world.row(3) == glam::Vec4::W
        && to_world.determinant().abs() > 0.0)
    {
        return Err(props.error(
            "to_world",
            "an sdfgrid's to_world must be finite, affine and invertible",
        ));
    }
    Ok(Geometry::SdfGrid(Box::new(grid), to_world))
}

/// Reads a Mitsuba `.vol` file of one channel (version 3, float32): resolution and
/// samples. Negative values are distances inside the surface, so unlike a medium's
/// grid they are welcome here; non-finite ones are not.
pub fn read(path: &Path) -> Result<([u32; 3], Vec<f32>), String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let bad = |what: String| format!("{}: not an sdfgrid .vol grid: {what}", path.display());
    if bytes.len() < 48 || &bytes[0..3] != b"VOL" {
        return Err(bad(
            "missing the 'VOL' header or shorter than its 48 bytes".into()
        ));
    }
    let int = |i: usize| i32::from_le_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    if bytes[3] != 3 || int(4) != 1 {
        return Err(bad(format!(
            "version {} encoding {} (only version 3 with float32 values is read, as in Mitsuba 3)",
            bytes[3],
            int(4)
        )));
    }
    let (xr, yr, zr, ch) = (int(8), int(12), int(16), int(20));
    if ch != 1 {
        return Err(bad(format!(
            "{ch} channels, an sdfgrid has 1 (Mitsuba: \"has {ch} channels, expected 1\")"
        )));
    }
    if xr < 2 || yr < 2 || zr < 2 {
        return Err(bad(format!(
            "resolution {xr} x {yr} x {zr}: an sdfgrid needs at least 2 samples per axis (one voxel)"
        )));
    }
    let count = [yr, zr]
        .iter()
        .try_fold(xr as u64, |n, &k| n.checked_mul(k as u64))
        .filter(|&n| n <= crate::scene::medium::MAX_GRID_VALUES)
        .ok_or_else(|| {
            bad(format!(
                "{xr} x {yr} x {zr} values is more than wavetrace accepts ({})",
                crate::scene::medium::MAX_GRID_VALUES
            ))
        })? as usize;
    let need = 48 + 4 * count;
    if bytes.len() < need {
        return Err(bad(format!(
            "{} bytes, but {xr} x {yr} x {zr} float32 values need {need}",
            bytes.len()
        )));
    }
    let mut values = Vec::with_capacity(count);
    for (i, b) in bytes[48..need].chunks_exact(4).enumerate() {
        let v = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        if !v.is_finite() {
            return Err(bad(format!("value {v} at index {i} (need finite values)")));
        }
        values.push(v);
    }
    Ok(([xr as u32, yr as u32, zr as u32], values))
}

/// The world (or group) space box of the unit cube under `to_world`.
pub fn bounds(to_world: &Mat4) -> (Vec3, Vec3) {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for c in 0..8u32 {
        let corner = Vec3::new((c & 1) as f32, ((c >> 1) & 1) as f32, (c >> 2) as f32);
        let p = to_world.transform_point3(corner);
        lo = lo.min(p);
        hi = hi.max(p);
    }
    // Pad by a little of the extent, so rounding in the box tests never culls a ray
    // that grazes the grid's faces.
    let pad = (hi - lo) * 1e-5 + lo.abs().max(hi.abs()) * 1e-6;
    (lo - pad, hi + pad)
}

/// Appends grid `g` of the quadric `kind` = [`QuadricKind::SdfGrid`] placed by
/// `to_world` to the grid buffer `words` at its offset (which must be `words.len()`):
/// the header (world to voxel coordinates as three rows of a 3x4 matrix, i.e.
/// `(res - 1) * to_world^-1`; res x, y, z and the flags; the occupied voxels' box
/// [`SdfPlace::lo`], 0, [`SdfPlace::hi`], 0, as floats), the samples, and one
/// occupancy bit per voxel (voxel `i = (z * vy + y) * vx + x` at bit `i % 32` of word
/// `i / 32`).
pub fn pack(g: &SdfGrid, to_world: &Mat4, words: &mut Vec<f32>) {
    let scale = Mat4::from_scale(Vec3::from(g.voxels().map(|v| v as f32)));
    let m = scale * to_world.inverse();
    for r in 0..3 {
        words.extend_from_slice(&m.row(r).to_array());
    }
    words.extend(g.res.map(f32::from_bits));
    words.push(f32::from_bits(if g.smooth { SDF_SMOOTH } else { 0 }));
    let place = g.place();
    words.extend(place.lo.map(|v| v as f32));
    words.push(0.0);
    words.extend(place.hi.map(|v| v as f32));
    words.push(0.0);
    words.extend_from_slice(&g.values);
    let [vx, vy, vz] = g.voxels();
    let mut occ = vec![0u32; ((vx * vy * vz) as usize).div_ceil(32)];
    let mut i = 0usize;
    for z in 0..vz {
        for y in 0..vy {
            for x in 0..vx {
                if g.occupied(x, y, z) {
                    occ[i / 32] |= 1 << (i % 32);
                }
                i += 1;
            }
        }
    }
    words.extend(occ.iter().map(|&w| f32::from_bits(w)));
}

/// Appends every sdfgrid of `scene` to the empty grid buffer `words` ([`pack`]), each
/// at the offset its quadric holds.
pub fn pack_scene(scene: &crate::scene::Scene, words: &mut Vec<f32>) {
    let mut placed: Vec<(u32, &Mat4)> = scene
        .quadrics
        .iter()
        .filter_map(|q| match q.kind {
            QuadricKind::SdfGrid(place) => Some((place.offset, &q.to_world)),
            _ => None,
        })
        .collect();
    placed.sort_by_key(|&(offset, _)| offset);
    for (offset, to_world) in placed {
        let g = scene
            .sdfgrids
            .iter()
            .find(|g| g.offset == offset)
            .expect("every sdfgrid quadric has its grid (scene loader)");
        assert_eq!(
            words.len(),
            offset as usize,
            "sdfgrids lead the grid buffer"
        );
        pack(g, to_world, words);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vol(res: [i32; 3], ch: i32, values: &[f32]) -> Vec<u8> {
        let mut b = b"VOL\x03".to_vec();
        for v in [1, res[0], res[1], res[2], ch] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b.extend_from_slice(&[0u8; 24]);
        for v in values {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b
    }

    #[test]
    fn reads_one_channel_grids_and_refuses_others() {
        let dir = std::env::temp_dir().join(format!("wavetrace_sdf_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let ok = dir.join("ok.vol");
        let values: Vec<f32> = (0..8).map(|i| i as f32 - 3.5).collect();
        std::fs::write(&ok, vol([2, 2, 2], 1, &values)).unwrap();
        let (res, v) = read(&ok).unwrap();
        assert_eq!((res, v), ([2, 2, 2], values.clone()));
        let three = dir.join("three.vol");
        std::fs::write(&three, vol([2, 2, 2], 3, &[0.0; 24])).unwrap();
        assert!(read(&three).unwrap_err().contains("3 channels"));
        let flat = dir.join("flat.vol");
        std::fs::write(&flat, vol([2, 1, 2], 1, &[0.0; 4])).unwrap();
        assert!(read(&flat).unwrap_err().contains("at least 2 samples"));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn packs_header_samples_and_occupancy() {
        // Two voxels along x: the first holds the sign change, the second is outside.
        let g = SdfGrid {
            res: [3, 2, 2],
            values: vec![
                -1.0, 1.0, 2.0, -1.0, 1.0, 2.0, -1.0, 1.0, 2.0, -1.0, 1.0, 2.0,
            ],
            smooth: true,
            offset: 0,
        };
        assert!(g.occupied(0, 0, 0) && !g.occupied(1, 0, 0));
        let place = g.place();
        assert_eq!((place.lo, place.hi), ([0, 0, 0], [1, 1, 1]));
        let mut w = Vec::new();
        pack(&g, &Mat4::from_scale(Vec3::splat(2.0)), &mut w);
        assert_eq!(w.len(), g.words());
        // World (1, 1, 1) is the grid's centre: voxel coordinates (1, 0.5, 0.5).
        let p = Vec3::ONE.extend(1.0);
        let row = |r: usize| glam::Vec4::from_slice(&w[4 * r..4 * r + 4]).dot(p);
        assert_eq!([row(0), row(1), row(2)], [1.0, 0.5, 0.5]);
        assert_eq!(w[12].to_bits(), 3);
        assert_eq!(w[15].to_bits(), SDF_SMOOTH);
        assert_eq!(w[16..24], [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 0.0]);
        assert_eq!(w[HEADER_WORDS + 1], 1.0);
        assert_eq!(w[HEADER_WORDS + 12].to_bits(), 1);
    }
}
