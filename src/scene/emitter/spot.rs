//! `spot`: a spot light ([`Emitter::Spot`]), as Mitsuba 3's spotlight: full intensity
//! inside the beam width, falling linearly in angle to 0 at the cutoff; an optional
//! `texture` (a bitmap) multiplies it, looked up at Mitsuba's
//! uv = ½ + ½ (x, y) / (z tan cutoff) of the direction (x, y, z) in the light's frame.
//!
//! ```xml
//! <emitter type="spot"><transform name="to_world"><lookat origin="0,5,0" target="0,0,0"/></transform>
//!     <rgb name="intensity" value="10"/><float name="cutoff_angle" value="30"/></emitter>
//! ```

use glam::Vec3;

use crate::gpu::layout::{EmitterRecord, EMITTER_SPOT, NONE};

use super::{Emitter, SAMPLING_WEIGHT};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Emitter,
    Dialect::Mitsuba,
    "spot",
    "A spot light at the origin of to_world shining down its +z.",
    &[
        Param::new(
            "to_world",
            "transform",
            "identity",
            "places the light at its origin, looking down +z",
        ),
        Param::new(
            "intensity",
            "rgb",
            "1",
            "radiant intensity on the axis (W/sr)",
        ),
        Param::new(
            "cutoff_angle",
            "float",
            "20",
            "angle (degrees) where the light ends, in (0, 180]",
        ),
        Param::new(
            "beam_width",
            "float",
            "3/4 cutoff_angle",
            "angle (degrees) of full intensity, in [0, cutoff_angle]",
        ),
        Param::new(
            "texture",
            "texture",
            "",
            "a spatially varying texture projected over the cone (uv 0..1 spans tan cutoff_angle)",
        ),
        SAMPLING_WEIGHT,
    ],
);

/// A Mitsuba `spot` emitter.
pub fn mitsuba(props: &Properties) -> Result<Emitter, Error> {
    let mut texture = None;
    for (name, index) in props.textures() {
        match name.as_str() {
            "texture" => texture = Some(index),
            "intensity" => {
                return Err(props.error(
                    &name,
                    "the spot light's 'intensity' cannot vary in space (give 'texture')",
                ))
            }
            _ => {
                return Err(props.error(
                    &name,
                    format!("'{name}' of a spot light cannot be a texture"),
                ))
            }
        }
    }
    if texture.is_none() && props.has("texture") {
        return Err(props.error(
            "texture",
            "the spot light's 'texture' must be spatially varying (e.g. a bitmap)",
        ));
    }
    if texture.is_some() {
        let _ = props.color_opt("texture")?;
    }
    let m = props
        .transform_opt("to_world")?
        .unwrap_or(glam::Mat4::IDENTITY);
    let axis = m.transform_vector3(Vec3::Z);
    if axis.length_squared() == 0.0 || !axis.is_finite() {
        return Err(props.error("to_world", "the spot light's transform collapses its axis"));
    }
    let cutoff_deg = props.float("cutoff_angle", 20.0)?;
    if !(cutoff_deg > 0.0 && cutoff_deg <= 180.0) {
        return Err(props.error("cutoff_angle", "cutoff_angle must lie in (0, 180] degrees"));
    }
    let beam_width_deg = props.float("beam_width", 0.75 * cutoff_deg)?;
    if !(beam_width_deg >= 0.0 && beam_width_deg <= cutoff_deg) {
        return Err(props.error(
            "beam_width",
            "beam_width must lie in [0, cutoff_angle] degrees",
        ));
    }
    Ok(Emitter::Spot {
        position: m.w_axis.truncate(),
        axis: axis.normalize(),
        intensity: props.color("intensity", Vec3::ONE)?,
        cutoff_deg,
        beam_width_deg,
        texture,
        frame: glam::Mat3::from_mat4(m),
    })
}

/// The GPU record of a spot light: with a texture, `texture` is its index + 1,
/// `to_world_*` the rows of world-to-light (of the linear part of to_world, `frame`)
/// and `area` 1 / tan cutoff (the uv scale).
pub fn record(
    position: Vec3,
    axis: Vec3,
    intensity: Vec3,
    (cutoff_deg, beam_width_deg): (f32, f32),
    texture: Option<u32>,
    frame: glam::Mat3,
) -> EmitterRecord {
    let (cutoff, beam) = (cutoff_deg.to_radians(), beam_width_deg.to_radians());
    let mut rec = EmitterRecord {
        position: position.into(),
        kind: EMITTER_SPOT,
        radiance: intensity.into(),
        shape: NONE,
        axis: axis.into(),
        cos_cutoff: cutoff.cos(),
        cutoff,
        // A zero-width transition is a hard edge: a huge slope.
        inv_transition: 1.0 / (cutoff - beam).max(1e-6),
        ..Default::default()
    };
    if let Some(t) = texture {
        let inv = frame.inverse().transpose();
        rec.texture = t + 1;
        rec.area = 1.0 / cutoff.tan();
        rec.to_world_x = inv.x_axis.extend(0.0).into();
        rec.to_world_y = inv.y_axis.extend(0.0).into();
        rec.to_world_z = inv.z_axis.extend(0.0).into();
    }
    rec
}

#[cfg(test)]
mod tests {
    use crate::scene::testutil::{error_at, load, mitsuba};
    use crate::scene::Emitter;

    #[test]
    fn reads_a_texture() {
        let body =
            r#"<emitter type="spot"><texture type="checkerboard" name="texture"/></emitter>"#;
        let s = load(&[("s.xml", &mitsuba(body))], &[]).unwrap();
        assert!(matches!(
            s.emitters[0],
            Emitter::Spot {
                texture: Some(0),
                ..
            }
        ));
        for (body, msg) in [
            (
                r#"<emitter type="spot"><rgb name="texture" value="0.5"/></emitter>"#,
                "must be spatially varying",
            ),
            (
                r#"<emitter type="spot"><texture type="checkerboard" name="intensity"/></emitter>"#,
                "cannot vary in space",
            ),
        ] {
            let e = error_at(load(&[("s.xml", &mitsuba(body))], &[]), "s.xml", 3);
            assert!(e.contains(msg), "{e}\n  wanted: {msg}");
        }
    }
}
