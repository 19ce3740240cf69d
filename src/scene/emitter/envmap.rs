//! `envmap`: radiance from a lat-long image at infinity ([`Emitter::EnvMap`]; the
//! convention and its sampling in [`crate::scene::envmap`]).
//!
//! ```xml
//! <emitter type="envmap"><string name="filename" value="sky.exr"/><float name="scale" value="2"/></emitter>
//! ```

use super::{Emitter, SAMPLING_WEIGHT};
use crate::gpu::layout::{EmitterRecord, EMITTER_ENVMAP, NONE};
use crate::scene::builder::Builder;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::texture::{self, Texture};
use crate::scene::xml::{Dialect, Element};
use crate::scene::{envmap, Error};

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Emitter,
    Dialect::Mitsuba,
    "envmap",
    "Radiance from a lat-long image at infinity (EXR, Radiance HDR, or PNG/JPEG as sRGB).",
    &[
        Param::new("filename", "string", "", "the image (required)"),
        Param::new(
            "scale",
            "float",
            "1",
            "factor on the radiance, finite and >= 0",
        ),
        Param::new("to_world", "transform", "identity", "a rotation of the map"),
        Param::new(
            "sampling",
            "string",
            "importance",
            "wavetrace's extension: `importance` or `uniform` (sin θ-weighted cells)",
        ),
        Param::new("mis_compensation", "boolean", "false", "read and ignored"),
        SAMPLING_WEIGHT,
    ],
);

/// A Mitsuba `envmap`: loads the image into a texture of `b`.
pub fn mitsuba(el: &Element, props: &Properties, b: &mut Builder) -> Result<Emitter, Error> {
    let name = props
        .string_opt("filename")?
        .ok_or_else(|| props.object_error("envmap needs a 'filename'"))?;
    let path = el
        .resolve(&name)
        .map_err(|tried| props.error("filename", format!("image file {tried} not found")))?;
    let (width, height, texels) =
        texture::load_image(&path, false).map_err(|e| props.error("filename", e))?;
    if height < 2 {
        return Err(props.error("filename", "an envmap needs at least two rows"));
    }
    let scale = props.float("scale", 1.0)?;
    if !(scale >= 0.0 && scale.is_finite()) {
        return Err(props.error(
            "scale",
            format!("scale must be finite and >= 0, found {scale}"),
        ));
    }
    let m = props.transform("to_world")?;
    let to_world = envmap::rotation_of(glam::Mat3::from_mat4(m)).ok_or_else(|| {
        props.error(
            "to_world",
            "an envmap's to_world must be a rotation (no shear, mirroring or non-uniform scale)",
        )
    })?;
    props.ignore(&["mis_compensation"]);
    let importance = match props.string("sampling", "importance")?.as_str() {
        "importance" => true,
        "uniform" => false,
        other => {
            return Err(props.error(
                "sampling",
                format!("sampling must be importance or uniform, found '{other}'"),
            ))
        }
    };
    let texture = b.add_texture(Texture::Bitmap {
        width,
        height,
        texels,
        nearest: false,
        wrap: texture::Wrap::Repeat,
        to_uv: texture::IDENTITY_UV,
    });
    Ok(Emitter::EnvMap {
        texture,
        scale,
        to_world,
        importance,
    })
}

/// The GPU record of an envmap whose bitmap is `textures[texture]`, its sampling
/// distribution appended to `distributions`; and the map's mean luminance.
pub fn record(
    texture: u32,
    scale: f32,
    to_world: glam::Mat3,
    importance: bool,
    textures: &[Texture],
    distributions: &mut Vec<f32>,
) -> (EmitterRecord, f64) {
    let Texture::Bitmap {
        width,
        height,
        texels,
        ..
    } = &textures[texture as usize]
    else {
        unreachable!("the loader gives an envmap a bitmap")
    };
    let dist = envmap::Distribution::build(*width, *height, texels, importance);
    let offset = distributions.len() as u32;
    distributions.extend_from_slice(&dist.cdf);
    let col = |v: glam::Vec3| [v.x, v.y, v.z, 0.0];
    let rec = EmitterRecord {
        kind: EMITTER_ENVMAP,
        radiance: [scale; 3],
        shape: NONE,
        texture: texture + 1,
        dist_offset: offset,
        dist_width: *width,
        dist_height: *height,
        to_world_x: col(to_world.x_axis),
        to_world_y: col(to_world.y_axis),
        to_world_z: col(to_world.z_axis),
        ..Default::default()
    };
    (rec, dist.mean_luminance)
}
