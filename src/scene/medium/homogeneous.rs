//! `homogeneous`: constant extinction `sigma_t` × `scale` ([`MediumKind::Homogeneous`]).
//!
//! ```xml
//! <medium type="homogeneous" name="interior"><rgb name="sigma_t" value="1"/><rgb name="albedo" value="0.9"/></medium>
//! ```

use glam::Vec3;

use super::{
    check_color, MediumKind, ALBEDO, BOUNDS_MAX, BOUNDS_MIN, HAS_SPECTRAL_EXTINCTION,
    SAMPLE_EMITTERS, SCALE, SIGMA_A, SIGMA_S,
};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

const SIGMA_T: Param = Param::new(
    "sigma_t",
    "rgb|volume",
    "1",
    "extinction per unit length (a constvolume at most)",
);

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Medium,
    Dialect::Mitsuba,
    "homogeneous",
    "Constant extinction; a nested <phase> (isotropic by default).",
    &[
        SIGMA_T,
        ALBEDO,
        SIGMA_A,
        SIGMA_S,
        SCALE,
        SAMPLE_EMITTERS,
        HAS_SPECTRAL_EXTINCTION,
    ],
);

pub const NORI: PluginDoc = PluginDoc::new(
    Family::Medium,
    Dialect::Nori,
    "homogeneous",
    "Constant extinction filling the box bounds_min .. bounds_max (an invisible index-matched box).",
    &[
        SIGMA_T,
        ALBEDO,
        SIGMA_A,
        SIGMA_S,
        SCALE,
        SAMPLE_EMITTERS,
        BOUNDS_MIN,
        BOUNDS_MAX,
    ],
);

/// The extinction of a homogeneous medium: `sigma_t` (default 1) × `scale`.
pub fn kind(
    props: &Properties,
    sigma_t: Option<Vec3>,
    has_grid: bool,
    scale: f32,
) -> Result<MediumKind, Error> {
    if has_grid {
        return Err(props.object_error(
            "a homogeneous medium's sigma_t is constant, not a grid (use heterogeneous; its albedo may be a grid)",
        ));
    }
    let st = check_color(props, "sigma_t", sigma_t.unwrap_or(Vec3::ONE), None)?;
    let st = st * scale;
    if !st.is_finite() {
        return Err(props.error("scale", "sigma_t x scale overflows"));
    }
    Ok(MediumKind::Homogeneous { sigma_t: st })
}
