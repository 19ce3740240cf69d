//! Textures: functions of the surface uv that any color or float parameter of a BSDF,
//! the radiance of an area emitter or a normal map can read; the texture family, one
//! file per plugin type with its parameters, and [`REGISTRY`].
//!
//! The GLSL is `shaders/texture/texture.glsl`; [`Texture::eval`] here is its CPU
//! reference (the GPU test compares them at random uvs) and also gives the means the
//! host needs (emitter power, sampling weights of plastics).
//!
//! Every texture first maps the surface uv by the affine `to_uv` (Mitsuba's
//! `<transform name="to_uv">`: rows 0 and 1 of the 4x4, columns x, y and translation).
//!
//! Mitsuba 3 conventions (checked against Mitsuba 3.9.1's `bitmap` and `checkerboard`):
//! image row 0 (the top of the file) lies at v = 0, uv is not flipped; texel (i, j)
//! is centred at ((i + ½)/W, (j + ½)/H); wrap modes act on texel indices.

use std::path::Path;

use glam::{Mat4, Vec2, Vec3};

pub mod bitmap;
pub mod checkerboard;
pub mod marble;
pub mod mesh_attribute;
pub mod noise;
pub mod rawconstant;

use super::plugin::{Family, Param, PluginDoc};
use super::properties::Properties;
use super::xml::{Dialect, Element};
use super::Error;
use crate::gpu::layout::{
    TextureRecord, TEXTURE_BITMAP, TEXTURE_CHECKERBOARD, TEXTURE_CONSTANT, TEXTURE_MARBLE,
    TEXTURE_MESH_ATTRIBUTE, TEXTURE_NEAREST, TEXTURE_NOISE, TEXTURE_WRAP_CLAMP,
    TEXTURE_WRAP_MIRROR, TEXTURE_WRAP_REPEAT, TEXTURE_WRAP_SHIFT,
};

/// How texel indices outside the image are brought back (Mitsuba `wrap_mode`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wrap {
    Repeat,
    Mirror,
    Clamp,
}

/// A texture. Types and parameters as written in a Mitsuba scene:
///
/// - `bitmap`: `filename` (EXR or Radiance HDR: linear; PNG or JPEG: sRGB, converted
///   to linear unless `raw` = true), `filter_type` (`bilinear` | `nearest`, default
///   bilinear), `wrap_mode` (`repeat` | `mirror` | `clamp`, default repeat), `to_uv`.
///   `<texture type="bitmap" name="reflectance"><string name="filename" value="bricks.jpg"/></texture>`
/// - `checkerboard`: `color0` (0.4), `color1` (0.2), `to_uv`; color0 where
///   (u mod 1 > ½) equals (v mod 1 > ½), as Mitsuba's.
/// - `noise` (wavetrace's; Mitsuba has none): Perlin gradient noise (Perlin 2002,
///   "Improving Noise": quintic fade, hashed lattice gradients) summed over `octaves`
///   (4) as fractal Brownian motion, each octave at twice the frequency and half the
///   amplitude; `frequency` (8) lattice cells per unit uv; `seed` (0). The sum n in
///   [-1, 1] blends `color0` (0) and `color1` (1) by t = ½ + ½ n.
///   `<texture type="noise" name="reflectance"><float name="frequency" value="16"/><integer name="octaves" value="5"/></texture>`
/// - `marble` (wavetrace's): stripes along u bent by the same fBm, through a cosine:
///   t = ½ − ½ cos(2π (`frequency` u + `variation` n)); `frequency` (4) stripes per
///   unit u, `variation` (1) the bend in stripe widths, `octaves` (4), `seed` (0),
///   `color0` (0), `color1` (1). (Perlin 1985, "An Image Synthesizer", marble.)
/// - `rawconstant`: `value` (a float or a 3D vector) everywhere, with no color
///   conversion ([`rawconstant`]).
/// - `mesh_attribute`: `name` (`vertex_...` or `face_...`), `scale` (1): the hit
///   mesh's attribute, interpolated over a triangle or constant per face
///   ([`mesh_attribute`]).
#[derive(Debug, Clone, PartialEq)]
pub enum Texture {
    /// Mitsuba `rawconstant`: the value as written, in every channel.
    Constant { value: Vec3 },
    /// Mitsuba `mesh_attribute`: attribute `name` of the mesh hit, times `scale`.
    MeshAttribute { name: String, scale: f32 },
    Bitmap {
        width: u32,
        height: u32,
        /// Linear RGB, row 0 first (at v = 0).
        texels: Vec<[f32; 3]>,
        nearest: bool,
        wrap: Wrap,
        to_uv: [[f32; 3]; 2],
    },
    Checkerboard {
        color0: Vec3,
        color1: Vec3,
        to_uv: [[f32; 3]; 2],
    },
    Noise {
        color0: Vec3,
        color1: Vec3,
        frequency: f32,
        octaves: u32,
        seed: u32,
        to_uv: [[f32; 3]; 2],
    },
    Marble {
        color0: Vec3,
        color1: Vec3,
        frequency: f32,
        variation: f32,
        octaves: u32,
        seed: u32,
        to_uv: [[f32; 3]; 2],
    },
}

/// The identity `to_uv`.
pub const IDENTITY_UV: [[f32; 3]; 2] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

/// Most octaves a noise may sum (more are below float precision).
pub const MAX_OCTAVES: u32 = 16;

/// Every texture type: the supported ones with the parameters they read, then
/// Mitsuba 3's not supported yet (and its volumes, which are no surface textures).
pub const REGISTRY: &[PluginDoc] = &[
    bitmap::MITSUBA,
    checkerboard::MITSUBA,
    noise::MITSUBA,
    marble::MITSUBA,
    rawconstant::MITSUBA,
    mesh_attribute::MITSUBA,
    not_yet("volume"),
    not_yet("constvolume"),
    not_yet("gridvolume"),
];

const fn not_yet(name: &'static str) -> PluginDoc {
    PluginDoc::not_yet(Family::Texture, Dialect::Mitsuba, name)
}

/// `to_uv` of every texture.
const TO_UV: Param = Param::new(
    "to_uv",
    "transform",
    "identity",
    "affine map of the surface uv (rows 0 and 1: x, y and translation)",
);

/// sRGB transfer function to linear (IEC 61966-2-1).
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// How an image file stores its samples (Mitsuba's component format), which decides
/// the storage of a `bitmap` with `format="auto"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Depth {
    /// 8 bits per channel (PNG, JPEG, BMP, TGA, PPM).
    U8,
    /// 16 bits per channel (PNG, PPM).
    U16,
    /// Floats (OpenEXR, RGBE, PFM).
    F32,
}

/// An image file's samples before any conversion: integers normalized to [0, 1],
/// RGB (grey channels repeated, alpha dropped), row 0 = the top of the file.
#[derive(Debug, Clone)]
pub struct SourceImage {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[f32; 3]>,
    pub depth: Depth,
    /// sRGB-encoded (Mitsuba: every integer format), else linear (float formats).
    pub srgb: bool,
}

impl SourceImage {
    /// The texels as linear values: sRGB-decoded unless linear already or `raw`.
    pub fn linear(mut self, raw: bool) -> Vec<[f32; 3]> {
        if self.srgb && !raw {
            for t in &mut self.texels {
                for c in t.iter_mut() {
                    *c = srgb_to_linear(*c);
                }
            }
        }
        self.texels
    }
}

/// Reads an image as linear RGB, row 0 = the top of the file (see [`read_image`]):
/// float formats are linear, integer ones sRGB-decoded unless `raw`.
pub fn load_image(path: &Path, raw: bool) -> Result<(u32, u32, Vec<[f32; 3]>), String> {
    let img = read_image(path)?;
    Ok((img.width, img.height, img.linear(raw)))
}

/// Reads every image format Mitsuba 3 reads (`Bitmap::read`): PNG, JPEG, BMP, TGA and
/// PPM/PNM through the `image` crate, OpenEXR through [`crate::image::exr`], RGBE
/// (`.hdr`) through `image` and PFM through [`crate::image::pfm`]. As Mitsuba, the
/// format comes from the file's first bytes (TGA, which has no signature, and
/// anything unrecognized from the extension), and the integer formats are taken as
/// sRGB-encoded, the float ones as linear. Every message names the file.
pub fn read_image(path: &Path) -> Result<SourceImage, String> {
    if !path.exists() {
        return Err(format!("image file '{}' not found", path.display()));
    }
    let cannot = |e: &dyn std::fmt::Display| format!("cannot read image '{}': {e}", path.display());
    let bytes = std::fs::read(path).map_err(|e| cannot(&e))?;
    let (w, h, texels, depth) = if bytes.starts_with(&[0x76, 0x2f, 0x31, 0x01]) {
        let img =
            crate::image::Image::read_exr(path).map_err(|e| format!("cannot read EXR {e}"))?; // e names the file
        let texels = img.rgb.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
        (img.width, img.height, texels, Depth::F32)
    } else if bytes.starts_with(b"PF") || bytes.starts_with(b"Pf") {
        let (w, h, channels, data) =
            crate::image::pfm::read(path).map_err(|e| format!("cannot read PFM {e}"))?; // e names the file
        let texels = data
            .chunks(channels)
            .map(|c| {
                if channels == 1 {
                    [c[0]; 3]
                } else {
                    [c[0], c[1], c[2]]
                }
            })
            .collect();
        (w, h, texels, Depth::F32)
    } else {
        decode_with_image_crate(path, bytes).map_err(|e| cannot(&e))?
    };
    if w == 0 || h == 0 {
        return Err(format!("image '{}' is empty", path.display()));
    }
    if let Some(bad) = texels.iter().position(|t| t.iter().any(|c| !c.is_finite())) {
        return Err(format!(
            "image '{}' has a NaN or infinite value at pixel ({}, {})",
            path.display(),
            bad as u32 % w,
            bad as u32 / w
        ));
    }
    Ok(SourceImage {
        width: w,
        height: h,
        texels,
        depth,
        srgb: depth != Depth::F32,
    })
}

/// The `image` crate's decoders: the format from the signature, else the extension.
#[allow(clippy::type_complexity)]
fn decode_with_image_crate(
    path: &Path,
    bytes: Vec<u8>,
) -> Result<(u32, u32, Vec<[f32; 3]>, Depth), String> {
    // Mitsuba writes RGBE files as `#?RGBE`, whose signature the crate does not know.
    let format = if bytes.starts_with(b"#?") {
        Ok(image::ImageFormat::Hdr)
    } else {
        image::guess_format(&bytes).or_else(|_| image::ImageFormat::from_path(path))
    }
    .map_err(|e| e.to_string())?;
    let bytes = if format == image::ImageFormat::Hdr {
        radiance_signature(bytes)
    } else {
        bytes
    };
    let reader = || image::ImageReader::with_format(std::io::Cursor::new(&bytes[..]), format);
    // The header first: the decoders allocate from its size, and the float RGB
    // texels below take up to 12 bytes per 1-byte pixel of the file's format.
    let (w, h) = reader().into_dimensions().map_err(|e| e.to_string())?;
    crate::image::check_texels(w.into(), h.into())?;
    let img = reader().decode().map_err(|e| e.to_string())?;
    use image::DynamicImage as D;
    let depth = match img {
        D::ImageRgb32F(_) | D::ImageRgba32F(_) => Depth::F32,
        D::ImageLuma16(_) | D::ImageLumaA16(_) | D::ImageRgb16(_) | D::ImageRgba16(_) => Depth::U16,
        _ => Depth::U8,
    };
    let rgb = img.to_rgb32f();
    let (w, h) = rgb.dimensions();
    Ok((w, h, rgb.pixels().map(|p| p.0).collect(), depth))
}

/// A Radiance HDR file starts with `#?` and the name of the program that wrote it:
/// `#?RADIANCE` mostly, `#?RGBE` from Mitsuba. The `image` crate reads only the
/// first, so another name is replaced by it.
fn radiance_signature(mut bytes: Vec<u8>) -> Vec<u8> {
    const SIGNATURE: &[u8] = b"#?RADIANCE";
    if bytes.starts_with(b"#?") && !bytes.starts_with(SIGNATURE) {
        if let Some(end) = bytes.iter().position(|&b| b == b'\n') {
            bytes.splice(..end, SIGNATURE.iter().copied());
        }
    }
    bytes
}

/// `to_uv` of a Mitsuba `<transform>`: rows 0 and 1, columns x, y, translation.
pub fn to_uv_from(m: Mat4) -> [[f32; 3]; 2] {
    let r = m.transpose();
    [
        [r.x_axis.x, r.x_axis.y, r.x_axis.w],
        [r.y_axis.x, r.y_axis.y, r.y_axis.w],
    ]
}

/// The texture-space point of surface `uv` under the 2 x 3 affine map `m` (`to_uv`).
pub fn apply_uv(m: &[[f32; 3]; 2], uv: Vec2) -> Vec2 {
    Vec2::new(
        m[0][0] * uv.x + m[0][1] * uv.y + m[0][2],
        m[1][0] * uv.x + m[1][1] * uv.y + m[1][2],
    )
}

/// A lookup at `p` (already through `to_uv`) on a `w` x `h` grid of texels, texel
/// (i, j) centred at ((i+½)/w, (j+½)/h), row 0 at v = 0: with `nearest` the texel
/// (⌊pw⌋, ⌊ph⌋), else the bilinear interpolation of the four around p, indices
/// through the wrap mode (`texture_footprint` in texture.glsl). `texel(i, j)` reads a
/// texel, `lerp(a, b, t)` interpolates two. Bitmaps ([`Texture::eval`]) and textured
/// emitters' densities (`TextureSampling::density`) look up their grids through it.
pub fn filtered_lookup<T>(
    p: Vec2,
    (w, h): (u32, u32),
    nearest: bool,
    wrap: Wrap,
    texel: impl Fn(u32, u32) -> T,
    lerp: impl Fn(T, T, f32) -> T,
) -> T {
    let at = |x: i32, y: i32| texel(wrap_index(x, w, wrap), wrap_index(y, h, wrap));
    if nearest {
        return at(
            (p.x * w as f32).floor() as i32,
            (p.y * h as f32).floor() as i32,
        );
    }
    let x = p.x * w as f32 - 0.5;
    let y = p.y * h as f32 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let (x0, y0) = (x0 as i32, y0 as i32);
    let a = lerp(at(x0, y0), at(x0 + 1, y0), fx);
    let b = lerp(at(x0, y0 + 1), at(x0 + 1, y0 + 1), fx);
    lerp(a, b, fy)
}

/// A texel index brought into [0, n) by the wrap mode.
pub fn wrap_index(i: i32, n: u32, wrap: Wrap) -> u32 {
    let n = n as i32;
    match wrap {
        Wrap::Repeat => i.rem_euclid(n) as u32,
        Wrap::Clamp => i.clamp(0, n - 1) as u32,
        Wrap::Mirror => {
            let m = i.rem_euclid(2 * n);
            (if m >= n { 2 * n - 1 - m } else { m }) as u32
        }
    }
}

/// Integer hash of a lattice point (the same in texture.glsl).
pub fn lattice_hash(x: i32, y: i32, seed: u32) -> u32 {
    let mut h = (x as u32).wrapping_mul(0x8da6_b343)
        ^ (y as u32).wrapping_mul(0xd816_3841)
        ^ seed.wrapping_mul(0xcb1a_b31f);
    h ^= h >> 16;
    h = h.wrapping_mul(0x7feb_352d);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846c_a68b);
    h ^= h >> 16;
    h
}

/// Perlin's quintic fade 6t⁵ − 15t⁴ + 10t³ (Perlin 2002).
fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// Dot product of lattice point (x, y)'s gradient, one of eight unit directions, with
/// the offset d.
fn grad(h: u32, d: Vec2) -> f32 {
    const S: f32 = std::f32::consts::FRAC_1_SQRT_2;
    let g = match h & 7 {
        0 => Vec2::new(1.0, 0.0),
        1 => Vec2::new(-1.0, 0.0),
        2 => Vec2::new(0.0, 1.0),
        3 => Vec2::new(0.0, -1.0),
        4 => Vec2::new(S, S),
        5 => Vec2::new(-S, S),
        6 => Vec2::new(S, -S),
        _ => Vec2::new(-S, -S),
    };
    g.dot(d)
}

/// 2D gradient noise in [-1, 1] (scaled by √2 from the unit-gradient range ±√½).
pub fn perlin(p: Vec2, seed: u32) -> f32 {
    let i = p.floor();
    let f = p - i;
    let (x, y) = (i.x as i32, i.y as i32);
    let n00 = grad(lattice_hash(x, y, seed), f);
    let n10 = grad(
        lattice_hash(x.wrapping_add(1), y, seed),
        f - Vec2::new(1.0, 0.0),
    );
    let n01 = grad(
        lattice_hash(x, y.wrapping_add(1), seed),
        f - Vec2::new(0.0, 1.0),
    );
    let n11 = grad(
        lattice_hash(x.wrapping_add(1), y.wrapping_add(1), seed),
        f - Vec2::new(1.0, 1.0),
    );
    let (sx, sy) = (fade(f.x), fade(f.y));
    let a = n00 + sx * (n10 - n00);
    let b = n01 + sx * (n11 - n01);
    std::f32::consts::SQRT_2 * (a + sy * (b - a))
}

/// Fractal Brownian motion: octaves of [`perlin`] at doubling frequency and halving
/// amplitude, normalized to [-1, 1].
pub fn fbm(p: Vec2, octaves: u32, seed: u32) -> f32 {
    let (mut sum, mut amp, mut norm, mut freq) = (0.0f32, 1.0f32, 0.0f32, 1.0f32);
    for o in 0..octaves {
        sum += amp * perlin(p * freq, seed.wrapping_add(o));
        norm += amp;
        amp *= 0.5;
        freq *= 2.0;
    }
    if norm > 0.0 {
        sum / norm
    } else {
        0.0
    }
}

impl Texture {
    /// The texture at surface uv (the CPU reference of `texture_eval`).
    pub fn eval(&self, uv: Vec2) -> Vec3 {
        match self {
            Texture::Constant { value } => *value,
            // Known at a hit only (mesh_attribute::eval): a neutral value here.
            Texture::MeshAttribute { scale, .. } => Vec3::splat(0.5 * scale),
            Texture::Bitmap {
                width,
                height,
                texels,
                nearest,
                wrap,
                to_uv,
            } => filtered_lookup(
                apply_uv(to_uv, uv),
                (*width, *height),
                *nearest,
                *wrap,
                |i, j| Vec3::from(texels[(j * width + i) as usize]),
                Vec3::lerp,
            ),
            Texture::Checkerboard {
                color0,
                color1,
                to_uv,
            } => {
                let p = apply_uv(to_uv, uv);
                let (fu, fv) = (p.x - p.x.floor(), p.y - p.y.floor());
                if (fu > 0.5) == (fv > 0.5) {
                    *color0
                } else {
                    *color1
                }
            }
            Texture::Noise {
                color0,
                color1,
                frequency,
                octaves,
                seed,
                to_uv,
            } => {
                let p = apply_uv(to_uv, uv) * *frequency;
                let t = 0.5 + 0.5 * fbm(p, *octaves, *seed);
                color0.lerp(*color1, t)
            }
            Texture::Marble {
                color0,
                color1,
                frequency,
                variation,
                octaves,
                seed,
                to_uv,
            } => {
                let p = apply_uv(to_uv, uv) * *frequency;
                let n = fbm(p, *octaves, *seed);
                let t = 0.5 - 0.5 * (std::f32::consts::TAU * (p.x + *variation * n)).cos();
                color0.lerp(*color1, t)
            }
        }
    }

    /// Mean over the unit uv square: exact for bitmaps with an identity `to_uv` (the
    /// texel average), else from a 64 x 64 grid of lookups.
    pub fn mean(&self) -> Vec3 {
        if let Texture::Bitmap { texels, to_uv, .. } = self {
            if *to_uv == IDENTITY_UV {
                let sum = texels
                    .iter()
                    .fold(glam::DVec3::ZERO, |s, t| s + Vec3::from(*t).as_dvec3());
                return (sum / texels.len() as f64).as_vec3();
            }
        }
        let n = 64;
        let mut sum = glam::DVec3::ZERO;
        for j in 0..n {
            for i in 0..n {
                let uv = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                sum += self.eval(uv).as_dvec3();
            }
        }
        (sum / (n * n) as f64).as_vec3()
    }

    /// Reads a Mitsuba `<texture type=t>` (element `el`, whose folder relative file
    /// names resolve against): the registry's dispatch.
    pub fn from_mitsuba(t: &str, props: &Properties, el: &Element) -> Result<Texture, Error> {
        // Every texture but rawconstant maps the surface uv first.
        let to_uv = || {
            let to_uv = to_uv_from(props.transform("to_uv")?);
            if to_uv.iter().flatten().any(|v| !v.is_finite()) {
                return Err(props.error("to_uv", "to_uv is not finite"));
            }
            Ok(to_uv)
        };
        let tex = match t {
            "bitmap" => bitmap::mitsuba(props, el, to_uv()?)?,
            "checkerboard" => checkerboard::mitsuba(props, to_uv()?)?,
            "noise" => noise::mitsuba(props, to_uv()?)?,
            "marble" => marble::mitsuba(props, to_uv()?)?,
            "rawconstant" => rawconstant::mitsuba(props)?,
            "mesh_attribute" => mesh_attribute::mitsuba(props)?,
            _ if REGISTRY.iter().any(|p| p.name == t) => {
                return Err(props.object_error(format!("texture type '{t}' is not supported")))
            }
            _ => return Err(props.object_error(format!("unknown texture type '{t}'"))),
        };
        props.finish()?;
        Ok(tex)
    }

    /// The GPU record, with bitmap texels appended to `texels` (three floats each).
    pub fn record(&self, texels: &mut Vec<f32>) -> TextureRecord {
        let uv = |m: &[[f32; 3]; 2]| {
            (
                [m[0][0], m[0][1], m[0][2], 0.0],
                [m[1][0], m[1][1], m[1][2], 0.0],
            )
        };
        match self {
            Texture::Constant { value } => TextureRecord {
                kind: TEXTURE_CONSTANT,
                color0: (*value).into(),
                ..Default::default()
            },
            // Its table of shapes is written with the meshes (mesh_attribute::records).
            Texture::MeshAttribute { .. } => TextureRecord {
                kind: TEXTURE_MESH_ATTRIBUTE,
                ..Default::default()
            },
            Texture::Bitmap {
                width,
                height,
                texels: data,
                nearest,
                wrap,
                to_uv,
            } => {
                let offset = texels.len() as u32;
                texels.extend(data.iter().flatten());
                let wrap = match wrap {
                    Wrap::Repeat => TEXTURE_WRAP_REPEAT,
                    Wrap::Mirror => TEXTURE_WRAP_MIRROR,
                    Wrap::Clamp => TEXTURE_WRAP_CLAMP,
                };
                let (u, v) = uv(to_uv);
                TextureRecord {
                    kind: TEXTURE_BITMAP,
                    offset,
                    width: *width,
                    height: *height,
                    flags: (*nearest as u32 * TEXTURE_NEAREST) | (wrap << TEXTURE_WRAP_SHIFT),
                    to_uv_u: u,
                    to_uv_v: v,
                    ..Default::default()
                }
            }
            Texture::Checkerboard {
                color0,
                color1,
                to_uv,
            } => {
                let (u, v) = uv(to_uv);
                TextureRecord {
                    kind: TEXTURE_CHECKERBOARD,
                    color0: (*color0).into(),
                    color1: (*color1).into(),
                    to_uv_u: u,
                    to_uv_v: v,
                    ..Default::default()
                }
            }
            Texture::Noise {
                color0,
                color1,
                frequency,
                octaves,
                seed,
                to_uv,
            } => {
                let (u, v) = uv(to_uv);
                TextureRecord {
                    kind: TEXTURE_NOISE,
                    color0: (*color0).into(),
                    color1: (*color1).into(),
                    frequency: *frequency,
                    octaves: *octaves,
                    seed: *seed,
                    to_uv_u: u,
                    to_uv_v: v,
                    ..Default::default()
                }
            }
            Texture::Marble {
                color0,
                color1,
                frequency,
                variation,
                octaves,
                seed,
                to_uv,
            } => {
                let (u, v) = uv(to_uv);
                TextureRecord {
                    kind: TEXTURE_MARBLE,
                    color0: (*color0).into(),
                    color1: (*color1).into(),
                    frequency: *frequency,
                    variation: *variation,
                    octaves: *octaves,
                    seed: *seed,
                    to_uv_u: u,
                    to_uv_v: v,
                    ..Default::default()
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bitmap(nearest: bool, wrap: Wrap) -> Texture {
        // 4 x 2, texel (x, y) = (x, y, 0), as the Mitsuba probes below.
        let texels = (0..2)
            .flat_map(|y| (0..4).map(move |x| [x as f32, y as f32, 0.0]))
            .collect();
        Texture::Bitmap {
            width: 4,
            height: 2,
            texels,
            nearest,
            wrap,
            to_uv: IDENTITY_UV,
        }
    }

    /// A Radiance HDR file as Mitsuba 3.9.1 writes it (`mi.Bitmap(...).write`, whose
    /// first line is `#?RGBE`, not `#?RADIANCE`) reads with its values (RGBE keeps
    /// 8 bits of mantissa: 1% of the largest channel).
    #[test]
    fn mitsuba_rgbe_files_read() {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("src/image/testdata/mitsuba_rgbe.hdr");
        assert!(std::fs::read(&path).unwrap().starts_with(b"#?RGBE\n"));
        let (w, h, texels) = load_image(&path, false).unwrap();
        assert_eq!((w, h), (2, 2));
        let want = [
            [0.8, 0.2, 0.1],
            [0.1, 0.7, 0.2],
            [0.2, 0.3, 0.9],
            [1.5, 1.0, 0.5],
        ];
        for (got, want) in texels.iter().zip(want) {
            let max = want.iter().fold(0.0f32, |m, &v| m.max(v));
            for c in 0..3 {
                assert!(
                    (got[c] - want[c]).abs() <= max / 100.0,
                    "{got:?} vs {want:?}"
                );
            }
        }
    }

    /// A 3 x 2 image in every format Mitsuba reads reads back as the same texels: the
    /// integer ones as 8 or 16-bit values marked sRGB, the float ones as written and
    /// linear (RGBE within its 8-bit mantissa), JPEG (lossy) within a few levels.
    #[test]
    fn every_format_reads_the_same_texels() {
        let dir = crate::scene::testutil::temp_dir("formats");
        let bytes: [[u8; 3]; 6] = [
            [0, 64, 255],
            [12, 200, 99],
            [255, 255, 255],
            [1, 2, 3],
            [128, 127, 129],
            [77, 0, 180],
        ];
        let img8 = image::RgbImage::from_fn(3, 2, |x, y| image::Rgb(bytes[(y * 3 + x) as usize]));
        let want8: Vec<[f32; 3]> = bytes.iter().map(|b| b.map(|v| v as f32 / 255.0)).collect();
        for (name, format) in [
            ("t.png", image::ImageFormat::Png),
            ("t.bmp", image::ImageFormat::Bmp),
            ("t.tga", image::ImageFormat::Tga),
            ("t.ppm", image::ImageFormat::Pnm),
        ] {
            let path = dir.join(name);
            img8.save_with_format(&path, format).unwrap();
            let got = read_image(&path).unwrap();
            assert_eq!((got.width, got.height), (3, 2), "{name}");
            assert_eq!((got.depth, got.srgb), (Depth::U8, true), "{name}");
            assert_eq!(got.texels, want8, "{name}");
            // Decoded to linear unless raw.
            let (_, _, lin) = load_image(&path, false).unwrap();
            assert_eq!(lin[1][1], srgb_to_linear(200.0 / 255.0), "{name}");
            assert_eq!(load_image(&path, true).unwrap().2, want8, "{name}");
        }
        // A flat JPEG at top quality: lossy, within 2 levels.
        let flat = image::RgbImage::from_pixel(8, 8, image::Rgb([40, 120, 220]));
        flat.save_with_format(dir.join("t.jpg"), image::ImageFormat::Jpeg)
            .unwrap();
        let got = read_image(&dir.join("t.jpg")).unwrap();
        assert_eq!((got.depth, got.srgb), (Depth::U8, true));
        for t in &got.texels {
            for (c, w) in t.iter().zip([40.0, 120.0, 220.0]) {
                assert!((c * 255.0 - w).abs() <= 2.0, "jpeg {t:?}");
            }
        }
        // 16 bits: PNG and PPM.
        let img16 = image::ImageBuffer::<image::Rgb<u16>, _>::from_fn(3, 2, |x, y| {
            image::Rgb(bytes[(y * 3 + x) as usize].map(|v| v as u16 * 256 + 7))
        });
        let want16: Vec<[f32; 3]> = bytes
            .iter()
            .map(|b| b.map(|v| (v as u16 * 256 + 7) as f32 / 65535.0))
            .collect();
        for name in ["t16.png", "t16.ppm"] {
            let path = dir.join(name);
            img16.save(&path).unwrap();
            let got = read_image(&path).unwrap();
            assert_eq!((got.depth, got.srgb), (Depth::U16, true), "{name}");
            close_texels(&got.texels, &want16, 1e-7, name);
        }
        // Floats: EXR, PFM, RGBE (exact in RGBE: 8-bit mantissas).
        let floats: Vec<f32> = (0..18).map(|i| (i as f32 - 4.0) * 0.125).collect();
        let positive: Vec<f32> = floats.iter().map(|v| v.abs() + 0.25).collect();
        let image = |v: &[f32]| crate::image::Image::from_rgb(3, 2, v.to_vec()).unwrap();
        image(&floats).write_exr(dir.join("t.exr")).unwrap();
        crate::image::pfm::write(dir.join("t.pfm"), 3, 2, 3, &floats).unwrap();
        crate::image::rgbe::write(&image(&positive), dir.join("t.hdr")).unwrap();
        for (name, want) in [("t.exr", &floats), ("t.pfm", &floats), ("t.hdr", &positive)] {
            let got = read_image(&dir.join(name)).unwrap();
            assert_eq!((got.depth, got.srgb), (Depth::F32, false), "{name}");
            let want: Vec<[f32; 3]> = want.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
            close_texels(&got.texels, &want, 0.0, name);
            assert_eq!(
                load_image(&dir.join(name), false).unwrap().2,
                want,
                "{name}"
            );
        }
        // The format comes from the signature, not the name (as Mitsuba's).
        std::fs::copy(dir.join("t.bmp"), dir.join("bmp.png")).unwrap();
        assert_eq!(read_image(&dir.join("bmp.png")).unwrap().texels, want8);
        // Unreadable files name themselves.
        std::fs::write(dir.join("bad.png"), b"\x89PNG\r\n\x1a\nnot really").unwrap();
        std::fs::write(dir.join("bad.xyz"), b"hello").unwrap();
        for bad in ["bad.png", "bad.xyz", "missing.bmp"] {
            let e = read_image(&dir.join(bad)).unwrap_err();
            assert!(e.contains(bad), "{e}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    fn close_texels(got: &[[f32; 3]], want: &[[f32; 3]], tol: f32, name: &str) {
        assert_eq!(got.len(), want.len(), "{name}");
        for (g, w) in got.iter().zip(want) {
            for c in 0..3 {
                assert!((g[c] - w[c]).abs() <= tol, "{name}: {g:?} vs {w:?}");
            }
        }
    }

    /// Values Mitsuba 3.9.1 (scalar_rgb) returns for the same 4 x 2 bitmap.
    #[test]
    fn bitmap_lookups_match_mitsuba() {
        let near = bitmap(true, Wrap::Repeat);
        for (uv, want) in [
            ((0.1, 0.1), [0.0, 0.0]),
            ((0.9, 0.1), [3.0, 0.0]),
            ((0.1, 0.9), [0.0, 1.0]),
            ((0.6, 0.6), [2.0, 1.0]),
        ] {
            let v = near.eval(Vec2::new(uv.0, uv.1));
            assert_eq!([v.x, v.y], want, "nearest at {uv:?}");
        }
        let lin = bitmap(false, Wrap::Repeat);
        for (uv, want) in [
            ((0.0, 0.0), [1.5, 0.5]),
            ((0.125, 0.25), [0.0, 0.0]),
            ((0.25, 0.25), [0.5, 0.0]),
            ((0.01, 0.99), [1.38, 0.52]),
        ] {
            let v = lin.eval(Vec2::new(uv.0, uv.1));
            assert!(
                (v.x - want[0]).abs() < 1e-4 && (v.y - want[1]).abs() < 1e-4,
                "bilinear at {uv:?}: {v}"
            );
        }
        let clamp = bitmap(false, Wrap::Clamp);
        assert_eq!(clamp.eval(Vec2::new(1.3, -0.2)).x, 3.0);
        assert_eq!(clamp.eval(Vec2::new(0.0, 0.0)).x, 0.0);
        let mirror = bitmap(true, Wrap::Mirror);
        for (u, want) in [(1.1, 3.0), (-0.1, 0.0), (2.1, 0.0)] {
            assert_eq!(mirror.eval(Vec2::new(u, 0.1)).x, want, "mirror at {u}");
        }
    }

    #[test]
    fn checkerboard_and_to_uv_match_mitsuba() {
        let c = Texture::Checkerboard {
            color0: Vec3::splat(0.4),
            color1: Vec3::splat(0.2),
            to_uv: IDENTITY_UV,
        };
        assert_eq!(c.eval(Vec2::new(0.1, 0.1)).x, 0.4);
        assert_eq!(c.eval(Vec2::new(0.6, 0.1)).x, 0.2);
        assert_eq!(c.eval(Vec2::new(0.6, 0.6)).x, 0.4);
        // Mitsuba: to_uv = translate(0.25, 0) maps (0.3, 0.7) to texel (2, 1).
        let m = to_uv_from(Mat4::from_translation(Vec3::new(0.25, 0.0, 0.0)));
        let Texture::Bitmap { texels, .. } = bitmap(true, Wrap::Repeat) else {
            unreachable!()
        };
        let t = Texture::Bitmap {
            width: 4,
            height: 2,
            texels,
            nearest: true,
            wrap: Wrap::Repeat,
            to_uv: m,
        };
        assert_eq!(t.eval(Vec2::new(0.3, 0.7)), Vec3::new(2.0, 1.0, 0.0));
    }

    #[test]
    fn noise_is_bounded_and_varies() {
        let mut lo = f32::MAX;
        let mut hi = f32::MIN;
        for i in 0..2000 {
            let p = Vec2::new(i as f32 * 0.0173, (i * 7 % 13) as f32 * 0.31);
            let n = fbm(p, 4, 3);
            lo = lo.min(n);
            hi = hi.max(n);
        }
        assert!((-1.0..=1.0).contains(&lo) && (-1.0..=1.0).contains(&hi));
        assert!(hi - lo > 0.5, "noise barely varies: {lo}..{hi}");
        // Zero at lattice points.
        assert_eq!(perlin(Vec2::new(3.0, -2.0), 0), 0.0);
    }
}
