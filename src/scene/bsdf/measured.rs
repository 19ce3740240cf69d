//! `measured`: a measured material from the RGL database (`.bsdf` files; Dupuy and
//! Jakob 2018, "An Adaptive Parameterization for Efficient Material Acquisition and
//! Rendering"), as Mitsuba 3's `measured.cpp` reads, evaluates and samples it.
//! One-sided (black from behind: wrap it in `twosided` for both faces). GLSL:
//! `shaders/bsdf/measured.glsl`.
//!
//! | parameter | type | default |
//! |-----------|------|---------|
//! | `filename` | string | (required) an RGB `.bsdf` file |
//!
//! The file is a Mitsuba "tensor file" (`include/mitsuba/core/tensor.h`): the header
//! `tensor_file\0`, version 1.0, a field count, then per field its name, rank, type,
//! data offset and shape. Its fields: `description` (text), `jacobian` (one byte),
//! `theta_i` and `phi_i` (the incident directions tabulated, radians), `ndf` and
//! `sigma` (2-D: the microfacet distribution D and the projected area σ over the
//! unit square u = (sqrt(2θ/π), (φ + π) / 2π)), `vndf` (4-D: per incident direction,
//! the visible normals' density over u), `luminance` and `rgb` (4-D and 5-D: over the
//! square the VNDF warp maps to u, the luminance sampled first and the RGB value
//! f cos θo / (D / 4σ)). One or two `phi_i` make an isotropic material (normals
//! relative to φi); an anisotropic one whose `phi_i` span 2π / k (k = 2, 4) is
//! mirrored into that span. Spectral files (`spectra` + `wavelengths`) need a
//! spectral renderer, as in Mitsuba's RGB variants: use the database's RGB file.
//!
//! Evaluation, as Mitsuba: the half vector's u inverted through the VNDF warp gives
//! the sample-space point where `rgb` is interpolated (bilinearly in the square and
//! linearly in θi, φi), times D(m) / (4 σ(wi)). Sampling draws the luminance warp, then
//! the VNDF warp (Mitsuba's `Marginal2D` with `Continuous` = true: a conditional and a
//! marginal CDF of the bilinear interpolant per (φi, θi), interpolated between them);
//! its density is the VNDF's over u over the Jacobian 2π² u sin θm · 4 (wi·m), times the
//! luminance's. `tools/make_measured_bsdf.py` writes such files from an analytic model.
//!
//! The tables live in the scene's texel buffer (`place_tables`), each distinct file
//! once; the record holds where they start (`table[0].x`) and the file's hash
//! (`table[0].yz`) that finds them.
//!
//! ```xml
//! <bsdf type="measured"><string name="filename" value="cc_nothern_aurora_rgb.bsdf"/></bsdf>
//! ```

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use super::kinds::{self, Kind};
use super::{Bsdf, BsdfModel, Plugin, TestParams, WarpTest};
use crate::gpu::layout::BsdfRecord;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const KIND: &Kind = kinds::find("measured");

/// A measured material: its tables, shared by every BSDF naming the same file.
#[derive(Clone, PartialEq)]
pub struct Measured {
    pub data: Arc<MeasuredData>,
}

/// The prints a scene's dump shows: the file, not its tables.
impl std::fmt::Debug for Measured {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let d = &self.data;
        f.debug_struct("Measured")
            .field("file", &d.name)
            .field("description", &d.description)
            .field("phi_i", &d.phi_i.len())
            .field("theta_i", &d.theta_i.len())
            .field("isotropic", &d.isotropic)
            .finish()
    }
}

/// A 2-D table over the unit square: `w` x `h` values per slice, row-major (x
/// contiguous), slices after one another.
#[derive(Debug, Clone, PartialEq)]
pub struct Table2 {
    pub w: u32,
    pub h: u32,
    pub data: Vec<f32>,
}

/// Mitsuba's `Marginal2D<Float, 2, true>` (normalized, sampling enabled) for every
/// (φi, θi) slice: the density normalized to integrate to 1 over the square, the
/// marginal CDF of the rows (`h - 1` a slice) and each row's conditional CDF (`h` rows
/// of `w - 1`), as its constructor builds them.
#[derive(Debug, Clone, PartialEq)]
pub struct Warp2 {
    pub density: Table2,
    pub marginal: Vec<f32>,
    pub conditional: Vec<f32>,
}

/// The contents of a `.bsdf` file, checked, with the sampling CDFs built.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredData {
    /// The file's name, for messages.
    pub name: String,
    pub description: String,
    /// FNV-1a of the file's bytes: what the record names its tables by.
    pub key: u64,
    pub theta_i: Vec<f32>,
    pub phi_i: Vec<f32>,
    pub isotropic: bool,
    pub jacobian: bool,
    /// 2π over the span of `phi_i` (anisotropic), else 0.
    pub reduction: u32,
    pub ndf: Table2,
    pub sigma: Table2,
    pub vndf: Warp2,
    pub luminance: Warp2,
    /// [φi][θi][channel] slices of the `rgb` field.
    pub rgb: Table2,
}

pub const MITSUBA: Plugin = Plugin::new(
    PluginDoc::new(
        Family::Bsdf,
        Dialect::Mitsuba,
        "measured",
        "A measured material (RGL .bsdf file, Dupuy and Jakob 2018).",
        &[Param::new(
            "filename",
            "string",
            "",
            "the RGB .bsdf file (required)",
        )],
    ),
    mitsuba,
)
.warptest(WarpTest {
    kind: KIND,
    params: &[],
    make: warptest,
});

fn mitsuba(props: &Properties) -> Result<Bsdf, Error> {
    let name = props
        .string_opt("filename")?
        .ok_or_else(|| props.object_error("measured BSDF needs a 'filename'"))?;
    let path = props.resolve(&name).map_err(|tried| {
        props.error(
            "filename",
            format!("parameter 'filename': measured file {tried} not found"),
        )
    })?;
    let bytes = std::fs::read(&path).map_err(|e| {
        props.error(
            "filename",
            format!("parameter 'filename': {}: {e}", path.display()),
        )
    })?;
    let data = parse(&bytes, &path)
        .map_err(|e| props.error("filename", format!("parameter 'filename': {e}")))?;
    Ok(Bsdf::Measured(Measured {
        data: Arc::new(data),
    }))
}

/// `wavetrace warptest measured`: the anisotropic test file (a GGX conductor, α =
/// (0.15, 0.4), tabulated by tools/make_measured_bsdf.py, mirrored into a quarter of
/// the azimuths).
fn warptest(_: &TestParams) -> Bsdf {
    let bytes = include_bytes!("../../../tests/data/measured_aniso.bsdf");
    let data = parse(bytes, Path::new("measured_aniso.bsdf")).expect("the shipped test file");
    Bsdf::Measured(Measured {
        data: Arc::new(data),
    })
}

impl BsdfModel for Measured {
    fn kind(&self) -> &'static Kind {
        KIND
    }

    fn pack(&self, r: &mut BsdfRecord) {
        // table[0].x: where the tables start, written by `place_tables`.
        r.table[0] = [0, self.data.key as u32, (self.data.key >> 32) as u32, 0];
    }
}

/// One field of a tensor file.
struct Field<'a> {
    dtype: u8,
    shape: Vec<usize>,
    bytes: &'a [u8],
}

/// Mitsuba's `Struct::Type` numbers (tensor_io.py).
const UINT8: u8 = 1;
const FLOAT32: u8 = 10;

fn dtype_size(t: u8) -> Option<usize> {
    match t {
        1 | 2 => Some(1),
        3 | 4 | 9 => Some(2),
        5 | 6 | 10 => Some(4),
        7 | 8 | 11 => Some(8),
        _ => None,
    }
}

fn dtype_name(t: u8) -> &'static str {
    [
        "?", "uint8", "int8", "uint16", "int16", "uint32", "int32", "uint64", "int64", "float16",
        "float32", "float64",
    ]
    .get(t as usize)
    .copied()
    .unwrap_or("?")
}

/// Reads the fields of a tensor file (Mitsuba's `TensorFile`), checking that every
/// header and data range lies within the file.
fn tensor_fields(bytes: &[u8]) -> Result<HashMap<String, Field<'_>>, String> {
    if bytes.len() < 12 + 2 + 4 {
        return Err(format!(
            "not a tensor file: {} bytes, fewer than its 18-byte header (truncated?)",
            bytes.len()
        ));
    }
    if &bytes[..12] != b"tensor_file\0" {
        return Err("not a tensor file (its header is not 'tensor_file')".into());
    }
    if bytes[12..14] != [1, 0] {
        return Err(format!(
            "tensor file version {}.{}, not 1.0",
            bytes[12], bytes[13]
        ));
    }
    let mut at = 14;
    let truncated = |what: &str| format!("truncated tensor file: it ends inside {what}");
    let mut take = |n: usize, what: &str| -> Result<&[u8], String> {
        let s = bytes.get(at..at + n).ok_or_else(|| truncated(what))?;
        at += n;
        Ok(s)
    };
    let count = u32::from_le_bytes(take(4, "the header")?.try_into().expect("4 bytes"));
    let mut fields = HashMap::new();
    for i in 0..count {
        let what = format!("the description of field {} of {count}", i + 1);
        let len = u16::from_le_bytes(take(2, &what)?.try_into().expect("2 bytes")) as usize;
        let name = String::from_utf8_lossy(take(len, &what)?).into_owned();
        let what = format!("the description of field '{name}'");
        let ndim = u16::from_le_bytes(take(2, &what)?.try_into().expect("2 bytes")) as usize;
        let dtype = take(1, &what)?[0];
        let offset = u64::from_le_bytes(take(8, &what)?.try_into().expect("8 bytes"));
        let mut shape = Vec::with_capacity(ndim.min(16));
        for _ in 0..ndim {
            let n = u64::from_le_bytes(take(8, &what)?.try_into().expect("8 bytes"));
            shape.push(usize::try_from(n).map_err(|_| format!("field '{name}': size {n}"))?);
        }
        let size = dtype_size(dtype)
            .ok_or_else(|| format!("field '{name}' has an unknown data type ({dtype})"))?;
        let total = shape
            .iter()
            .try_fold(size, |a, &n| a.checked_mul(n))
            .ok_or_else(|| format!("field '{name}': shape {shape:?} too large"))?;
        let start = usize::try_from(offset).unwrap_or(usize::MAX);
        let data = start
            .checked_add(total)
            .and_then(|end| bytes.get(start..end))
            .ok_or_else(|| {
                format!(
                    "truncated tensor file: field '{name}' ({shape:?} {}) needs bytes {offset}..{} of {}",
                    dtype_name(dtype),
                    offset as u128 + total as u128,
                    bytes.len()
                )
            })?;
        fields.insert(
            name,
            Field {
                dtype,
                shape,
                bytes: data,
            },
        );
    }
    Ok(fields)
}

fn floats(f: &Field) -> Vec<f32> {
    f.bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes(c.try_into().expect("4 bytes")))
        .collect()
}

/// Reads a `.bsdf` file's bytes (`path` names it in messages) as Mitsuba's
/// `measured` does, with its checks, each failure said by field.
pub fn parse(bytes: &[u8], path: &Path) -> Result<MeasuredData, String> {
    let file = path.display();
    let fields = tensor_fields(bytes).map_err(|e| format!("{file}: {e}"))?;
    let field = |name: &str| {
        fields.get(name).ok_or_else(|| {
            let mut have: Vec<&str> = fields.keys().map(|k| k.as_str()).collect();
            have.sort();
            format!(
                "{file}: not a measured BSDF: field '{name}' is missing (fields: {})",
                have.join(", ")
            )
        })
    };
    // Each field's type and rank, as Mitsuba's "Invalid file structure" check.
    let typed = |name: &str, dtype: u8, rank: usize| -> Result<&Field, String> {
        let f = field(name)?;
        if f.dtype != dtype || f.shape.len() != rank {
            return Err(format!(
                "{file}: field '{name}' is {} of shape {:?}; a measured BSDF needs {} of rank {rank}",
                dtype_name(f.dtype),
                f.shape,
                dtype_name(dtype)
            ));
        }
        Ok(f)
    };
    let shape_err = |name: &str, f: &Field, want: String| {
        format!(
            "{file}: field '{name}' has shape {:?}; expected {want}",
            f.shape
        )
    };
    let description = typed("description", UINT8, 1)?;
    let theta_i = typed("theta_i", FLOAT32, 1)?;
    let phi_i = typed("phi_i", FLOAT32, 1)?;
    if fields.contains_key("wavelengths") {
        return Err(format!(
            "{file}: a spectral measurement (fields 'spectra', 'wavelengths'); wavetrace renders \
             in RGB, as Mitsuba's RGB variants, which refuse it too: use the material's RGB file"
        ));
    }
    let ndf = typed("ndf", FLOAT32, 2)?;
    let sigma = typed("sigma", FLOAT32, 2)?;
    let vndf = typed("vndf", FLOAT32, 4)?;
    let luminance = typed("luminance", FLOAT32, 4)?;
    let rgb = typed("rgb", FLOAT32, 5)?;
    let jacobian = typed("jacobian", UINT8, 1)?;
    let (np, nt) = (phi_i.shape[0], theta_i.shape[0]);
    if np == 0 || nt == 0 {
        return Err(format!(
            "{file}: 'phi_i' and 'theta_i' need at least one value each (found {np} and {nt})"
        ));
    }
    if jacobian.shape[0] != 1 {
        return Err(shape_err("jacobian", jacobian, "[1]".into()));
    }
    let per_direction = |name: &str, f: &Field| -> Result<(), String> {
        if f.shape[0] != np || f.shape[1] != nt {
            return Err(shape_err(
                name,
                f,
                format!("[{np} (phi_i), {nt} (theta_i), ...]"),
            ));
        }
        Ok(())
    };
    per_direction("vndf", vndf)?;
    per_direction("luminance", luminance)?;
    per_direction("rgb", rgb)?;
    let n = luminance.shape[2];
    if luminance.shape[3] != n {
        return Err(shape_err(
            "luminance",
            luminance,
            "a square last two dimensions".into(),
        ));
    }
    if rgb.shape[2] != 3 || rgb.shape[3] != n || rgb.shape[4] != n {
        return Err(shape_err(
            "rgb",
            rgb,
            format!("[{np}, {nt}, 3, {n}, {n}] (as 'luminance')"),
        ));
    }
    for (name, f) in [
        ("ndf", ndf),
        ("sigma", sigma),
        ("vndf", vndf),
        ("luminance", luminance),
    ] {
        let r = f.shape.len();
        if f.shape[r - 1] < 2 || f.shape[r - 2] < 2 {
            return Err(shape_err(
                name,
                f,
                "at least 2 x 2 values over the square".into(),
            ));
        }
    }
    let table = |f: &Field| {
        let r = f.shape.len();
        Table2 {
            w: f.shape[r - 1] as u32,
            h: f.shape[r - 2] as u32,
            data: floats(f),
        }
    };
    let phi_values = floats(phi_i);
    let theta_values = floats(theta_i);
    let isotropic = np <= 2;
    let reduction = if isotropic {
        0
    } else {
        (std::f32::consts::TAU / (phi_values[np - 1] - phi_values[0])).round() as u32
    };
    let vndf = warp(table(vndf)).map_err(|e| format!("{file}: field 'vndf': {e}"))?;
    let luminance =
        warp(table(luminance)).map_err(|e| format!("{file}: field 'luminance': {e}"))?;
    for (name, t) in [("vndf", &vndf.density), ("luminance", &luminance.density)] {
        if t.data.iter().any(|v| !v.is_finite()) {
            return Err(format!(
                "{file}: field '{name}' has a slice with no positive value or a value not finite"
            ));
        }
    }
    Ok(MeasuredData {
        name: path
            .file_name()
            .map_or_else(|| file.to_string(), |n| n.to_string_lossy().into_owned()),
        description: String::from_utf8_lossy(description.bytes).into_owned(),
        key: fnv1a(bytes),
        theta_i: theta_values,
        phi_i: phi_values,
        isotropic,
        jacobian: jacobian.bytes[0] != 0,
        reduction,
        ndf: table(ndf),
        sigma: table(sigma),
        vndf,
        luminance,
        rgb: table(rgb),
    })
}

fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf29ce484222325u64, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x100000001b3)
    })
}

/// Mitsuba's `Marginal2D<Float, Dim, true>` constructor with `normalize` on: per
/// slice, the conditional CDF of each row and the marginal CDF of the rows of the
/// bilinear interpolant (trapezoids, in double precision), and the density divided by
/// the integral.
fn warp(t: Table2) -> Result<Warp2, String> {
    let (w, h) = (t.w as usize, t.h as usize);
    let n = w * h;
    let slices = t.data.len() / n;
    let (sx, sy) = (0.5 / (w - 1) as f64, 0.5 / (h - 1) as f64);
    let mut marginal = Vec::with_capacity(slices * (h - 1));
    let mut conditional = Vec::with_capacity(slices * h * (w - 1));
    let mut density = Vec::with_capacity(t.data.len());
    let mut row_sum = vec![0f64; h];
    for s in 0..slices {
        let d = &t.data[s * n..(s + 1) * n];
        let cond_start = conditional.len();
        for (y, sum) in row_sum.iter_mut().enumerate() {
            let mut acc = 0f64;
            for x in 0..w - 1 {
                acc += sx * (d[y * w + x] as f64 + d[y * w + x + 1] as f64);
                conditional.push(acc as f32);
            }
            *sum = acc;
        }
        let marg_start = marginal.len();
        let mut acc = 0f64;
        for y in 0..h - 1 {
            acc += sy * (row_sum[y] + row_sum[y + 1]);
            marginal.push(acc as f32);
        }
        if d.iter().any(|v| *v < 0.0) {
            return Err(format!("slice {s} has a negative value"));
        }
        let norm = (1.0 / acc) as f32;
        conditional[cond_start..]
            .iter_mut()
            .for_each(|v| *v *= norm);
        marginal[marg_start..].iter_mut().for_each(|v| *v *= norm);
        density.extend(d.iter().map(|v| v * norm));
    }
    Ok(Warp2 {
        density: Table2 { data: density, ..t },
        marginal,
        conditional,
    })
}

/// Words of a header: counts, flags and where each table starts (from the header).
const HEADER: usize = 24;

impl MeasuredData {
    /// The words `shaders/bsdf/measured.glsl` reads (floats, integers by their bits):
    ///
    /// | word | content |
    /// |------|---------|
    /// | 0, 1 | the numbers of φi and θi |
    /// | 2 | 1: isotropic, 2: jacobian |
    /// | 3 | reduction (0, 1, 2, 4) |
    /// | 4 .. 11 | w, h of `ndf`, `sigma`, `vndf`, `luminance` (= `rgb`'s) |
    /// | 12 .. 22 | where (from word 0) `phi_i`, `theta_i`, `ndf`, `sigma`, the VNDF's density, marginal and conditional CDFs, the luminance's, and `rgb` start |
    pub fn words(&self) -> Vec<f32> {
        let u = f32::from_bits;
        let flags = self.isotropic as u32 | (self.jacobian as u32) << 1;
        let mut head = vec![
            u(self.phi_i.len() as u32),
            u(self.theta_i.len() as u32),
            u(flags),
            u(self.reduction),
        ];
        for t in [
            &self.ndf,
            &self.sigma,
            &self.vndf.density,
            &self.luminance.density,
        ] {
            head.extend([u(t.w), u(t.h)]);
        }
        let parts: [&[f32]; 11] = [
            &self.phi_i,
            &self.theta_i,
            &self.ndf.data,
            &self.sigma.data,
            &self.vndf.density.data,
            &self.vndf.marginal,
            &self.vndf.conditional,
            &self.luminance.density.data,
            &self.luminance.marginal,
            &self.luminance.conditional,
            &self.rgb.data,
        ];
        let mut body = Vec::new();
        for p in parts {
            head.push(u((HEADER + body.len()) as u32));
            body.extend_from_slice(p);
        }
        head.resize(HEADER, 0.0);
        head.extend(body);
        head
    }
}

/// Every measured model among `bsdfs` (wrappers and composites searched).
fn collect<'a>(bsdf: &'a Bsdf, out: &mut Vec<&'a MeasuredData>) {
    match bsdf {
        Bsdf::Measured(m) => out.push(&m.data),
        Bsdf::TwoSided(b)
        | Bsdf::Textured { bsdf: b, .. }
        | Bsdf::NormalMap { bsdf: b, .. }
        | Bsdf::Mask { bsdf: b, .. }
        | Bsdf::BumpMap { bsdf: b, .. } => collect(b, out),
        Bsdf::Blend { bsdfs, .. } | Bsdf::TwoSidedPair(bsdfs) => {
            bsdfs.iter().for_each(|b| collect(b, out))
        }
        _ => {}
    }
}

/// Appends the tables of the measured models among `bsdfs` to `words` (the scene's
/// texel words), each distinct file once, and writes where they start into the
/// records of kind `measured` among `records` (found by the file's hash).
pub fn place_tables(bsdfs: &[Bsdf], records: &mut [BsdfRecord], words: &mut Vec<f32>) {
    let mut models = Vec::new();
    bsdfs.iter().for_each(|b| collect(b, &mut models));
    let mut start: HashMap<u64, u32> = HashMap::new();
    for m in models {
        start.entry(m.key).or_insert_with(|| {
            let at = words.len() as u32;
            words.extend(m.words());
            at
        });
    }
    for r in records.iter_mut().filter(|r| r.kind == KIND.id) {
        let key = r.table[0][1] as u64 | (r.table[0][2] as u64) << 32;
        if let Some(&at) = start.get(&key) {
            r.table[0][0] = at;
        }
    }
}

/// The record of `bsdf` and the table words it reads (for a BSDF tested alone, as
/// `wavetrace warptest` and the tests' probes do; empty for models without tables).
pub fn record_with_tables(bsdf: &Bsdf) -> (BsdfRecord, Vec<f32>) {
    let mut rec = BsdfRecord::from(bsdf);
    let mut words = Vec::new();
    place_tables(
        std::slice::from_ref(bsdf),
        std::slice::from_mut(&mut rec),
        &mut words,
    );
    (rec, words)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn repo(p: &str) -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
    }

    fn iso() -> Vec<u8> {
        std::fs::read(repo("tests/data/measured_iso.bsdf")).expect("tests/data/measured_iso.bsdf")
    }

    #[test]
    fn reads_the_test_files() {
        let d = parse(&iso(), Path::new("iso.bsdf")).expect("iso");
        assert!(d.isotropic && d.jacobian && d.reduction == 0);
        assert_eq!((d.phi_i.len(), d.theta_i.len()), (1, 6));
        let a = parse(
            &std::fs::read(repo("tests/data/measured_aniso.bsdf")).expect("aniso"),
            Path::new("aniso.bsdf"),
        )
        .expect("aniso");
        assert!(!a.isotropic && a.reduction == 4);
        // Each slice's marginal CDF ends at 1 (normalized), and its rows' ends match.
        let (w, h) = (a.vndf.density.w as usize, a.vndf.density.h as usize);
        for s in 0..a.phi_i.len() * a.theta_i.len() {
            let last = a.vndf.marginal[s * (h - 1) + h - 2];
            assert!((last - 1.0).abs() < 1e-5, "slice {s}: {last}");
            assert!(a.vndf.conditional[s * h * (w - 1)..].len() >= h * (w - 1));
        }
        let words = a.words();
        assert_eq!(words[0].to_bits(), 3);
        let rgb_at = words[22].to_bits() as usize;
        assert_eq!(words.len() - rgb_at, a.rgb.data.len());
    }

    /// Bad files: each error names the file and what is wrong.
    #[test]
    fn bad_files_are_named_with_their_fault() {
        let path = Path::new("dir/m.bsdf");
        let err = |b: &[u8]| parse(b, path).expect_err("a bad file");
        let good = iso();
        let e = err(b"hello");
        assert!(
            e.contains("dir/m.bsdf") && e.contains("not a tensor file"),
            "{e}"
        );
        let mut png = good.clone();
        png[..12].copy_from_slice(b"\x89PNG\r\n\x1a\n\0\0\0\0");
        assert!(err(&png).contains("not a tensor file"));
        // Cut inside the field table, and inside the data.
        assert!(
            err(&good[..40]).contains("truncated"),
            "{}",
            err(&good[..40])
        );
        let e = err(&good[..good.len() - 100]);
        assert!(e.contains("truncated") && e.contains("field 'rgb'"), "{e}");
        // A valid tensor file without the fields.
        let mut t = b"tensor_file\0\x01\x00".to_vec();
        t.extend(1u32.to_le_bytes());
        t.extend(1u16.to_le_bytes());
        t.extend(b"x");
        t.extend(1u16.to_le_bytes());
        t.push(FLOAT32);
        t.extend(40u64.to_le_bytes());
        t.extend(1u64.to_le_bytes());
        t.resize(44, 0);
        let e = err(&t);
        assert!(
            e.contains("field 'description' is missing") && e.contains("x"),
            "{e}"
        );
        // A wrong shape: rename `theta_i`'s size in the header to 5.
        let fields = tensor_fields(&good).expect("fields");
        assert_eq!(fields["theta_i"].shape, vec![6]);
        let name = b"\x07\x00theta_i";
        let at = good
            .windows(name.len())
            .position(|w| w == name)
            .expect("theta_i in the header");
        let mut bad = good.clone();
        bad[at + name.len() + 2 + 1 + 8] = 5;
        let e = err(&bad);
        assert!(
            e.contains("field 'vndf' has shape") && e.contains("5 (theta_i)"),
            "{e}"
        );
    }

    #[test]
    fn records_find_their_tables() {
        let d = Arc::new(parse(&iso(), Path::new("iso.bsdf")).expect("iso"));
        let m = Bsdf::Measured(Measured { data: d.clone() });
        let bsdfs = vec![
            Bsdf::default(),
            m.clone(),
            Bsdf::TwoSided(Box::new(m.clone())),
        ];
        let mut records: Vec<BsdfRecord> = bsdfs.iter().map(BsdfRecord::from).collect();
        let mut words = vec![0.0; 7];
        place_tables(&bsdfs, &mut records, &mut words);
        assert_eq!(
            words.len(),
            7 + d.words().len(),
            "one copy of the file's tables"
        );
        assert_eq!((records[1].table[0][0], records[2].table[0][0]), (7, 7));
    }
}
