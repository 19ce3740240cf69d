//! The film: how samples become pixels (the reconstruction filter), which pixels are
//! rendered (the crop window, the sampled border) and what the output file holds
//! (pixel format, component format, file format). The film's size is the camera's
//! (`Camera::width`, `Camera::height`).
//!
//! Mitsuba 3: `<film type="hdrfilm">` in the sensor, with
//!
//! | parameter | default | meaning |
//! | --- | --- | --- |
//! | `width`, `height` | 768, 576 | film size in pixels |
//! | `crop_offset_x`, `crop_offset_y` | 0, 0 | top-left corner of the rendered window |
//! | `crop_width`, `crop_height` | the film's | size of the rendered window |
//! | `sample_border` | false | also sample the pixels just outside the film that the filter reaches |
//! | `pixel_format` | `rgb` | `rgb`, `rgba`, `luminance`, `luminance_alpha`, `xyz`, `xyza` |
//! | `component_format` | `float16` | `float16`, `float32` |
//! | `file_format` | `openexr` | `openexr` (`exr`), `rgbe`, `pfm` |
//! | `banner` | | accepted; Mitsuba 3 ignores it too |
//!
//! and a nested `<rfilter>`: `box`, `tent` (`radius` 1), `gaussian` (`stddev` 0.5,
//! radius 4 stddev), `mitchell` (`B`, `C` 1/3; radius 2), `catmullrom` (Mitchell with
//! B = 0, C = 1/2), `lanczos` (`lobes` 3; radius = lobes). No `<rfilter>`: a Gaussian
//! of stddev 0.5. Mitsuba treats every filter of radius 1/2 as the box filter
//! (`ReconstructionFilter::is_box_filter`), and so does this reader.
//!
//! ```xml
//! <film type="hdrfilm">
//!     <integer name="width" value="256"/> <integer name="height" value="256"/>
//!     <string name="pixel_format" value="rgba"/>
//!     <rfilter type="mitchell"/>
//! </film>
//! ```
//!
//! Nori: a `<rfilter>` nested in the `<camera>`: `gaussian` (`radius` 2, `stddev` 0.5),
//! `mitchell` (`radius` 2, `B`, `C` 1/3), `tent` (radius 1), `box`; none: Nori's
//! Gaussian. Nori writes RGB float32 EXRs and has no crop window or sample border.
//!
//! Each pixel is the filter-weighted mean of the samples around it:
//! I(x, y) = Σ w_i L_i / Σ w_i with w_i = f(x + ½ - p_i.x) f(y + ½ - p_i.y), p_i the
//! sample's film position (Mitsuba's `ImageBlock::put` and `HDRFilm::develop`; Nori's
//! `ImageBlock::put`), the box filter giving every sample weight 1 in its own pixel.
//! Filters are evaluated exactly, as Mitsuba's JIT variants (llvm, cuda) do; its
//! scalar variants and Nori look them up in a step table of 31 (Nori 32) entries
//! over the radius, a slightly wider filter.

use super::plugin::{Family, Param, PluginDoc};
use super::properties::Properties;
use super::xml::{Dialect, Element};
use super::Error;

/// Every film and reconstruction filter type of both dialects. One file holds them:
/// each is a handful of parameters read by [`Film::from_mitsuba`],
/// [`Filter::from_mitsuba`] and [`Filter::from_nori`], and the filters' code is one
/// `match` in `eval` and in `shaders/film/`.
pub const REGISTRY: &[PluginDoc] = &[
    PluginDoc::new(
        Family::Film,
        Dialect::Mitsuba,
        "hdrfilm",
        "A high dynamic range film: the image size, crop window and output format; nests an <rfilter>.",
        &[
            Param::new("width", "integer", "768", "film width in pixels"),
            Param::new("height", "integer", "576", "film height in pixels"),
            Param::new("crop_offset_x", "integer", "0", "left edge of the rendered window"),
            Param::new("crop_offset_y", "integer", "0", "top edge of the rendered window"),
            Param::new("crop_width", "integer", "width", "width of the rendered window"),
            Param::new("crop_height", "integer", "height", "height of the rendered window"),
            Param::new("sample_border", "boolean", "false", "also sample the pixels just outside the film that the filter reaches"),
            Param::new("pixel_format", "string", "rgb", "rgb, rgba, luminance, luminance_alpha, xyz or xyza"),
            Param::new("component_format", "string", "float16", "float16 or float32"),
            Param::new("file_format", "string", "openexr", "openexr (exr), rgbe or pfm"),
            Param::new("banner", "boolean", "", "read and ignored, as in Mitsuba 3"),
        ],
    ),
    PluginDoc::not_yet(Family::Film, Dialect::Mitsuba, "specfilm"),
    rfilter(Dialect::Mitsuba, "box", "Weight 1 in the sample's pixel.", &[]),
    rfilter(Dialect::Mitsuba, "tent", "max(0, 1 - |x| / radius).", &[RADIUS_1]),
    rfilter(
        Dialect::Mitsuba,
        "gaussian",
        "A Gaussian less its value at the radius (4 stddev); the default.",
        &[Param::new("stddev", "float", "0.5", "standard deviation (pixels)")],
    ),
    rfilter(
        Dialect::Mitsuba,
        "mitchell",
        "Mitchell-Netravali, radius 2.",
        &[MITCHELL_B, MITCHELL_C],
    ),
    rfilter(Dialect::Mitsuba, "catmullrom", "Mitchell-Netravali with B = 0, C = 1/2.", &[]),
    rfilter(
        Dialect::Mitsuba,
        "lanczos",
        "Windowed sinc, radius = lobes.",
        &[Param::new("lobes", "integer", "3", "lobes, in 1..=64")],
    ),
    rfilter(Dialect::Nori, "box", "Weight 1 in the sample's pixel.", &[]),
    rfilter(Dialect::Nori, "tent", "max(0, 1 - |x|), radius 1.", &[]),
    rfilter(
        Dialect::Nori,
        "gaussian",
        "A Gaussian less its value at the radius; the default.",
        &[
            Param::new("radius", "float", "2", "radius (pixels)"),
            Param::new("stddev", "float", "0.5", "standard deviation (pixels)"),
        ],
    ),
    rfilter(
        Dialect::Nori,
        "mitchell",
        "Mitchell-Netravali.",
        &[
            Param::new("radius", "float", "2", "radius (pixels)"),
            MITCHELL_B,
            MITCHELL_C,
        ],
    ),
];

const RADIUS_1: Param = Param::new("radius", "float", "1", "radius (pixels)");
const MITCHELL_B: Param = Param::new("B", "float", "1/3", "B parameter");
const MITCHELL_C: Param = Param::new("C", "float", "1/3", "C parameter");

const fn rfilter(
    dialect: Dialect,
    name: &'static str,
    summary: &'static str,
    params: &'static [Param],
) -> PluginDoc {
    PluginDoc::new(Family::ReconstructionFilter, dialect, name, summary, params)
}

/// A separable reconstruction filter f(x) f(y) (x, y in pixels from the pixel centre).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Filter {
    /// Every sample counts with weight 1 in the pixel it falls in, and nowhere else.
    Box,
    /// max(0, 1 - |x| / radius).
    Tent { radius: f32 },
    /// A Gaussian less its value at the radius, so that it reaches 0 there:
    /// max(0, exp(-x² / 2σ²) - exp(-r² / 2σ²)). Mitsuba: r = 4σ; Nori: r = 2.
    Gaussian { stddev: f32, radius: f32 },
    /// Mitchell and Netravali 1988, "Reconstruction Filters in Computer Graphics",
    /// eq. 8, of |2x / radius| (radius 2 in Mitsuba; Catmull-Rom is B = 0, C = 1/2).
    /// Negative lobes between |x| = radius/2 and radius.
    Mitchell { b: f32, c: f32, radius: f32 },
    /// Lanczos windowed sinc: sinc(x) sinc(x / lobes) for |x| < lobes, with
    /// sinc(t) = sin(πt) / (πt). Negative lobes.
    Lanczos { lobes: u32 },
}

/// Mitsuba 3's `math::RayEpsilon<float>` (Epsilon 2^-24 times 1500), which
/// `ReconstructionFilter::border_size` subtracts twice.
const MITSUBA_RAY_EPSILON: f32 = 1500.0 / 16_777_216.0;

impl Filter {
    /// Mitsuba's default (and Nori's, whose radius 2 equals 4 x 0.5).
    pub const DEFAULT: Filter = Filter::Gaussian {
        stddev: 0.5,
        radius: 2.0,
    };

    /// Half the width of the filter's support, in pixels.
    pub fn radius(&self) -> f32 {
        match *self {
            Filter::Box => 0.5,
            Filter::Tent { radius } => radius,
            Filter::Gaussian { radius, .. } => radius,
            Filter::Mitchell { radius, .. } => radius,
            Filter::Lanczos { lobes } => lobes as f32,
        }
    }

    /// The filter's name, as scene files spell it.
    pub fn name(&self) -> &'static str {
        match self {
            Filter::Box => "box",
            Filter::Tent { .. } => "tent",
            Filter::Gaussian { .. } => "gaussian",
            Filter::Mitchell { .. } => "mitchell",
            Filter::Lanczos { .. } => "lanczos",
        }
    }

    /// f(x) at `x` pixels from the pixel centre, as `shaders/film/filter.glsl`
    /// evaluates it (in f32). Zero from the radius on; the box is 1 on [-½, ½).
    pub fn eval(&self, x: f32) -> f32 {
        let ax = x.abs();
        match *self {
            Filter::Box => {
                if (-0.5..0.5).contains(&x) {
                    1.0
                } else {
                    0.0
                }
            }
            Filter::Tent { radius } => (1.0 - ax / radius).max(0.0),
            Filter::Gaussian { stddev, radius } => {
                let alpha = -1.0 / (2.0 * stddev * stddev);
                ((alpha * x * x).exp() - (alpha * radius * radius).exp()).max(0.0)
            }
            Filter::Mitchell { b, c, radius } => {
                let t = 2.0 * ax / radius;
                let (t2, t3) = (t * t, t * t * t);
                let v = if t < 1.0 {
                    (12.0 - 9.0 * b - 6.0 * c) * t3
                        + (-18.0 + 12.0 * b + 6.0 * c) * t2
                        + (6.0 - 2.0 * b)
                } else if t < 2.0 {
                    (-b - 6.0 * c) * t3
                        + (6.0 * b + 30.0 * c) * t2
                        + (-12.0 * b - 48.0 * c) * t
                        + (8.0 * b + 24.0 * c)
                } else {
                    0.0
                };
                v / 6.0
            }
            Filter::Lanczos { lobes } => {
                let r = lobes as f32;
                if ax < f32::EPSILON {
                    1.0
                } else if ax >= r {
                    0.0
                } else {
                    let x1 = std::f32::consts::PI * ax;
                    let x2 = x1 / r;
                    (x1.sin() * x2.sin()) / (x1 * x2)
                }
            }
        }
    }

    /// Pixels on each side of its own that a sample can reach: a sample at p in
    /// pixel q weighs pixel x when |x + ½ - p| < radius, so |x - q| ≤ ⌈radius + ½⌉ - 1.
    /// 0 for the box.
    pub fn reach(&self) -> u32 {
        match self {
            Filter::Box => 0,
            f => ((f.radius() + 0.5).ceil() - 1.0).max(0.0) as u32,
        }
    }

    /// Pixels sampled outside the film on each side with `sample_border`: Mitsuba's
    /// `border_size`, ⌈radius - ½ - 2ε⌉ (ε its ray epsilon), 0 for the box.
    pub fn border_size(&self) -> u32 {
        match self {
            Filter::Box => 0,
            f => (f.radius() - 0.5 - 2.0 * MITSUBA_RAY_EPSILON)
                .ceil()
                .max(0.0) as u32,
        }
    }

    /// The correlation of the noise of two pixels `d` columns (or rows) apart, along
    /// one axis: a(d) = A(d) / A(0), A(d) = ∫ f(u) f(u + d) du. A sample weighs both
    /// pixels, so with noise independent of where in a pixel a sample lies, two pixels
    /// (dx, dy) apart correlate by a(dx) a(dy). 0 for the box at d ≠ 0.
    pub fn noise_correlation(&self, d: i32) -> f64 {
        if d == 0 {
            return 1.0;
        }
        if *self == Filter::Box {
            return 0.0;
        }
        let r = self.radius() as f64;
        let auto = |d: f64| {
            let steps = 4000;
            let h = 2.0 * r / steps as f64;
            (0..steps)
                .map(|i| {
                    let u = -r + (i as f64 + 0.5) * h;
                    self.eval(u as f32) as f64 * self.eval((u + d) as f32) as f64 * h
                })
                .sum::<f64>()
        };
        auto(d as f64) / auto(0.0)
    }

    /// How much larger the variance of the mean of an n x n block of pixels is than
    /// for independent pixels: (Σ_{|d| < n} (n - |d|) a(d) / n)², a from
    /// [`Filter::noise_correlation`]. 1 for the box.
    pub fn block_variance_factor(&self, n: u32) -> f64 {
        let n = n as i32;
        let reach = 2 * self.reach() as i32 + 1;
        let one_axis: f64 = (-(n - 1).min(reach)..=(n - 1).min(reach))
            .map(|d| (n - d.abs()) as f64 / n as f64 * self.noise_correlation(d))
            .sum();
        one_axis * one_axis
    }

    /// Reads a Mitsuba `<rfilter>`.
    pub fn from_mitsuba(el: &Element) -> Result<Filter, Error> {
        el.check_attrs(&["type", "id", "name"])?;
        let t = el.require("type")?;
        let (props, nested) = Properties::read(el, Dialect::Mitsuba, false)?;
        if let Some(n) = nested.first() {
            return Err(n.err(format!("unexpected <{}> in <rfilter>", n.tag)));
        }
        let filter = match t {
            "box" => Filter::Box,
            "tent" => Filter::Tent {
                radius: positive_float(&props, "radius", 1.0)?,
            },
            "gaussian" => {
                let stddev = positive_float(&props, "stddev", 0.5)?;
                Filter::Gaussian {
                    stddev,
                    radius: 4.0 * stddev,
                }
            }
            "mitchell" => Filter::Mitchell {
                b: finite_float(&props, "B", 1.0 / 3.0)?,
                c: finite_float(&props, "C", 1.0 / 3.0)?,
                radius: 2.0,
            },
            "catmullrom" => Filter::Mitchell {
                b: 0.0,
                c: 0.5,
                radius: 2.0,
            },
            "lanczos" => {
                let lobes = props.integer("lobes", 3)?;
                if !(1..=64).contains(&lobes) {
                    return Err(props.error(
                        "lobes",
                        format!("lobes of rfilter 'lanczos' must be in 1..=64, found {lobes}"),
                    ));
                }
                Filter::Lanczos {
                    lobes: lobes as u32,
                }
            }
            t => {
                return Err(el.err(format!(
                    "unknown rfilter type '{t}' (Mitsuba 3 has box, tent, gaussian, mitchell, catmullrom, lanczos)"
                )))
            }
        };
        props.finish()?;
        check_radius(el, filter)?;
        // Mitsuba's rule (`ReconstructionFilter::is_box_filter`): radius 1/2 is the box.
        Ok(if filter.radius() == 0.5 {
            Filter::Box
        } else {
            filter
        })
    }

    /// Reads a Nori `<rfilter>` (nested in the camera).
    pub fn from_nori(el: &Element) -> Result<Filter, Error> {
        el.check_attrs(&["type"])?;
        let t = el.require("type")?;
        let (props, nested) = Properties::read(el, Dialect::Nori, false)?;
        if let Some(n) = nested.first() {
            return Err(n.err(format!("unexpected <{}> in <rfilter>", n.tag)));
        }
        let filter = match t {
            "box" => Filter::Box,
            "tent" => Filter::Tent { radius: 1.0 },
            "gaussian" => Filter::Gaussian {
                radius: positive_float(&props, "radius", 2.0)?,
                stddev: positive_float(&props, "stddev", 0.5)?,
            },
            "mitchell" => Filter::Mitchell {
                radius: positive_float(&props, "radius", 2.0)?,
                b: finite_float(&props, "B", 1.0 / 3.0)?,
                c: finite_float(&props, "C", 1.0 / 3.0)?,
            },
            t => {
                return Err(el.err(format!(
                    "unknown rfilter type '{t}' (Nori has gaussian, mitchell, tent, box)"
                )))
            }
        };
        props.finish()?;
        check_radius(el, filter)?;
        Ok(filter)
    }
}

/// Filters wider than this many pixels are refused: each pixel gathers
/// (2 reach + 1)² neighbours per sample.
pub const MAX_FILTER_RADIUS: f32 = 16.0;

fn check_radius(el: &Element, filter: Filter) -> Result<(), Error> {
    let r = filter.radius();
    if r > MAX_FILTER_RADIUS {
        return Err(el.err(format!(
            "rfilter '{}' has radius {r} pixels; wavetrace supports up to {MAX_FILTER_RADIUS}",
            filter.name()
        )));
    }
    Ok(())
}

fn positive_float(props: &Properties, name: &str, default: f32) -> Result<f32, Error> {
    let v = props.float(name, default)?;
    if !(v > 0.0 && v.is_finite()) {
        return Err(props.error(
            name,
            format!(
                "parameter '{name}' of {} must be positive, found {v}",
                props.object()
            ),
        ));
    }
    Ok(v)
}

fn finite_float(props: &Properties, name: &str, default: f32) -> Result<f32, Error> {
    let v = props.float(name, default)?;
    if !v.is_finite() {
        return Err(props.error(
            name,
            format!(
                "parameter '{name}' of {} must be finite, found {v}",
                props.object()
            ),
        ));
    }
    Ok(v)
}

/// A rectangle of the film, in pixels from its top-left corner.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Crop {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

/// What the output file's pixels hold (Mitsuba's `pixel_format`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PixelFormat {
    /// Y = 0.212671 R + 0.715160 G + 0.072169 B (Mitsuba's sRGB luminance).
    Luminance,
    LuminanceAlpha,
    Rgb,
    /// RGB and alpha: the filter-weighted fraction of a pixel's samples whose camera
    /// path found a surface, a medium or a visible environment (Mitsuba's
    /// `valid_ray`). The colour is not divided by alpha (premultiplied, as in
    /// Mitsuba's and OpenEXR's convention).
    Rgba,
    /// CIE XYZ of the linear sRGB values (Mitsuba's `srgb_to_xyz`).
    Xyz,
    Xyza,
}

impl PixelFormat {
    /// Whether the format has an alpha channel.
    pub fn has_alpha(self) -> bool {
        matches!(
            self,
            PixelFormat::LuminanceAlpha | PixelFormat::Rgba | PixelFormat::Xyza
        )
    }

    /// The channels of the format, named as Mitsuba's `hdrfilm` writes them.
    pub fn channel_names(self) -> Vec<&'static str> {
        match self {
            PixelFormat::Luminance => vec!["Y"],
            PixelFormat::LuminanceAlpha => vec!["Y", "A"],
            PixelFormat::Rgb => vec!["R", "G", "B"],
            PixelFormat::Rgba => vec!["R", "G", "B", "A"],
            PixelFormat::Xyz => vec!["X", "Y", "Z"],
            PixelFormat::Xyza => vec!["X", "Y", "Z", "A"],
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            PixelFormat::Luminance => "luminance",
            PixelFormat::LuminanceAlpha => "luminance_alpha",
            PixelFormat::Rgb => "rgb",
            PixelFormat::Rgba => "rgba",
            PixelFormat::Xyz => "xyz",
            PixelFormat::Xyza => "xyza",
        }
    }
}

/// The type of every channel in the output file (Mitsuba's `component_format`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ComponentFormat {
    Float16,
    Float32,
}

/// The output file's format (Mitsuba's `file_format`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileFormat {
    OpenExr,
    /// Radiance RGBE (`.hdr`): RGB only, 8-bit mantissas and a shared exponent.
    Rgbe,
    /// Portable float map (`.pfm`): RGB or luminance, float32.
    Pfm,
}

impl FileFormat {
    /// The file name extension Mitsuba gives the format (it replaces any other).
    pub fn extension(self) -> &'static str {
        match self {
            FileFormat::OpenExr => "exr",
            FileFormat::Rgbe => "rgbe",
            FileFormat::Pfm => "pfm",
        }
    }
}

/// Everything about the film but its size (which is the camera's).
#[derive(Debug, Clone, PartialEq)]
pub struct Film {
    pub filter: Filter,
    /// The window to render; `None`: the whole film.
    pub crop: Option<Crop>,
    /// Mitsuba's `sample_border`: pixels up to the filter's border size outside the
    /// film are sampled too, so edge pixels see samples on all sides.
    pub sample_border: bool,
    pub pixel_format: PixelFormat,
    pub component_format: ComponentFormat,
    pub file_format: FileFormat,
}

impl Default for Film {
    /// Mitsuba's `hdrfilm` defaults: Gaussian filter, no crop, RGB float16 OpenEXR.
    fn default() -> Film {
        Film {
            filter: Filter::DEFAULT,
            crop: None,
            sample_border: false,
            pixel_format: PixelFormat::Rgb,
            component_format: ComponentFormat::Float16,
            file_format: FileFormat::OpenExr,
        }
    }
}

impl Film {
    /// Nori's film: its Gaussian filter (radius 2, stddev 0.5), RGB float32 OpenEXR.
    pub fn nori(filter: Filter) -> Film {
        Film {
            filter,
            component_format: ComponentFormat::Float32,
            ..Film::default()
        }
    }

    /// The rendered window of a `width` x `height` film.
    pub fn window(&self, width: u32, height: u32) -> Crop {
        self.crop.unwrap_or(Crop {
            x: 0,
            y: 0,
            width,
            height,
        })
    }

    /// Reads a Mitsuba `<film type="hdrfilm">`: its size and the rest.
    pub fn from_mitsuba(
        el: &Element,
        default_width: u32,
        default_height: u32,
    ) -> Result<(u32, u32, Film), Error> {
        let (props, nested) = Properties::read(el, Dialect::Mitsuba, false)?;
        let mut filter = None;
        for n in nested {
            match n.tag.as_str() {
                "rfilter" if filter.is_none() => filter = Some(Filter::from_mitsuba(n)?),
                "rfilter" => return Err(n.err("a film can only have one reconstruction filter")),
                _ => return Err(n.err(format!("unexpected <{}> in <film>", n.tag))),
            }
        }
        let width = props.positive("width", default_width)?;
        let height = props.positive("height", default_height)?;

        let crop_width = props.positive("crop_width", width)?;
        let crop_height = props.positive("crop_height", height)?;
        let offset = |name: &str| -> Result<u32, Error> {
            let v = props.integer(name, 0)?;
            u32::try_from(v).map_err(|_| {
                props.error(
                    name,
                    format!("parameter '{name}' of film must be at least 0, found {v}"),
                )
            })
        };
        let (crop_x, crop_y) = (offset("crop_offset_x")?, offset("crop_offset_y")?);
        if u64::from(crop_x) + u64::from(crop_width) > u64::from(width)
            || u64::from(crop_y) + u64::from(crop_height) > u64::from(height)
        {
            let key = [
                "crop_width",
                "crop_height",
                "crop_offset_x",
                "crop_offset_y",
            ]
            .into_iter()
            .find(|k| props.has(k))
            .unwrap_or("width");
            return Err(props.error(
                key,
                format!(
                    "the crop window {crop_width}x{crop_height} at ({crop_x}, {crop_y}) does not fit in the {width}x{height} film"
                ),
            ));
        }
        let crop = (crop_x, crop_y, crop_width, crop_height) != (0, 0, width, height);

        let pixel_format = match props.string("pixel_format", "rgb")?.to_lowercase().as_str() {
            "luminance" => PixelFormat::Luminance,
            "luminance_alpha" => PixelFormat::LuminanceAlpha,
            "rgb" => PixelFormat::Rgb,
            "rgba" => PixelFormat::Rgba,
            "xyz" => PixelFormat::Xyz,
            "xyza" => PixelFormat::Xyza,
            other => {
                return Err(props.error(
                    "pixel_format",
                    format!(
                        "unknown pixel_format '{other}' (expected luminance, luminance_alpha, rgb, rgba, xyz or xyza)"
                    ),
                ))
            }
        };
        let component_format = match props
            .string("component_format", "float16")?
            .to_lowercase()
            .as_str()
        {
            "float16" => ComponentFormat::Float16,
            "float32" => ComponentFormat::Float32,
            "uint32" => {
                return Err(props.error(
                    "component_format",
                    "component_format 'uint32' is not supported (float16 or float32)",
                ))
            }
            other => {
                return Err(props.error(
                    "component_format",
                    format!("unknown component_format '{other}' (expected float16 or float32)"),
                ))
            }
        };
        let file_format = match props
            .string("file_format", "openexr")?
            .to_lowercase()
            .as_str()
        {
            "openexr" | "exr" => FileFormat::OpenExr,
            "rgbe" => FileFormat::Rgbe,
            "pfm" => FileFormat::Pfm,
            other => {
                return Err(props.error(
                    "file_format",
                    format!("unknown file_format '{other}' (expected openexr, rgbe or pfm)"),
                ))
            }
        };
        let mut film = Film {
            filter: filter.unwrap_or(Filter::DEFAULT),
            crop: crop.then_some(Crop {
                x: crop_x,
                y: crop_y,
                width: crop_width,
                height: crop_height,
            }),
            sample_border: props.boolean("sample_border", false)?,
            pixel_format,
            component_format,
            file_format,
        };
        // As Mitsuba's hdrfilm: RGBE holds RGB float32, PFM RGB or luminance float32
        // (Mitsuba warns and overrides).
        match film.file_format {
            FileFormat::Rgbe => {
                film.pixel_format = PixelFormat::Rgb;
                film.component_format = ComponentFormat::Float32;
            }
            FileFormat::Pfm => {
                if film.pixel_format != PixelFormat::Luminance {
                    film.pixel_format = PixelFormat::Rgb;
                }
                film.component_format = ComponentFormat::Float32;
            }
            FileFormat::OpenExr => {}
        }
        props.ignore(&["banner"]);
        props.finish()?;
        Ok((width, height, film))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::testutil::{error_at, load};

    fn film_of(film_xml: &str) -> Result<crate::scene::Scene, Error> {
        load(
            &[(
                "s.xml",
                &format!(
                    r#"<scene version="3.0.0"><sensor type="perspective">{film_xml}</sensor></scene>"#
                ),
            )],
            &[],
        )
    }

    /// Values printed by Mitsuba 3.9.1's `mi.load_dict({'type': T}).eval(x)`
    /// (llvm_ad_rgb, the exact evaluation) at x = 0, 0.5, 1, 1.5: our filters are
    /// the same functions (the Gaussian only to Mitsuba's polynomial fit of exp,
    /// about 4e-4 absolute).
    #[test]
    fn filters_match_mitsubas_values() {
        let cases: [(Filter, [f32; 4], f32); 5] = [
            (Filter::Tent { radius: 1.0 }, [1.0, 0.5, 0.0, 0.0], 1e-7),
            (
                Filter::Mitchell {
                    b: 1.0 / 3.0,
                    c: 1.0 / 3.0,
                    radius: 2.0,
                },
                [0.888_888_96, 0.534_722_27, 0.055_555_62, -0.034_721_967],
                1e-6,
            ),
            (
                Filter::Mitchell {
                    b: 0.0,
                    c: 0.5,
                    radius: 2.0,
                },
                [1.0, 0.5625, 0.0, -0.0625],
                1e-6,
            ),
            (
                Filter::Lanczos { lobes: 3 },
                [1.0, 0.607_927_1, 0.0, -0.135_094_9],
                1e-6,
            ),
            (
                Filter::DEFAULT,
                [0.999_247_1, 0.606_423, 0.134_960_5, 0.010_758_2],
                5e-4,
            ),
        ];
        for (f, want, tol) in cases {
            for (i, w) in want.iter().enumerate() {
                let x = 0.5 * i as f32;
                assert!(
                    (f.eval(x) - w).abs() <= tol && (f.eval(-x) - w).abs() <= tol,
                    "{f:?} at {x}: {} vs Mitsuba's {w}",
                    f.eval(x)
                );
            }
            assert_eq!(f.eval(f.radius()), 0.0, "{f:?} at its radius");
            assert_eq!(f.eval(f.radius() + 0.3), 0.0, "{f:?} past its radius");
        }
        // The Gaussian reaches 0 at the radius from above, continuously.
        let g = Filter::DEFAULT;
        assert!(g.eval(1.999) > 0.0 && g.eval(1.999) < 1e-5);
        // The box: 1 on [-1/2, 1/2).
        assert_eq!((Filter::Box.eval(-0.5), Filter::Box.eval(0.5)), (1.0, 0.0));
    }

    #[test]
    fn reach_and_border_size() {
        // (filter, reach, Mitsuba's border_size): Mitsuba 3.9.1 prints border_size 2
        // for gaussian, mitchell, catmullrom, 1 for tent, 3 for lanczos, 0 for box.
        for (f, reach, border) in [
            (Filter::Box, 0, 0),
            (Filter::Tent { radius: 1.0 }, 1, 1),
            (Filter::Tent { radius: 1.5 }, 1, 1),
            (Filter::Tent { radius: 1.6 }, 2, 2),
            (Filter::DEFAULT, 2, 2),
            (
                Filter::Gaussian {
                    stddev: 0.25,
                    radius: 1.0,
                },
                1,
                1,
            ),
            (Filter::Lanczos { lobes: 3 }, 3, 3),
        ] {
            assert_eq!((f.reach(), f.border_size()), (reach, border), "{f:?}");
        }
    }

    #[test]
    fn mitsuba_film_parameters() {
        let s = film_of(
            r#"<film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="48"/>
  <integer name="crop_offset_x" value="8"/><integer name="crop_offset_y" value="4"/>
  <integer name="crop_width" value="16"/><integer name="crop_height" value="20"/>
  <boolean name="sample_border" value="true"/>
  <string name="pixel_format" value="RGBA"/><string name="component_format" value="float32"/>
  <rfilter type="lanczos"><integer name="lobes" value="2"/></rfilter></film>"#,
        )
        .unwrap();
        assert_eq!((s.camera.width, s.camera.height), (64, 48));
        let f = &s.film;
        assert_eq!(f.filter, Filter::Lanczos { lobes: 2 });
        assert_eq!(
            f.crop,
            Some(Crop {
                x: 8,
                y: 4,
                width: 16,
                height: 20
            })
        );
        assert!(f.sample_border);
        assert_eq!(f.pixel_format, PixelFormat::Rgba);
        assert_eq!(f.component_format, ComponentFormat::Float32);
        assert_eq!(f.file_format, FileFormat::OpenExr);

        // Defaults: a Gaussian of stddev 0.5, whole film, RGB float16 EXR.
        let s = film_of(r#"<film type="hdrfilm"/>"#).unwrap();
        assert_eq!(s.film, Film::default());
        assert_eq!(s.film.filter, Filter::DEFAULT);
        // No film at all: the same.
        let s = film_of("").unwrap();
        assert_eq!(s.film, Film::default());
        // A crop of the whole film is no crop.
        let s = film_of(
            r#"<film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/>
               <integer name="crop_width" value="8"/></film>"#,
        )
        .unwrap();
        assert_eq!(s.film.crop, None);
    }

    #[test]
    fn mitsuba_filters_and_their_parameters() {
        let filter = |xml: &str| {
            film_of(&format!(r#"<film type="hdrfilm">{xml}</film>"#))
                .unwrap()
                .film
                .filter
        };
        assert_eq!(filter(r#"<rfilter type="box"/>"#), Filter::Box);
        assert_eq!(
            filter(r#"<rfilter type="gaussian"><float name="stddev" value="0.25"/></rfilter>"#),
            Filter::Gaussian {
                stddev: 0.25,
                radius: 1.0
            }
        );
        assert_eq!(
            filter(r#"<rfilter type="tent"><float name="radius" value="1.25"/></rfilter>"#),
            Filter::Tent { radius: 1.25 }
        );
        assert_eq!(
            filter(
                r#"<rfilter type="mitchell"><float name="B" value="0.5"/><float name="C" value="0.25"/></rfilter>"#
            ),
            Filter::Mitchell {
                b: 0.5,
                c: 0.25,
                radius: 2.0
            }
        );
        assert_eq!(
            filter(r#"<rfilter type="catmullrom"/>"#),
            Filter::Mitchell {
                b: 0.0,
                c: 0.5,
                radius: 2.0
            }
        );
        assert_eq!(
            filter(r#"<rfilter type="lanczos"/>"#),
            Filter::Lanczos { lobes: 3 }
        );
        // Radius 1/2 is Mitsuba's box, whatever the filter.
        assert_eq!(
            filter(r#"<rfilter type="tent"><float name="radius" value="0.5"/></rfilter>"#),
            Filter::Box
        );
    }

    #[test]
    fn file_formats_override_as_mitsuba_does() {
        let s = film_of(
            r#"<film type="hdrfilm"><string name="file_format" value="rgbe"/><string name="pixel_format" value="rgba"/></film>"#,
        )
        .unwrap();
        assert_eq!(s.film.file_format, FileFormat::Rgbe);
        assert_eq!(s.film.pixel_format, PixelFormat::Rgb);
        assert_eq!(s.film.component_format, ComponentFormat::Float32);
        let s = film_of(
            r#"<film type="hdrfilm"><string name="file_format" value="pfm"/><string name="pixel_format" value="luminance"/></film>"#,
        )
        .unwrap();
        assert_eq!(
            (s.film.file_format, s.film.pixel_format),
            (FileFormat::Pfm, PixelFormat::Luminance)
        );
    }

    #[test]
    fn bad_film_values_name_file_and_line() {
        let cases = [
            (
                r#"<film type="hdrfilm">
<string name="pixel_format" value="rgbw"/></film>"#,
                "unknown pixel_format 'rgbw'",
            ),
            (
                r#"<film type="hdrfilm">
<string name="component_format" value="float64"/></film>"#,
                "unknown component_format 'float64'",
            ),
            (
                r#"<film type="hdrfilm">
<string name="file_format" value="png"/></film>"#,
                "unknown file_format 'png'",
            ),
            (
                r#"<film type="hdrfilm">
<rfilter type="sinc"/></film>"#,
                "unknown rfilter type 'sinc'",
            ),
            (
                r#"<film type="hdrfilm">
<rfilter type="gaussian"><float name="stddev" value="-1"/></rfilter></film>"#,
                "must be positive",
            ),
            (
                r#"<film type="hdrfilm">
<rfilter type="gaussian"><float name="radius" value="3"/></rfilter></film>"#,
                "unknown parameter 'radius'",
            ),
            (
                r#"<film type="hdrfilm"><integer name="width" value="16"/>
<integer name="crop_width" value="12"/><integer name="crop_offset_x" value="8"/></film>"#,
                "does not fit in the 16x576 film",
            ),
            (
                r#"<film type="hdrfilm">
<rfilter type="box"/><rfilter type="box"/></film>"#,
                "only have one reconstruction filter",
            ),
            (
                r#"<film type="hdrfilm">
<rfilter type="lanczos"><integer name="lobes" value="0"/></rfilter></film>"#,
                "lobes of rfilter 'lanczos' must be in 1..=64",
            ),
        ];
        for (xml, want) in cases {
            let text = error_at(film_of(xml), "s.xml", 2);
            assert!(text.contains(want), "{text}");
        }
    }

    #[test]
    fn nori_filters() {
        let camera = |rfilter: &str| {
            load(
                &[(
                    "n.xml",
                    &format!(
                        r#"<scene><camera type="perspective">{rfilter}</camera><integrator type="normals"/></scene>"#
                    ),
                )],
                &[],
            )
        };
        let s = camera("").unwrap();
        assert_eq!(s.film, Film::nori(Filter::DEFAULT));
        assert_eq!(s.film.component_format, ComponentFormat::Float32);
        let f = |xml: &str| camera(xml).unwrap().film.filter;
        assert_eq!(
            f(
                r#"<rfilter type="gaussian"><float name="radius" value="3"/><float name="stddev" value="1"/></rfilter>"#
            ),
            Filter::Gaussian {
                stddev: 1.0,
                radius: 3.0
            }
        );
        assert_eq!(
            f(r#"<rfilter type="mitchell"><float name="radius" value="3"/></rfilter>"#),
            Filter::Mitchell {
                b: 1.0 / 3.0,
                c: 1.0 / 3.0,
                radius: 3.0
            }
        );
        assert_eq!(f(r#"<rfilter type="tent"/>"#), Filter::Tent { radius: 1.0 });
        assert_eq!(f(r#"<rfilter type="box"/>"#), Filter::Box);
        let text = error_at(
            camera(
                r#"
<rfilter type="lanczos"/>"#,
            ),
            "n.xml",
            2,
        );
        assert!(text.contains("unknown rfilter type 'lanczos'"), "{text}");
    }

    #[test]
    fn noise_correlation_of_the_gaussian() {
        // An untruncated Gaussian of stddev σ correlates with itself shifted by d as
        // exp(-d² / 4σ²): e^-1 at one pixel for σ = 1/2; truncation at 4σ barely
        // changes that.
        let g = Filter::DEFAULT;
        assert!((g.noise_correlation(1) - (-1.0f64).exp()).abs() < 0.01);
        assert!((g.noise_correlation(-2) - (-4.0f64).exp()).abs() < 0.01);
        assert!(g.noise_correlation(4).abs() < 1e-9);
        assert_eq!(Filter::Box.noise_correlation(1), 0.0);
        assert_eq!(Filter::Box.block_variance_factor(8), 1.0);
        // 8x8 blocks: (1 + 2 (7/8 e^-1 + 6/8 e^-4 + ...))² ≈ 2.8.
        let f = g.block_variance_factor(8);
        assert!((f - 2.8).abs() < 0.1, "{f}");
        // Negative lobes anticorrelate pixels two apart.
        assert!(Filter::Lanczos { lobes: 3 }.noise_correlation(2) < 0.0);
    }

    /// Nori's Mitchell scales x by 2 / radius: at radius 2 it is Mitsuba's.
    #[test]
    fn nori_mitchell_scales_with_its_radius() {
        let m2 = Filter::Mitchell {
            b: 1.0 / 3.0,
            c: 1.0 / 3.0,
            radius: 2.0,
        };
        let m4 = Filter::Mitchell {
            b: 1.0 / 3.0,
            c: 1.0 / 3.0,
            radius: 4.0,
        };
        for x in [0.0f32, 0.3, 0.9, 1.7] {
            assert!((m4.eval(2.0 * x) - m2.eval(x)).abs() < 1e-6);
        }
    }
}
