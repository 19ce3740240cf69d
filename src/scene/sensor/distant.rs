//! `distant`: the radiance leaving the scene in one direction, as Mitsuba 3's
//! `distant` sensor ([`crate::scene::Projection::Distant`]), the adjoint of the
//! `directional` emitter: rays along `direction` (or to_world's +z) from a uniform point
//! of the scene's bounding sphere's cross-section, a sphere radius behind it, or aimed
//! at the point `target` (a shape as target is not supported yet); the film is 1 x 1
//! (Mitsuba refuses a film with neither side 1).
//!
//! ```xml
//! <sensor type="distant"><vector name="direction" value="0,0,-1"/>
//!     <film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/></film></sensor>
//! ```

use glam::{Mat4, Vec3};

use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Sensor,
    Dialect::Mitsuba,
    "distant",
    "The radiance leaving the scene in one direction (a 1 x 1 film); nests a <film>, a <sampler> and the <medium> it sits in.",
    &[
        Param::new("direction", "vector", "0,0,1", "where the rays go (or give to_world)"),
        Param::new("to_world", "transform", "identity", "the rays go along its +z"),
        Param::new("target", "point", "", "the point every ray aims at (default: the bounding sphere's cross-section)"),
    ],
);

/// The sensor's to_world (only its +z matters): `to_world`, or one whose +z is
/// `direction`; checks the film's size.
pub(super) fn to_world(props: &Properties, width: u32, height: u32) -> Result<Mat4, Error> {
    if width != 1 && height != 1 {
        return Err(props.object_error(format!(
            "a distant sensor needs a film of 1 x 1 pixels, not {width} x {height}"
        )));
    }
    match (
        props.point_opt("direction")?,
        props.transform_opt("to_world")?,
    ) {
        (Some(_), Some(_)) => Err(props.error(
            "direction",
            "give either 'direction' or 'to_world', not both",
        )),
        (Some(d), None) => {
            if !(d.is_finite() && d.length_squared() > 0.0) {
                return Err(props.error("direction", "the direction has zero length"));
            }
            let d = d.normalize();
            let x = d.any_orthonormal_vector();
            Ok(Mat4::from_cols(
                x.extend(0.0),
                d.cross(x).extend(0.0),
                d.extend(0.0),
                Vec3::ZERO.extend(1.0),
            ))
        }
        (None, m) => Ok(m.unwrap_or(Mat4::IDENTITY)),
    }
}
