//! Partial renders: the film sums of some of a render's samples, with the record of
//! which render they belong to, in an OpenEXR file; and merging them.
//!
//! A render is a pure function of the scene, its options and the sample index: sample
//! `s` of a pixel draws the same random numbers in whatever range, batch, process or
//! machine it is rendered (for the same whole-render sample count, which the sampler's
//! patterns depend on: [`Renderer::set_sample_count`](super::Renderer::set_sample_count)).
//! The film keeps per pixel the filter-weighted sums Σ w L and Σ w ([`FilmSums`]), so
//! the film of a union of disjoint sample sets is the sum of their films.
//!
//! A partial file is an ordinary float32 EXR: the developed image (`R`, `G`, `B` and
//! `A` where the film keeps alpha, viewable anywhere) plus the sums (`sum.R`, `sum.G`,
//! `sum.B`, `sum.W`, `sum.A`), and two header attributes: `wavetrace.samples` in words
//! ("12 of 16 samples per pixel: 0..12") and `wavetrace.partial`, the JSON
//! [`RenderRecord`].
//!
//! Exactness. On the GPU each pixel's sum is a float32 left fold over its samples in
//! sample order (`film_gather.comp`), whatever the batches. Hence:
//! - continuing a render from the sums of samples `0..k` (resume) gives the sums of the
//!   uninterrupted render bit for bit;
//! - [`merge`] adds the parts' sums in the order of their ranges, `((P0 + P1) + P2)...`:
//!   bit for bit the unsplit render where that is the same summation, i.e. when every
//!   part after the first holds one sample; otherwise the regrouped float32 additions
//!   differ from the unsplit fold by rounding (a relative error of a few 1e-7 per
//!   part, far below the image's noise). Merges of the same parts are always the same
//!   bits, whatever order the files are given in.

use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};

use serde_json::{json, Value};
use sha2::{Digest, Sha256};

use super::film::{ExrExtras, FilmSums};
use crate::image;
use crate::scene::film::{ComponentFormat, Crop, FileFormat, PixelFormat};

/// A set of sample indices: sorted, disjoint, non-adjacent, non-empty ranges.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SampleRanges {
    ranges: Vec<Range<u32>>,
}

impl SampleRanges {
    /// The set of one range (empty if the range is).
    pub fn of(range: Range<u32>) -> SampleRanges {
        let mut s = SampleRanges::default();
        s.add(range);
        s
    }

    pub fn ranges(&self) -> &[Range<u32>] {
        &self.ranges
    }

    /// Samples in the set.
    pub fn count(&self) -> u64 {
        self.ranges.iter().map(|r| u64::from(r.end - r.start)).sum()
    }

    pub fn is_empty(&self) -> bool {
        self.ranges.is_empty()
    }

    /// The first range where `range` meets the set, if any.
    pub fn overlap(&self, range: &Range<u32>) -> Option<Range<u32>> {
        self.ranges
            .iter()
            .map(|r| r.start.max(range.start)..r.end.min(range.end))
            .find(|r| r.start < r.end)
    }

    /// Adds `range` (which may overlap the set).
    pub fn add(&mut self, range: Range<u32>) {
        if range.start >= range.end {
            return;
        }
        self.ranges.push(range);
        self.ranges.sort_by_key(|r| r.start);
        let mut merged: Vec<Range<u32>> = Vec::with_capacity(self.ranges.len());
        for r in self.ranges.drain(..) {
            match merged.last_mut() {
                Some(last) if r.start <= last.end => last.end = last.end.max(r.end),
                _ => merged.push(r),
            }
        }
        self.ranges = merged;
    }

    /// The samples of `0..total` not in the set.
    pub fn missing(&self, total: u32) -> SampleRanges {
        let mut out = SampleRanges::default();
        let mut at = 0;
        for r in &self.ranges {
            out.add(at..r.start.min(total));
            at = at.max(r.end);
        }
        out.add(at..total);
        out
    }

    /// Parses "A..B" or "A..B,C..D" ("none" or empty: no samples).
    pub fn parse(text: &str) -> Result<SampleRanges, String> {
        let mut s = SampleRanges::default();
        if text.trim() == "none" {
            return Ok(s);
        }
        for part in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let r = parse_range(part)?;
            if let Some(o) = s.overlap(&r) {
                return Err(format!("sample ranges overlap in {}..{}", o.start, o.end));
            }
            s.add(r);
        }
        Ok(s)
    }
}

impl fmt::Display for SampleRanges {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.ranges.is_empty() {
            return f.write_str("none");
        }
        let parts: Vec<String> = self
            .ranges
            .iter()
            .map(|r| format!("{}..{}", r.start, r.end))
            .collect();
        f.write_str(&parts.join(","))
    }
}

/// Parses a sample range "A..B" (samples A to B - 1, A < B).
pub fn parse_range(text: &str) -> Result<Range<u32>, String> {
    let bad = || format!("expected a sample range A..B (samples A to B-1), got '{text}'");
    let (a, b) = text.split_once("..").ok_or_else(bad)?;
    let a: u32 = a.trim().parse().map_err(|_| bad())?;
    let b: u32 = b.trim().parse().map_err(|_| bad())?;
    if a >= b {
        return Err(format!(
            "the sample range {a}..{b} is empty: A..B renders samples A to B-1"
        ));
    }
    Ok(a..b)
}

/// The SHA-256 of a file's bytes, in hex: what a partial records of its scene (the
/// scene file itself, not the meshes, textures or grids it names).
pub fn file_sha256(path: &Path) -> std::io::Result<String> {
    let bytes = std::fs::read(path)?;
    Ok(Sha256::digest(&bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect())
}

/// Which render a partial belongs to: all that decides its pixels (the scene file's
/// hash and `-D` defines, seed, integrator, sampler, film, the whole render's sample
/// count), what is needed to render the rest (`--resume`), and the samples it holds.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderRecord {
    /// The scene file (absolute when it was rendered), to load it again on resume.
    pub scene: PathBuf,
    /// [`file_sha256`] of the scene file.
    pub scene_sha256: String,
    /// `-D name=value` defines, in the order given.
    pub defines: Vec<(String, String)>,
    pub seed: u32,
    /// The command line's `--integrator`, `--sampler` and `--max-bounces` (`None`: the
    /// scene's), as given.
    pub integrator_option: Option<String>,
    pub sampler_option: Option<String>,
    pub max_bounces: Option<u32>,
    /// The command line's `--aov`, as `name:type` entries (`None`: none).
    pub aov_option: Option<String>,
    /// The command line's `--sensor` (`None`: the scene's first sensor).
    pub sensor: Option<u32>,
    /// The integrator, sampler and film with all their parameters, as the renderer
    /// resolved them: what merges compare.
    pub integrator: String,
    pub sampler: String,
    pub film: String,
    /// The whole render's samples per pixel (as the sampler rounds them).
    pub spp: u32,
    /// The film's size and the window these pixels are (a crop).
    pub film_size: (u32, u32),
    pub crop: Crop,
    /// The film's output formats, which `merge` writes.
    pub pixel_format: String,
    pub component_format: String,
    pub file_format: String,
    /// The samples this partial holds.
    pub samples: SampleRanges,
    /// The samples its render was asked for (`--samples`, else all): what `--resume`
    /// completes.
    pub target: SampleRanges,
}

const PIXEL_FORMATS: [PixelFormat; 6] = [
    PixelFormat::Luminance,
    PixelFormat::LuminanceAlpha,
    PixelFormat::Rgb,
    PixelFormat::Rgba,
    PixelFormat::Xyz,
    PixelFormat::Xyza,
];

/// The names [`RenderRecord::formats`] reads the film's formats from.
pub fn format_names(
    pixel: PixelFormat,
    component: ComponentFormat,
    file: FileFormat,
) -> (String, String, String) {
    let component = match component {
        ComponentFormat::Float16 => "float16",
        ComponentFormat::Float32 => "float32",
    };
    let file = match file {
        FileFormat::OpenExr => "openexr",
        FileFormat::Rgbe => "rgbe",
        FileFormat::Pfm => "pfm",
    };
    (pixel.name().into(), component.into(), file.into())
}

/// The header attribute holding the JSON record.
pub const RECORD_ATTRIBUTE: &str = "wavetrace.partial";
/// The header attribute saying in words how many samples the image holds.
pub const SAMPLES_ATTRIBUTE: &str = "wavetrace.samples";

impl RenderRecord {
    pub fn to_json(&self) -> Value {
        json!({
            "format": 1,
            "scene": self.scene.to_string_lossy(),
            "scene_sha256": self.scene_sha256,
            "defines": self.defines.iter().map(|(k, v)| json!([k, v])).collect::<Vec<_>>(),
            "seed": self.seed,
            "integrator_option": self.integrator_option,
            "sampler_option": self.sampler_option,
            "max_bounces": self.max_bounces,
            "aov_option": self.aov_option,
            "sensor": self.sensor,
            "integrator": self.integrator,
            "sampler": self.sampler,
            "film": self.film,
            "spp": self.spp,
            "film_size": [self.film_size.0, self.film_size.1],
            "crop": [self.crop.x, self.crop.y, self.crop.width, self.crop.height],
            "pixel_format": self.pixel_format,
            "component_format": self.component_format,
            "file_format": self.file_format,
            "samples": self.samples.to_string(),
            "target": self.target.to_string(),
        })
    }

    pub fn from_json(v: &Value) -> Result<RenderRecord, String> {
        let field = |k: &str| v.get(k).ok_or_else(|| format!("no '{k}'"));
        let string = |k: &str| -> Result<String, String> {
            field(k)?
                .as_str()
                .map(str::to_string)
                .ok_or_else(|| format!("'{k}' is not a string"))
        };
        let opt_string = |k: &str| -> Result<Option<String>, String> {
            match field(k)? {
                Value::Null => Ok(None),
                s => s
                    .as_str()
                    .map(|s| Some(s.to_string()))
                    .ok_or_else(|| format!("'{k}' is not a string")),
            }
        };
        let u32_of = |x: &Value, k: &str| -> Result<u32, String> {
            x.as_u64()
                .and_then(|n| u32::try_from(n).ok())
                .ok_or_else(|| format!("'{k}' is not a 32-bit count"))
        };
        let list = |k: &str, n: usize| -> Result<Vec<u32>, String> {
            let a = field(k)?
                .as_array()
                .filter(|a| a.len() == n)
                .ok_or_else(|| format!("'{k}' is not a list of {n} numbers"))?;
            a.iter().map(|x| u32_of(x, k)).collect()
        };
        if field("format")?.as_u64() != Some(1) {
            return Err("written by an unknown version of wavetrace (format is not 1)".into());
        }
        let defines = field("defines")?
            .as_array()
            .ok_or("'defines' is not a list")?
            .iter()
            .map(|d| match d.as_array().map(|a| a.as_slice()) {
                Some([Value::String(k), Value::String(v)]) => Ok((k.clone(), v.clone())),
                _ => Err("'defines' holds something other than [name, value]".to_string()),
            })
            .collect::<Result<_, _>>()?;
        let size = list("film_size", 2)?;
        let crop = list("crop", 4)?;
        Ok(RenderRecord {
            scene: PathBuf::from(string("scene")?),
            scene_sha256: string("scene_sha256")?,
            defines,
            seed: u32_of(field("seed")?, "seed")?,
            integrator_option: opt_string("integrator_option")?,
            sampler_option: opt_string("sampler_option")?,
            max_bounces: match field("max_bounces")? {
                Value::Null => None,
                x => Some(u32_of(x, "max_bounces")?),
            },
            // Absent from partials written before `--aov` existed.
            aov_option: v
                .get("aov_option")
                .and_then(Value::as_str)
                .map(str::to_string),
            // (Absent from partials written before `--sensor`.)
            sensor: match v.get("sensor") {
                None | Some(Value::Null) => None,
                Some(x) => Some(u32_of(x, "sensor")?),
            },
            integrator: string("integrator")?,
            sampler: string("sampler")?,
            film: string("film")?,
            spp: u32_of(field("spp")?, "spp")?,
            film_size: (size[0], size[1]),
            crop: Crop {
                x: crop[0],
                y: crop[1],
                width: crop[2],
                height: crop[3],
            },
            pixel_format: string("pixel_format")?,
            component_format: string("component_format")?,
            file_format: string("file_format")?,
            samples: SampleRanges::parse(&string("samples")?)?,
            target: SampleRanges::parse(&string("target")?)?,
        })
    }

    /// "12 of 16 samples per pixel: 0..12".
    pub fn samples_in_words(&self) -> String {
        format!(
            "{} of {} samples per pixel: {}",
            self.samples.count(),
            self.spp,
            self.samples
        )
    }

    /// Whether the record holds every sample of its render.
    pub fn is_complete(&self) -> bool {
        self.samples.missing(self.spp).is_empty()
    }

    /// The samples of its target it lacks (what `--resume` renders).
    pub fn to_do(&self) -> SampleRanges {
        let mut out = SampleRanges::default();
        for t in self.target.ranges() {
            for m in self.samples.missing(t.end).ranges() {
                out.add(m.start.max(t.start)..m.end);
            }
        }
        out
    }

    /// The first way in which `self` and `other` are renders of different images, in
    /// words ("seeds 1 and 2"); `None` if they are parts of the same render.
    pub fn difference(&self, other: &RenderRecord) -> Option<String> {
        let d = |what: &str, a: &dyn fmt::Display, b: &dyn fmt::Display| {
            Some(format!("{what} {a} and {b}"))
        };
        if self.scene_sha256 != other.scene_sha256 {
            return d(
                "scene files (sha256)",
                &self.scene_sha256,
                &other.scene_sha256,
            );
        }
        if self.defines != other.defines {
            let f = |d: &[(String, String)]| {
                let v: Vec<String> = d.iter().map(|(k, v)| format!("-D {k}={v}")).collect();
                format!("[{}]", v.join(" "))
            };
            return d("defines", &f(&self.defines), &f(&other.defines));
        }
        if self.seed != other.seed {
            return d("seeds", &self.seed, &other.seed);
        }
        let (sa, sb) = (self.sensor.unwrap_or(0), other.sensor.unwrap_or(0));
        if sa != sb {
            return d("sensors", &sa, &sb);
        }
        if self.integrator != other.integrator {
            return d("integrators", &self.integrator, &other.integrator);
        }
        if self.sampler != other.sampler {
            return d("samplers", &self.sampler, &other.sampler);
        }
        if self.max_bounces != other.max_bounces {
            let f = |m: Option<u32>| m.map_or("the default".to_string(), |m| m.to_string());
            return d(
                "bounce budgets (--max-bounces)",
                &f(self.max_bounces),
                &f(other.max_bounces),
            );
        }
        if (&self.film, self.film_size, self.crop) != (&other.film, other.film_size, other.crop) {
            return d("films", &self.film, &other.film);
        }
        if self.spp != other.spp {
            return d("whole-render sample counts (--spp)", &self.spp, &other.spp);
        }
        None
    }

    /// The formats the film writes (`merge`'s output).
    pub fn formats(&self) -> Result<(PixelFormat, ComponentFormat, FileFormat), String> {
        let pixel = PIXEL_FORMATS
            .into_iter()
            .find(|p| p.name() == self.pixel_format)
            .ok_or_else(|| format!("unknown pixel format '{}'", self.pixel_format))?;
        let component = match self.component_format.as_str() {
            "float16" => ComponentFormat::Float16,
            "float32" => ComponentFormat::Float32,
            c => return Err(format!("unknown component format '{c}'")),
        };
        let file = match self.file_format.as_str() {
            "openexr" => FileFormat::OpenExr,
            "rgbe" => FileFormat::Rgbe,
            "pfm" => FileFormat::Pfm,
            f => return Err(format!("unknown file format '{f}'")),
        };
        Ok((pixel, component, file))
    }

    /// The header attributes of a file of this record.
    pub fn text(&self) -> Vec<(String, String)> {
        vec![
            (RECORD_ATTRIBUTE.to_string(), self.to_json().to_string()),
            (SAMPLES_ATTRIBUTE.to_string(), self.samples_in_words()),
        ]
    }
}

/// Why a partial could not be read, written or merged.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error(transparent)]
    Image(#[from] image::Error),
    #[error("{}: {message}", path.display())]
    File { path: PathBuf, message: String },
    /// Parts that cannot be merged (different renders, overlapping, gaps).
    #[error("{0}")]
    Merge(String),
}

/// The sums of some samples of a render and the record of which.
#[derive(Debug, Clone, PartialEq)]
pub struct Partial {
    pub record: RenderRecord,
    pub sums: FilmSums,
}

impl Partial {
    /// Writes the partial EXR at `path` and an sRGB PNG of it at `png`, each
    /// atomically (a temporary file beside it, then renamed over it: a reader or a
    /// crash never sees half a file).
    pub fn write(&self, path: &Path, png: Option<&Path>) -> Result<(), Error> {
        let pixel_format = if self.sums.alpha.is_some() {
            PixelFormat::Rgba
        } else {
            PixelFormat::Rgb
        };
        let extras = ExrExtras {
            text: self.record.text(),
            sums: true,
        };
        write_atomically(path, png, |exr, png| {
            self.sums.write_with(
                exr,
                pixel_format,
                ComponentFormat::Float32,
                FileFormat::OpenExr,
                png,
                &extras,
            )
        })
    }

    /// Reads a partial EXR.
    pub fn read(path: &Path) -> Result<Partial, Error> {
        let (w, h, channels, text) = image::exr::read_channels_with_text(path)?;
        let bad = |message: String| Error::File {
            path: path.to_path_buf(),
            message,
        };
        let json = text
            .iter()
            .find(|(k, _)| k == RECORD_ATTRIBUTE)
            .map(|(_, v)| v)
            .ok_or_else(|| {
                bad(
                    "not a partial render (no 'wavetrace.partial' record in its header: \
                     partials are written by `wavetrace render --samples`, by an interrupted \
                     render or by --checkpoint)"
                        .into(),
                )
            })?;
        let value: Value = serde_json::from_str(json)
            .map_err(|e| bad(format!("its partial-render record is not JSON: {e}")))?;
        let record = RenderRecord::from_json(&value)
            .map_err(|e| bad(format!("its partial-render record is damaged: {e}")))?;
        if (w, h) != (record.crop.width, record.crop.height) {
            return Err(bad(format!(
                "its image is {w}x{h} but its record says {}x{}",
                record.crop.width, record.crop.height
            )));
        }
        let sums = FilmSums::from_sum_channels(
            record.film_size.0,
            record.film_size.1,
            record.crop,
            &channels,
        )
        .ok_or_else(|| {
            bad(if record.is_complete() {
                "it is a finished image, not a partial (it holds no film sums): merge \
                         the partials it was made from"
                    .into()
            } else {
                "it lacks the float32 sum channels (sum.R, sum.G, sum.B, sum.W) a \
                         merge needs"
                    .into()
            })
        })?;
        if record
            .samples
            .ranges()
            .last()
            .is_some_and(|r| r.end > record.spp)
        {
            return Err(bad(format!(
                "its samples {} lie past the render's {} samples per pixel",
                record.samples, record.spp
            )));
        }
        Ok(Partial { record, sums })
    }
}

/// Calls `write(exr, png)` with temporary paths beside `path` and `png` (same
/// extensions), then renames them over the real ones.
pub fn write_atomically<E>(
    path: &Path,
    png: Option<&Path>,
    write: impl FnOnce(&Path, Option<&Path>) -> Result<(), E>,
) -> Result<(), Error>
where
    Error: From<E>,
{
    let temp = |p: &Path| {
        let name = p
            .file_name()
            .map(|n| n.to_string_lossy())
            .unwrap_or_default();
        p.with_file_name(format!(".{name}.{}.tmp", std::process::id()))
            .with_extension(p.extension().unwrap_or_default())
    };
    let exr_temp = temp(path);
    let png_temp = png.map(temp);
    let result = write(&exr_temp, png_temp.as_deref()).map_err(Error::from);
    let rename = |from: &Path, to: &Path| {
        std::fs::rename(from, to).map_err(|e| Error::File {
            path: to.to_path_buf(),
            message: format!("cannot move {} there: {e}", from.display()),
        })
    };
    let result = result.and_then(|()| {
        rename(&exr_temp, path)?;
        match (&png_temp, png) {
            (Some(t), Some(p)) => rename(t, p),
            _ => Ok(()),
        }
    });
    if result.is_err() {
        std::fs::remove_file(&exr_temp).ok();
        if let Some(t) = &png_temp {
            std::fs::remove_file(t).ok();
        }
    }
    result
}

/// Merges parts of one render into the partial of their union: refuses parts of
/// different renders, overlapping parts and (unless `allow_gaps`) a union that is not
/// the whole render. Sums are added in the order of the parts' first samples (see the
/// module's note on exactness). `parts`: (file name for messages, partial).
pub fn merge(parts: &[(PathBuf, Partial)], allow_gaps: bool) -> Result<Partial, Error> {
    let Some((first_path, first)) = parts.first() else {
        return Err(Error::Merge(
            "nothing to merge: name the partial EXRs".into(),
        ));
    };
    for (path, p) in &parts[1..] {
        if let Some(d) = first.record.difference(&p.record) {
            return Err(Error::Merge(format!(
                "{} and {} are parts of different renders ({d}): only parts of one render \
                 (same scene file, defines, seed, integrator, sampler, film and sample count) \
                 merge",
                first_path.display(),
                path.display()
            )));
        }
    }
    let mut order: Vec<usize> = (0..parts.len()).collect();
    order.sort_by_key(|&i| parts[i].1.record.samples.ranges().first().map(|r| r.start));
    let mut union = SampleRanges::default();
    let mut owner: Vec<(Range<u32>, usize)> = Vec::new();
    for &i in &order {
        let (path, p) = &parts[i];
        if p.record.samples.is_empty() {
            return Err(Error::Merge(format!("{} holds no samples", path.display())));
        }
        for r in p.record.samples.ranges() {
            if let Some(o) = union.overlap(r) {
                let j = owner
                    .iter()
                    .find(|(q, _)| q.start < o.end && o.start < q.end)
                    .map_or(i, |&(_, j)| j);
                return Err(Error::Merge(format!(
                    "{} (samples {}) and {} (samples {}) overlap in samples {}..{}: each \
                     sample must come from one part",
                    path.display(),
                    p.record.samples,
                    parts[j].0.display(),
                    parts[j].1.record.samples,
                    o.start,
                    o.end
                )));
            }
            owner.push((r.clone(), i));
        }
        for r in p.record.samples.ranges() {
            union.add(r.clone());
        }
    }
    let total = first.record.spp;
    let missing = union.missing(total);
    if !missing.is_empty() && !allow_gaps {
        return Err(Error::Merge(format!(
            "the parts hold {} of the render's {total} samples per pixel: samples {missing} are \
             missing (render them with `wavetrace render ... --samples A..B`, or merge with \
             --allow-gaps for an image of the samples there are)",
            union.count()
        )));
    }
    let mut sums = parts[order[0]].1.sums.clone();
    for &i in &order[1..] {
        sums.merge(&parts[i].1.sums)
            .map_err(|e| Error::Merge(format!("{}: {e}", parts[i].0.display())))?;
    }
    Ok(Partial {
        record: RenderRecord {
            samples: union,
            target: SampleRanges::of(0..total),
            ..first.record.clone()
        },
        sums,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_ranges_merge_and_find_gaps() {
        let mut s = SampleRanges::of(4..8);
        s.add(0..2);
        s.add(8..10);
        assert_eq!(s.to_string(), "0..2,4..10");
        assert_eq!(s.count(), 8);
        assert_eq!(s.missing(12).to_string(), "2..4,10..12");
        assert_eq!(s.overlap(&(1..5)), Some(1..2));
        assert_eq!(s.overlap(&(2..4)), None);
        assert_eq!(SampleRanges::parse("0..2,4..10").unwrap(), s);
        assert!(SampleRanges::parse("none").unwrap().is_empty());
        assert!(SampleRanges::parse("").unwrap().is_empty());
        assert!(SampleRanges::parse("0..4,3..5").is_err());
        assert!(parse_range("5..5").unwrap_err().contains("empty"));
        assert!(parse_range("a..5").is_err());
        assert_eq!(parse_range("2..7"), Ok(2..7));
    }

    fn record(samples: Range<u32>) -> RenderRecord {
        RenderRecord {
            scene: PathBuf::from("/s/scene.xml"),
            scene_sha256: "ab".into(),
            defines: vec![("res".into(), "16".into())],
            seed: 3,
            integrator_option: None,
            sampler_option: Some("stratified".into()),
            max_bounces: None,
            aov_option: None,
            sensor: None,
            integrator: "PathMis".into(),
            sampler: "Sampler".into(),
            film: "Film".into(),
            spp: 8,
            film_size: (2, 1),
            crop: Crop {
                x: 0,
                y: 0,
                width: 2,
                height: 1,
            },
            pixel_format: "rgb".into(),
            component_format: "float16".into(),
            file_format: "openexr".into(),
            samples: SampleRanges::of(samples),
            target: SampleRanges::of(0..8),
        }
    }

    fn part(samples: Range<u32>, value: f32) -> (PathBuf, Partial) {
        let r = record(samples.clone());
        (
            PathBuf::from(format!("p{}.exr", samples.start)),
            Partial {
                sums: FilmSums {
                    film_width: 2,
                    film_height: 1,
                    crop: r.crop,
                    sums: vec![[value, 0.0, 0.0, 1.0], [0.0, value, 0.0, 1.0]],
                    alpha: None,
                    extra: Box::default(),
                },
                record: r,
            },
        )
    }

    #[test]
    fn record_round_trips_through_json() {
        let r = record(0..4);
        assert_eq!(RenderRecord::from_json(&r.to_json()), Ok(r.clone()));
        assert_eq!(r.to_do().to_string(), "4..8");
        let r = RenderRecord {
            target: SampleRanges::of(2..6),
            samples: SampleRanges::of(2..3),
            ..r
        };
        assert_eq!(r.to_do().to_string(), "3..6");
    }

    #[test]
    fn merge_refuses_other_renders_overlaps_and_gaps() {
        let m = merge(&[part(4..8, 2.0), part(0..4, 1.0)], false).unwrap();
        assert_eq!(m.record.samples.to_string(), "0..8");
        assert_eq!(m.sums.sums[0], [3.0, 0.0, 0.0, 2.0]);
        let mut other = part(4..8, 1.0);
        other.1.record.seed = 4;
        let e = merge(&[part(0..4, 1.0), other], false).unwrap_err();
        assert!(e.to_string().contains("seeds 3 and 4"), "{e}");
        let e = merge(&[part(0..5, 1.0), part(4..8, 1.0)], false).unwrap_err();
        assert!(e.to_string().contains("overlap in samples 4..5"), "{e}");
        let e = merge(&[part(0..2, 1.0), part(4..8, 1.0)], false).unwrap_err();
        assert!(e.to_string().contains("samples 2..4 are missing"), "{e}");
        let m = merge(&[part(0..2, 1.0), part(4..8, 1.0)], true).unwrap();
        assert_eq!(
            m.record.samples_in_words(),
            "6 of 8 samples per pixel: 0..2,4..8"
        );
    }

    #[test]
    fn partial_files_round_trip_exactly() {
        let (_, mut p) = part(2..5, 0.1);
        p.sums.sums[1] = [1.0e-30, -3.5, 7.0e20, 0.3];
        p.sums.alpha = Some(vec![0.25, 0.125]);
        let dir = std::env::temp_dir().join(format!("wavetrace-partial-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("p.exr");
        p.write(&path, Some(&dir.join("p.png"))).unwrap();
        let back = Partial::read(&path).unwrap();
        assert!(dir.join("p.png").exists());
        // Nothing but the two files is left (temporaries were renamed).
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
        std::fs::remove_dir_all(&dir).ok();
        assert_eq!(back, p);
    }
}
