//! `thinlens`: a perspective camera with a thin lens, as Mitsuba 3's `thinlens`
//! ([`Projection::ThinLens`]): depth of field. Rays leave a uniform point of the
//! aperture disk (radius `aperture_radius`, the concentric map; shaders/sensor/
//! thinlens.glsl) towards the point where the pinhole ray through the same film
//! position meets the plane at `focus_distance` (default: far_clip); everything else as
//! `perspective` (`fov`, `fov_axis`, `focal_length`, `near_clip`, `far_clip`,
//! `to_world`, which may not scale).
//!
//! ```xml
//! <sensor type="thinlens"><float name="fov" value="45"/>
//!     <float name="aperture_radius" value="0.1"/><float name="focus_distance" value="4"/>
//!     <transform name="to_world"><lookat origin="0,1,5" target="0,1,0" up="0,1,0"/></transform>
//! </sensor>
//! ```

use glam::{Mat4, Vec3};

use super::SensorParts;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::{Dialect, Element};
use crate::scene::{Error, Projection};

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Sensor,
    Dialect::Mitsuba,
    "thinlens",
    "A perspective camera with a thin lens (depth of field); nests a <film>, a <sampler> and the <medium> it sits in.",
    &[
        Param::new("aperture_radius", "float", "", "radius of the lens (required; 0 becomes Mitsuba's epsilon)"),
        Param::new("focus_distance", "float", "far_clip", "distance of the plane in focus"),
        Param::new("fov", "float", "", "field of view (degrees, in (0, 180)) along fov_axis; or give focal_length"),
        Param::new("fov_axis", "string", "x", "x, y, diagonal, smaller or larger"),
        Param::new("focal_length", "string", "50mm", "focal length on 35 mm film, instead of fov"),
        Param::new("near_clip", "float", "0.01", "near clip distance"),
        Param::new("far_clip", "float", "10000", "far clip distance"),
        Param::new("to_world", "transform", "identity", "camera to world (no scale)"),
    ],
);

/// A Mitsuba `<sensor type="thinlens">` (its type already checked).
pub fn mitsuba(el: &Element) -> Result<SensorParts<'_>, Error> {
    super::perspective::projective(el, "thinlens")
}

/// The lens of a thin-lens camera: `aperture_radius`, `focus_distance`; `to_world`
/// must not scale (as in Mitsuba).
pub(super) fn lens(props: &Properties, to_world: Mat4, far_clip: f32) -> Result<Projection, Error> {
    let radius = props
        .float_opt("aperture_radius")?
        .ok_or_else(|| props.object_error("a thinlens sensor needs an 'aperture_radius'"))?;
    if !(radius >= 0.0 && radius.is_finite()) {
        return Err(props.error(
            "aperture_radius",
            format!("aperture_radius must be finite and >= 0, found {radius}"),
        ));
    }
    let focus = props.float("focus_distance", far_clip)?;
    if !(focus > 0.0 && focus.is_finite()) {
        return Err(props.error(
            "focus_distance",
            format!("focus_distance must be finite and > 0, found {focus}"),
        ));
    }
    let (scale, _, _) = to_world.to_scale_rotation_translation();
    if (scale.abs() - Vec3::ONE).abs().max_element() > 1e-3 {
        return Err(props.error(
            "to_world",
            "scale factors in a thinlens camera's to_world are not allowed (as in Mitsuba)",
        ));
    }
    Ok(Projection::ThinLens {
        // Mitsuba replaces 0 by its float epsilon.
        aperture_radius: if radius == 0.0 { f32::EPSILON } else { radius },
        focus_distance: focus,
    })
}

#[cfg(test)]
mod tests {
    use crate::scene::testutil::{error_at, load};
    use crate::scene::Projection;

    fn scene(sensor: &str) -> String {
        format!("<scene version=\"3.0.0\">\n{sensor}\n</scene>\n")
    }

    #[test]
    fn reads_the_lens() {
        let s = load(
            &[(
                "s.xml",
                &scene(r#"<sensor type="thinlens"><float name="aperture_radius" value="0.2"/><float name="focus_distance" value="3"/></sensor>"#),
            )],
            &[],
        )
        .unwrap();
        assert_eq!(
            s.camera.projection,
            Projection::ThinLens {
                aperture_radius: 0.2,
                focus_distance: 3.0
            }
        );
        // focus_distance defaults to far_clip.
        let s = load(
            &[(
                "s.xml",
                &scene(r#"<sensor type="thinlens"><float name="aperture_radius" value="0.2"/><float name="far_clip" value="50"/></sensor>"#),
            )],
            &[],
        )
        .unwrap();
        assert_eq!(
            s.camera.projection,
            Projection::ThinLens {
                aperture_radius: 0.2,
                focus_distance: 50.0
            }
        );
        for (body, msg) in [
            (r#"<sensor type="thinlens"/>"#, "needs an 'aperture_radius'"),
            (
                r#"<sensor type="thinlens"><float name="aperture_radius" value="0.1"/><transform name="to_world"><scale value="2"/></transform></sensor>"#,
                "scale factors",
            ),
        ] {
            let e = error_at(load(&[("s.xml", &scene(body))], &[]), "s.xml", 2);
            assert!(e.contains(msg), "{e}\n  wanted: {msg}");
        }
    }

    #[test]
    fn orthographic_reads_no_fov() {
        let s = load(
            &[(
                "s.xml",
                &scene(
                    r#"<sensor type="orthographic"><float name="near_clip" value="1"/></sensor>"#,
                ),
            )],
            &[],
        )
        .unwrap();
        assert_eq!(s.camera.projection, Projection::Orthographic);
        let e = error_at(
            load(
                &[("s.xml", &scene("<sensor type=\"orthographic\">\n<float name=\"fov\" value=\"30\"/></sensor>"))],
                &[],
            ),
            "s.xml",
            3,
        );
        assert!(e.contains("fov"), "{e}");
    }
}
