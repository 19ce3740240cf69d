//! Light sources, as the scene describes them: the emitter family, one file per
//! plugin type (Mitsuba 3's `src/emitters/`), each reading its parameters for both
//! dialects through [`Properties`], and [`REGISTRY`], the one list of every emitter
//! type of both dialects from which the parsers' dispatch and errors and
//! `docs/plugins.md` are derived.

pub mod area;
pub mod constant;
pub mod directional;
pub mod directionalarea;
pub mod distantdisk;
pub mod envmap;
pub mod point;
pub mod projector;
pub mod spot;

use glam::{Mat3, Vec3};

use super::builder::Builder;
use super::plugin::{self, Family, PluginDoc};
use super::properties::Properties;
use super::xml::{Dialect, Element};
use super::Error;

/// Every emitter type of both dialects: the supported ones with the parameters they
/// read, then the Mitsuba 3 types not supported yet.
pub const REGISTRY: &[PluginDoc] = &[
    area::MITSUBA,
    point::MITSUBA,
    spot::MITSUBA,
    constant::MITSUBA,
    envmap::MITSUBA,
    directional::MITSUBA,
    projector::MITSUBA,
    directionalarea::MITSUBA,
    not_yet("sunsky"),
    not_yet("timed_sunsky"),
    // Not a Mitsuba 3 name; kept so such scenes keep hearing "not supported yet".
    not_yet("environment"),
    area::NORI,
    point::NORI,
    distantdisk::NORI,
];

const fn not_yet(name: &'static str) -> PluginDoc {
    PluginDoc::not_yet(Family::Emitter, Dialect::Mitsuba, name)
}

impl Emitter {
    /// Its GPU record (the shape an area emitter sits on is filled in by the caller),
    /// an envmap's sampling distribution appended to `distributions`; and its mean
    /// luminance relative to its radiance (the texture's for a textured emitter), 1
    /// for a uniform one.
    pub fn record(
        &self,
        textures: &[super::Texture],
        distributions: &mut Vec<f32>,
    ) -> (crate::gpu::layout::EmitterRecord, f64) {
        match *self {
            Emitter::Point {
                position,
                intensity,
            } => (point::record(position, intensity), 1.0),
            Emitter::Spot {
                position,
                axis,
                intensity,
                cutoff_deg,
                beam_width_deg,
                texture,
                frame,
            } => (
                spot::record(
                    position,
                    axis,
                    intensity,
                    (cutoff_deg, beam_width_deg),
                    texture,
                    frame,
                ),
                texture.map_or(1.0, |t| {
                    super::envmap::luminance(textures[t as usize].mean()) as f64
                }),
            ),
            Emitter::Directional {
                direction,
                irradiance,
            } => (directional::record(direction, irradiance), 1.0),
            Emitter::Projector {
                to_world,
                irradiance,
                texture,
                scale,
                fov_x_deg,
                aspect,
            } => (
                projector::record(to_world, irradiance, texture, scale, fov_x_deg, aspect),
                texture.map_or(1.0, |t| {
                    super::envmap::luminance(textures[t as usize].mean()) as f64
                }),
            ),
            Emitter::Area { radiance } => (area::record(radiance), 1.0),
            Emitter::DirectionalArea { radiance } => (directionalarea::record(radiance), 1.0),
            Emitter::Constant { radiance } => (constant::record(radiance), 1.0),
            Emitter::TexturedArea { texture, scale } => (
                area::textured_record(texture, scale),
                super::envmap::luminance(textures[texture as usize].mean()) as f64,
            ),
            Emitter::EnvMap {
                texture,
                scale,
                to_world,
                importance,
            } => envmap::record(
                texture,
                scale,
                to_world,
                importance,
                textures,
                distributions,
            ),
        }
    }
}

/// Whether `t` names an emitter type of `dialect` at all (supported or not yet).
pub fn is_known(dialect: Dialect, t: &str) -> bool {
    REGISTRY.iter().any(|p| p.dialect == dialect && p.name == t)
}

/// A top-level Mitsuba emitter that is not `area`, read from its `props` (nested
/// elements already refused): the registry's dispatch.
pub fn mitsuba(
    t: &str,
    el: &Element,
    props: &Properties,
    b: &mut Builder,
) -> Result<Emitter, Error> {
    match t {
        "point" => point::mitsuba(props),
        "spot" => spot::mitsuba(props),
        "directional" => directional::mitsuba(props),
        "projector" => projector::mitsuba(props, b),
        "constant" => constant::mitsuba(props),
        "envmap" => envmap::mitsuba(el, props, b),
        _ => Err(unsupported(el, Dialect::Mitsuba)),
    }
}

/// A top-level Nori emitter, read from its `props`.
pub fn nori(t: &str, el: &Element, props: &Properties) -> Result<Emitter, Error> {
    match t {
        "point" => point::nori(props),
        "distantdisk" => distantdisk::nori(props),
        "area" => Err(el.err("an area emitter must be nested in a <mesh>")),
        _ => Err(unsupported(el, Dialect::Nori)),
    }
}

/// "emitter type 'X' is not supported yet" or "unknown emitter type 'X'".
pub fn unsupported(el: &Element, dialect: Dialect) -> Error {
    plugin::unsupported(el, Family::Emitter, dialect, REGISTRY)
}

/// An emitter's `sampling_weight` (Mitsuba 3: how often emitter sampling chooses it
/// relative to the others; default 1): finite and not negative.
pub fn sampling_weight(props: &Properties) -> Result<f32, Error> {
    let w = props.float("sampling_weight", 1.0)?;
    if !(w.is_finite() && w >= 0.0) {
        return Err(props.error(
            "sampling_weight",
            format!("sampling_weight must be a finite number >= 0, not {w}"),
        ));
    }
    Ok(w)
}

/// `sampling_weight`'s entry in a Mitsuba emitter's parameter list.
pub const SAMPLING_WEIGHT: plugin::Param = plugin::Param::new(
    "sampling_weight",
    "float",
    "1",
    "how often emitter sampling chooses this emitter relative to the others",
);

/// An emitter.
#[derive(Debug, Clone, PartialEq)]
pub enum Emitter {
    /// An isotropic point light. Mitsuba `point` (`position` or `to_world`, `intensity`
    /// in W/sr); Nori `point` (`position`, `power` in W: intensity = power / 4π).
    Point { position: Vec3, intensity: Vec3 },
    /// A spot light at `position` shining along `axis` (Mitsuba `spot`: `intensity`
    /// in W/sr on the axis, `cutoff_angle` (degrees, default 20), `beam_width`
    /// (degrees, default 3/4 of the cutoff), `to_world` placing the light at its
    /// origin looking down its +z). Full intensity inside the beam width, falling
    /// linearly in angle to 0 at the cutoff, as Mitsuba's spotlight.
    ///
    /// ```xml
    /// <emitter type="spot"><transform name="to_world"><lookat origin="0,5,0" target="0,0,0"/></transform>
    ///     <rgb name="intensity" value="10"/><float name="cutoff_angle" value="30"/></emitter>
    /// ```
    Spot {
        position: Vec3,
        axis: Vec3,
        intensity: Vec3,
        cutoff_deg: f32,
        beam_width_deg: f32,
        /// Mitsuba's `texture` (a scene texture) over the cone.
        texture: Option<u32>,
        /// The linear part of to_world (the light's frame, for the texture's uv).
        frame: Mat3,
    },
    /// Mitsuba `directional`: `irradiance` (W/m²) arriving along `-direction` at every
    /// point (`direction`: unit, where the light travels). A delta light at infinity.
    ///
    /// ```xml
    /// <emitter type="directional"><vector name="direction" value="0,0,-1"/><rgb name="irradiance" value="1"/></emitter>
    /// ```
    Directional { direction: Vec3, irradiance: Vec3 },
    /// Mitsuba `projector`: `irradiance` (or the texture `texture`) times `scale`
    /// through an image plane of horizontal field of view `fov_x_deg` and aspect ratio
    /// `aspect` (the texture's), from the origin of `to_world` down its +z
    /// (`emitter::projector` has the formulas).
    Projector {
        to_world: glam::Mat4,
        irradiance: Vec3,
        texture: Option<u32>,
        scale: f32,
        fov_x_deg: f32,
        aspect: f32,
    },
    /// Uniform emission from the surface of the shape that carries it (front side).
    /// Mitsuba and Nori `area` (`radiance`).
    Area { radiance: Vec3 },
    /// Emission along the normal of the shape that carries it, nowhere else: Mitsuba
    /// `directionalarea` (`radiance`). Only light paths leave it (ptracer, photons).
    DirectionalArea { radiance: Vec3 },
    /// Uniform radiance arriving from every direction at infinity. Mitsuba `constant`
    /// (`radiance`); Nori's `distantdisk` with `thetaA` = 180 is the same light.
    Constant { radiance: Vec3 },
    /// An area emitter whose radiance is a texture at the surface's uv times `scale`:
    /// Mitsuba `area` with a nested (or referenced) `<texture name="radiance">`.
    /// A bitmap on a rectangle (any mesh whose uv map is one affine map of the unit
    /// square) or a sphere has its points drawn by the texture's luminance, as Mitsuba
    /// does (`scene::textured_emitter`); other textures and shapes are sampled
    /// uniformly by area and weighted by the texture. Photon emission always samples
    /// by area.
    /// `<emitter type="area"><texture type="checkerboard" name="radiance"><rgb name="color0" value="8"/></texture></emitter>`
    TexturedArea { texture: u32, scale: Vec3 },
    /// Mitsuba `envmap`: radiance from a lat-long image at infinity (`filename`: EXR,
    /// Radiance HDR, or PNG/JPEG as sRGB), times `scale` (1), turned by `to_world` (a
    /// rotation). Convention and sampling in `scene::envmap`. `texture` is the image,
    /// a bitmap among the scene's textures.
    /// `<emitter type="envmap"><string name="filename" value="sky.exr"/><float name="scale" value="2"/></emitter>`
    EnvMap {
        texture: u32,
        scale: f32,
        to_world: Mat3,
        /// wavetrace's `sampling` parameter: `importance` (default) or `uniform`
        /// (sin θ-weighted cells only: uniform over the sphere, for comparisons).
        importance: bool,
    },
}
