//! `directional`: light arriving from one direction at infinity, as Mitsuba 3's
//! `directional` emitter ([`Emitter::Directional`]): every point sees the same
//! `irradiance` (W/m² on a surface facing the light) along `-direction`. A delta light:
//! BSDF-sampled rays never find it. Photons leave a disk as wide as the scene's
//! bounding sphere, facing the direction (Mitsuba's `sample_ray`).
//!
//! ```xml
//! <emitter type="directional"><vector name="direction" value="0,0,-1"/>
//!     <rgb name="irradiance" value="1"/></emitter>
//! ```

use glam::Vec3;

use super::{Emitter, SAMPLING_WEIGHT};
use crate::gpu::layout::{EmitterRecord, EMITTER_DIRECTIONAL, NONE};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Emitter,
    Dialect::Mitsuba,
    "directional",
    "Light from one direction at infinity (a delta light).",
    &[
        Param::new(
            "direction",
            "vector",
            "0,0,1",
            "the direction the light travels (or give to_world)",
        ),
        Param::new(
            "to_world",
            "transform",
            "identity",
            "the light travels along its +z",
        ),
        Param::new(
            "irradiance",
            "rgb",
            "1",
            "irradiance on a surface facing the light (W/m²); not a texture",
        ),
        SAMPLING_WEIGHT,
    ],
);

/// A Mitsuba `directional` emitter.
pub fn mitsuba(props: &Properties) -> Result<Emitter, Error> {
    if let Some((name, _)) = props.textures().first() {
        return Err(props.error(
            name,
            format!(
                "'{name}' of a directional emitter cannot be a texture (it must not vary in space)"
            ),
        ));
    }
    let direction = match (
        props.point_opt("direction")?,
        props.transform_opt("to_world")?,
    ) {
        (Some(_), Some(_)) => {
            return Err(props.error(
                "direction",
                "give either 'direction' or 'to_world', not both",
            ))
        }
        (Some(d), None) => (d, "direction"),
        (None, Some(m)) => (m.transform_vector3(Vec3::Z), "to_world"),
        (None, None) => (Vec3::Z, "direction"),
    };
    let (d, name) = direction;
    if !(d.is_finite() && d.length_squared() > 0.0) {
        return Err(props.error(name, "the light's direction has zero length"));
    }
    Ok(Emitter::Directional {
        direction: d.normalize(),
        irradiance: props.color("irradiance", Vec3::ONE)?,
    })
}

/// The GPU record of a directional light.
pub fn record(direction: Vec3, irradiance: Vec3) -> EmitterRecord {
    EmitterRecord {
        kind: EMITTER_DIRECTIONAL,
        radiance: irradiance.into(),
        axis: direction.into(),
        shape: NONE,
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use crate::scene::testutil::{error_at, load, mitsuba};
    use crate::scene::Emitter;
    use glam::Vec3;

    #[test]
    fn reads_direction_or_to_world() {
        let body = r#"<emitter type="directional"><vector name="direction" value="0,0,-2"/><rgb name="irradiance" value="3"/></emitter>
<emitter type="directional"><transform name="to_world"><lookat origin="0,0,0" target="1,0,0"/></transform></emitter>"#;
        let s = load(&[("s.xml", &mitsuba(body))], &[]).unwrap();
        assert_eq!(
            s.emitters[0],
            Emitter::Directional {
                direction: Vec3::new(0.0, 0.0, -1.0),
                irradiance: Vec3::splat(3.0)
            }
        );
        let Emitter::Directional { direction, .. } = s.emitters[1] else {
            panic!("{:?}", s.emitters[1])
        };
        assert!((direction - Vec3::X).length() < 1e-6, "{direction}");
        for (body, msg) in [
            (
                r#"<emitter type="directional"><vector name="direction" value="0,0,1"/><transform name="to_world"><translate value="1,0,0"/></transform></emitter>"#,
                "not both",
            ),
            (
                r#"<emitter type="directional"><vector name="direction" value="0,0,0"/></emitter>"#,
                "zero length",
            ),
            (
                r#"<emitter type="directional"><texture type="checkerboard" name="irradiance"/></emitter>"#,
                "cannot be a texture",
            ),
        ] {
            let e = error_at(load(&[("s.xml", &mitsuba(body))], &[]), "s.xml", 3);
            assert!(e.contains(msg), "{e}\n  wanted: {msg}");
        }
    }
}
