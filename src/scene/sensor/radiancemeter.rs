//! `radiancemeter`: the radiance arriving at one point from one direction, as Mitsuba
//! 3's `radiancemeter` ([`crate::scene::Projection::RadianceMeter`]): every sample is the ray from
//! the origin of `to_world` along its +z (or from `origin` along `direction`, both
//! given), unbounded; the film is 1 x 1 (Mitsuba refuses a film with neither side 1).
//!
//! ```xml
//! <sensor type="radiancemeter"><point name="origin" value="0,1,5"/><vector name="direction" value="0,0,-1"/>
//!     <film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/></film></sensor>
//! ```

use glam::Mat4;

use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Sensor,
    Dialect::Mitsuba,
    "radiancemeter",
    "The radiance arriving at a point from one direction (a 1 x 1 film); nests a <film>, a <sampler> and the <medium> it sits in.",
    &[
        Param::new("to_world", "transform", "identity", "the ray leaves its origin along its +z"),
        Param::new("origin", "point", "", "where the ray starts (with direction, instead of to_world)")
            .with("direction"),
        Param::new("direction", "vector", "", "where the ray goes (with origin)").with("origin"),
    ],
);

/// The sensor's to_world: `to_world`, or a frame at `origin` looking along
/// `direction`; checks the film's size.
pub(super) fn to_world(props: &Properties, width: u32, height: u32) -> Result<Mat4, Error> {
    if width != 1 && height != 1 {
        return Err(props.object_error(format!(
            "a radiancemeter needs a film of 1 x 1 pixels, not {width} x {height}"
        )));
    }
    let origin = props.point_opt("origin")?;
    let direction = props.point_opt("direction")?;
    let m = props.transform_opt("to_world")?;
    match (origin, direction, m) {
        (Some(_), _, Some(_)) | (_, Some(_), Some(_)) => Err(props.error(
            "to_world",
            "give either 'to_world' or 'origin' and 'direction', not both",
        )),
        (Some(o), Some(d), None) => {
            if !(d.is_finite() && d.length_squared() > 0.0) {
                return Err(props.error("direction", "the direction has zero length"));
            }
            let d = d.normalize();
            let x = d.any_orthonormal_vector();
            let y = d.cross(x);
            Ok(Mat4::from_cols(
                x.extend(0.0),
                y.extend(0.0),
                d.extend(0.0),
                o.extend(1.0),
            ))
        }
        (Some(_), None, None) | (None, Some(_), None) => {
            Err(props.object_error("a radiancemeter given by 'origin' and 'direction' needs both"))
        }
        (None, None, m) => Ok(m.unwrap_or(Mat4::IDENTITY)),
    }
}

#[cfg(test)]
mod tests {
    use crate::scene::testutil::{error_at, load};
    use crate::scene::Projection;
    use glam::Vec3;

    fn scene(sensor: &str) -> String {
        format!("<scene version=\"3.0.0\">\n{sensor}\n</scene>\n")
    }
    const FILM: &str = r#"<film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/></film>"#;

    #[test]
    fn reads_origin_and_direction() {
        let s = load(
            &[(
                "s.xml",
                &scene(&format!(r#"<sensor type="radiancemeter"><point name="origin" value="1,2,3"/><vector name="direction" value="0,0,-2"/>{FILM}</sensor>"#)),
            )],
            &[],
        )
        .unwrap();
        assert_eq!(s.camera.projection, Projection::RadianceMeter);
        let m = s.camera.to_world;
        assert!((m.transform_point3(Vec3::ZERO) - Vec3::new(1.0, 2.0, 3.0)).length() < 1e-6);
        assert!((m.transform_vector3(Vec3::Z) - Vec3::NEG_Z).length() < 1e-6);
        for (body, msg) in [
            (r#"<sensor type="radiancemeter"/>"#.to_string(), "1 x 1"),
            (
                format!(
                    r#"<sensor type="radiancemeter"><point name="origin" value="0,0,0"/>{FILM}</sensor>"#
                ),
                "needs both",
            ),
        ] {
            let e = error_at(load(&[("s.xml", &scene(&body))], &[]), "s.xml", 2);
            assert!(e.contains(msg), "{e}\n  wanted: {msg}");
        }
    }
}
