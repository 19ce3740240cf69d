//! `irradiancemeter`: the irradiance over a shape, as Mitsuba 3's `irradiancemeter`
//! ([`crate::scene::Projection::IrradianceMeter`]). It is nested in the shape it
//! measures and takes its place from it (a `to_world` is an error, as in Mitsuba):
//! each sample is a ray from a uniform point of the shape's surface (drawn from the
//! film position, as Mitsuba's `sample_position` draws it from its 2-D sample) in a
//! cosine-weighted direction about the normal there, weighted by π, so a pixel holds
//! the mean irradiance over (its part of) the shape. Mitsuba means it for a film of
//! 1 x 1 pixels with a box filter of radius ½; a larger film spreads the shape's
//! surface parametrization over its pixels, as Mitsuba's does.
//!
//! ```xml
//! <shape type="disk">
//!     <sensor type="irradiancemeter">
//!         <film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/>
//!             <rfilter type="box"/></film>
//!     </sensor>
//! </shape>
//! ```

use glam::Mat4;

use super::SensorParts;
use crate::scene::camera::SensorShape;
use crate::scene::plugin::{Family, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::{Dialect, Element};
use crate::scene::{Error, Projection};

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Sensor,
    Dialect::Mitsuba,
    "irradiancemeter",
    "The irradiance over the shape it is nested in (mean over its surface; a 1 x 1 film with a box filter); nests a <film>, a <sampler> and the <medium> it sits in.",
    &[],
);

/// The sensor's to_world: none of its own (it inherits the shape's placement).
pub(super) fn to_world(props: &Properties) -> Result<Mat4, Error> {
    if props.has("to_world") {
        return Err(props.error(
            "to_world",
            "an irradiancemeter inherits its placement from its parent shape: it takes no 'to_world'",
        ));
    }
    Ok(Mat4::IDENTITY)
}

/// A Mitsuba `<sensor type="irradiancemeter">` nested in `shape`.
pub fn mitsuba(el: &Element, shape: SensorShape) -> Result<SensorParts<'_>, Error> {
    el.check_attrs(&["type", "id", "name"])?;
    let mut parts = super::perspective::projective(el, "irradiancemeter")?;
    parts.0.projection = Projection::IrradianceMeter { shape };
    Ok(parts)
}

#[cfg(test)]
mod tests {
    use crate::scene::camera::SensorShape;
    use crate::scene::testutil::{error_at, load};
    use crate::scene::Projection;

    fn scene(body: &str) -> String {
        format!("<scene version=\"3.0.0\">\n{body}\n</scene>\n")
    }
    const FILM: &str = r#"<film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/></film>"#;

    #[test]
    fn sits_on_its_shape() {
        let s = load(
            &[(
                "s.xml",
                &scene(&format!(
                    r#"<shape type="sphere"/><shape type="disk"><sensor type="irradiancemeter">{FILM}</sensor></shape>"#
                )),
            )],
            &[],
        )
        .unwrap();
        assert_eq!(
            s.camera.projection,
            Projection::IrradianceMeter {
                shape: SensorShape::Quadric(1)
            }
        );
        assert_eq!((s.camera.width, s.camera.height), (1, 1));
        let s = load(
            &[(
                "s.xml",
                &scene(&format!(
                    r#"<shape type="rectangle"><sensor type="irradiancemeter">{FILM}</sensor></shape>"#
                )),
            )],
            &[],
        )
        .unwrap();
        assert_eq!(
            s.camera.projection,
            Projection::IrradianceMeter {
                shape: SensorShape::Mesh(0)
            }
        );
    }

    #[test]
    fn refuses_what_mitsuba_refuses() {
        for (body, msg) in [
            (
                r#"<sensor type="irradiancemeter"/>"#,
                "put it inside a <shape>",
            ),
            (
                r#"<shape type="disk"><sensor type="irradiancemeter"><transform name="to_world"><translate value="1,0,0"/></transform></sensor></shape>"#,
                "inherits its placement",
            ),
            (
                r#"<shape type="disk"><sensor type="perspective"/></shape>"#,
                "carries an irradiancemeter only",
            ),
        ] {
            let e = error_at(load(&[("s.xml", &scene(body))], &[]), "s.xml", 2);
            assert!(e.contains(msg), "{e}\n  wanted: {msg}");
        }
    }

    /// Sensors in document order, those nested in shapes among them, as Mitsuba's
    /// `scene.sensors()` (which `mi.render(scene, sensor=i)` indexes); picking one
    /// makes it the scene's camera, and one out of range says how many there are.
    #[test]
    fn sensors_in_document_order() {
        let mut s = load(
            &[(
                "s.xml",
                &scene(&format!(
                    r#"<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="3"/><integer name="height" value="3"/></film></sensor>
                    <shape type="disk"><sensor type="irradiancemeter">{FILM}</sensor></shape>
                    <sensor type="orthographic"><film type="hdrfilm"><integer name="width" value="2"/><integer name="height" value="2"/></film></sensor>"#
                )),
            )],
            &[],
        )
        .unwrap();
        assert_eq!(s.sensors.len(), 3);
        assert_eq!(s.camera.projection, Projection::Perspective);
        assert!(matches!(
            s.sensors[1].camera.projection,
            Projection::IrradianceMeter { .. }
        ));
        s.select_sensor(2).unwrap();
        assert_eq!(s.camera.projection, Projection::Orthographic);
        assert_eq!((s.camera.width, s.camera.height), (2, 2));
        let e = s.select_sensor(3).unwrap_err();
        assert!(e.contains("has 3 sensors (0 to 2)"), "{e}");
    }
}
