//! `directionalarea`: an area emitter whose light leaves its shape only along the
//! normal, as Mitsuba 3's `directionalarea` ([`Emitter::DirectionalArea`]). As in
//! Mitsuba, no ray from the camera or a surface can meet it at exactly that angle:
//! emitter sampling gives nothing (its `sample_direction` returns zero), a ray that
//! hits it sees no emission (its `eval` is zero), and only light paths leave it (the
//! particle tracer and the photon mappers: a uniform point of the shape, along the
//! normal there, with power `radiance` times the shape's area, Mitsuba's `sample_ray`).
//! The shape's BSDF defaults to black, as under any emitter.
//!
//! ```xml
//! <shape type="rectangle"><emitter type="directionalarea"><rgb name="radiance" value="1"/></emitter></shape>
//! ```

use glam::Vec3;

use super::Emitter;
use crate::gpu::layout::{EmitterRecord, EMITTER_DIRECTIONAL_AREA, NONE};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Emitter,
    Dialect::Mitsuba,
    "directionalarea",
    "Light leaving the shape it is nested in along the normal only (reached by light paths alone: ptracer, photon mappers).",
    &[
        Param::new("radiance", "rgb", "1", "emitted radiance (power per unit area and steradian)"),
        Param::new("sampling_weight", "float", "1", "how often emitter sampling chooses it"),
    ],
);

/// A Mitsuba `<emitter type="directionalarea">` nested in a shape: the emitter and its
/// sampling weight.
pub fn mitsuba(props: &Properties) -> Result<(Emitter, f32), Error> {
    if props.has("to_world") {
        return Err(props.error(
            "to_world",
            "a directionalarea emitter inherits its placement from its parent shape: it takes no 'to_world'",
        ));
    }
    let radiance = props.color("radiance", Vec3::ONE)?;
    let weight = super::sampling_weight(props)?;
    props.finish()?;
    Ok((Emitter::DirectionalArea { radiance }, weight))
}

/// Its GPU record (the shape it sits on is filled in by the caller, as an area
/// emitter's).
pub fn record(radiance: Vec3) -> EmitterRecord {
    EmitterRecord {
        kind: EMITTER_DIRECTIONAL_AREA,
        radiance: radiance.into(),
        shape: NONE,
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use crate::scene::testutil::{error_at, load};
    use crate::scene::Emitter;
    use glam::Vec3;

    fn scene(body: &str) -> String {
        format!("<scene version=\"3.0.0\">\n<sensor type=\"perspective\"/>\n{body}\n</scene>\n")
    }

    #[test]
    fn sits_on_its_shape() {
        let s = load(
            &[(
                "s.xml",
                &scene(r#"<shape type="rectangle"><emitter type="directionalarea"><rgb name="radiance" value="2, 3, 4"/></emitter></shape>"#),
            )],
            &[],
        )
        .unwrap();
        assert_eq!(
            s.emitters,
            vec![Emitter::DirectionalArea {
                radiance: Vec3::new(2.0, 3.0, 4.0)
            }]
        );
        assert_eq!(s.meshes[0].emitter, Some(0));
        for (body, msg) in [
            (
                r#"<emitter type="directionalarea"/>"#,
                "must be nested in a <shape>",
            ),
            (
                r#"<shape type="disk"><emitter type="directionalarea"><transform name="to_world"/></emitter></shape>"#,
                "inherits its placement",
            ),
        ] {
            let e = error_at(load(&[("s.xml", &scene(body))], &[]), "s.xml", 3);
            assert!(e.contains(msg), "{e}\n  wanted: {msg}");
        }
    }
}
