//! `projector`: a slide projector, as Mitsuba 3's `projector` emitter
//! ([`Emitter::Projector`]): a delta-position light at the origin of `to_world`
//! shining down its +z through an image plane, `irradiance` (a color or a texture)
//! stretched over the plane's field of view (`fov`, `fov_axis` or `focal_length`, the
//! aspect ratio the texture's), times `scale`.
//!
//! At a point x with local coordinates (x, y, z) (z > 0 along the axis) the image
//! coordinate is Mitsuba's perspective projection
//! uv = (½ - ½ x / (z tan_x), ½ - ½ y / (z tan_y)), and the light arriving there is
//! π · scale · irradiance(uv) / (z² cos θ) for θ the angle off the axis (Mitsuba's
//! `sample_direction`: a surface facing the projector at z = 1 on its axis receives
//! π · irradiance). Photons leave through a uniform point of the image rectangle of
//! area A at z = 1 with power π · scale · irradiance(uv) · A (Mitsuba's `sample_ray`,
//! which draws uv by the texture instead: the same expectation).
//!
//! ```xml
//! <emitter type="projector"><float name="fov" value="45"/>
//!     <transform name="to_world"><lookat origin="1,1,1" target="1,2,1" up="0,0,1"/></transform>
//!     <texture type="bitmap" name="irradiance"><string name="filename" value="slide.png"/></texture></emitter>
//! ```

use glam::{Mat4, Vec3};

use super::{Emitter, SAMPLING_WEIGHT};
use crate::gpu::layout::{EmitterRecord, EMITTER_PROJECTOR, NONE};
use crate::scene::builder::Builder;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::texture::Texture;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Emitter,
    Dialect::Mitsuba,
    "projector",
    "A projector at the origin of to_world shining an image down its +z.",
    &[
        Param::new(
            "irradiance",
            "rgb or texture",
            "1",
            "the image: irradiance/π at unit distance on the axis (W/m²)",
        ),
        Param::new("scale", "float", "1", "factor on the irradiance"),
        Param::new(
            "fov",
            "float",
            "",
            "field of view (degrees) along fov_axis; or give focal_length",
        ),
        Param::new(
            "fov_axis",
            "string",
            "x",
            "x, y, diagonal, smaller or larger",
        ),
        Param::new(
            "focal_length",
            "string",
            "50mm",
            "focal length on 35 mm film, instead of fov",
        ),
        Param::new(
            "to_world",
            "transform",
            "identity",
            "places the projector at its origin, looking down +z",
        ),
        SAMPLING_WEIGHT,
    ],
);

/// A Mitsuba `projector` (textures already attached to `props`).
pub fn mitsuba(props: &Properties, b: &Builder) -> Result<Emitter, Error> {
    let mut texture = None;
    for (name, index) in props.textures() {
        if name != "irradiance" {
            return Err(props.error(
                &name,
                format!("'{name}' of a projector cannot be a texture"),
            ));
        }
        texture = Some(index);
    }
    let irradiance = props.color("irradiance", Vec3::ONE)?;
    // The aspect ratio is the texture's (Mitsuba: its resolution, 1 x 1 but for bitmaps).
    let (width, height) = match texture.map(|t| &b.textures[t as usize]) {
        Some(Texture::Bitmap { width, height, .. }) => (*width, *height),
        _ => (1, 1),
    };
    let fov_x_deg = crate::scene::sensor::perspective::parse_fov(props, width, height)? as f32;
    let scale = props.float("scale", 1.0)?;
    if !scale.is_finite() {
        return Err(props.error("scale", format!("scale must be finite, found {scale}")));
    }
    let to_world = props.transform("to_world")?;
    if !(to_world.determinant().abs() > 0.0 && to_world.is_finite()) {
        return Err(props.error("to_world", "the projector's transform is not invertible"));
    }
    Ok(Emitter::Projector {
        to_world,
        irradiance: if texture.is_some() {
            Vec3::ONE
        } else {
            irradiance
        },
        texture,
        scale,
        fov_x_deg,
        aspect: width as f32 / height as f32,
    })
}

/// The GPU record of a projector: `radiance` π · scale · irradiance, `axis` the
/// image-plane normal (to_world's +z, as Mitsuba's, unnormalised), `to_world_*` the
/// rows of world-to-local, `cutoff` and `inv_transition` tan of half the fields of
/// view along x and y, `area` the image rectangle's at z = 1.
pub fn record(
    to_world: Mat4,
    irradiance: Vec3,
    texture: Option<u32>,
    scale: f32,
    fov_x_deg: f32,
    aspect: f32,
) -> EmitterRecord {
    let tan_x = (0.5 * fov_x_deg.to_radians()).tan();
    let tan_y = tan_x / aspect;
    let inv = to_world.inverse().transpose();
    EmitterRecord {
        position: to_world.w_axis.truncate().into(),
        kind: EMITTER_PROJECTOR,
        radiance: (irradiance * scale * std::f32::consts::PI).into(),
        shape: NONE,
        axis: to_world.transform_vector3(Vec3::Z).into(),
        cutoff: tan_x,
        inv_transition: tan_y,
        area: 4.0 * tan_x * tan_y,
        texture: texture.map_or(0, |t| t + 1),
        to_world_x: inv.x_axis.into(),
        to_world_y: inv.y_axis.into(),
        to_world_z: inv.z_axis.into(),
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use crate::scene::testutil::{error_at, load, mitsuba};
    use crate::scene::Emitter;
    use glam::Vec3;

    #[test]
    fn reads_fov_scale_and_texture() {
        let body = r#"<emitter type="projector"><float name="fov" value="90"/><float name="scale" value="2"/>
    <rgb name="irradiance" value="0.5"/></emitter>"#;
        let s = load(&[("s.xml", &mitsuba(body))], &[]).unwrap();
        let Emitter::Projector {
            irradiance,
            texture,
            scale,
            fov_x_deg,
            aspect,
            ..
        } = s.emitters[0]
        else {
            panic!("{:?}", s.emitters[0])
        };
        assert_eq!(
            (irradiance, texture, scale, fov_x_deg, aspect),
            (Vec3::splat(0.5), None, 2.0, 90.0, 1.0)
        );
        let body = r#"<emitter type="projector"><texture type="checkerboard" name="irradiance"/></emitter>"#;
        let s = load(&[("s.xml", &mitsuba(body))], &[]).unwrap();
        assert!(matches!(
            s.emitters[0],
            Emitter::Projector {
                texture: Some(0),
                ..
            }
        ));
        let body =
            r#"<emitter type="projector"><texture type="checkerboard" name="scale"/></emitter>"#;
        let e = error_at(load(&[("s.xml", &mitsuba(body))], &[]), "s.xml", 3);
        assert!(e.contains("cannot be a texture"), "{e}");
    }
}
