//! `heterogeneous`: extinction `scale` × a `sigma_t` volume (a grid, or a constant
//! over its unit cube), delta-tracked through a coarse grid of majorants
//! ([`MediumKind::Grid`]).
//!
//! ```xml
//! <medium type="heterogeneous" id="smoke">
//!     <volume type="gridvolume" name="sigma_t"><string name="filename" value="smoke.vol"/></volume>
//!     <float name="scale" value="4"/>
//! </medium>
//! ```

use glam::{Mat4, Vec3};

use super::{
    check_color, Grid, MediumKind, ALBEDO, BOUNDS_MAX, BOUNDS_MIN, HAS_SPECTRAL_EXTINCTION,
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
    "extinction: a gridvolume, a constvolume or a color (over the unit cube)",
);
const MAJORANT: Param = Param::new(
    "majorant_resolution_factor",
    "integer",
    "8",
    "voxels per majorant cell along each axis, in [0, 1024]; 0: one majorant",
);
const MAJORANT_FACTOR: Param = Param::new("majorant_factor", "float", "", "read and ignored");

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Medium,
    Dialect::Mitsuba,
    "heterogeneous",
    "Extinction from a volume; ends at the sigma_t volume's bounding box.",
    &[
        SIGMA_T,
        ALBEDO,
        SIGMA_A,
        SIGMA_S,
        SCALE,
        SAMPLE_EMITTERS,
        HAS_SPECTRAL_EXTINCTION,
        MAJORANT,
        MAJORANT_FACTOR,
    ],
);

pub const NORI: PluginDoc = PluginDoc::new(
    Family::Medium,
    Dialect::Nori,
    "heterogeneous",
    "Extinction from a volume, the medium filling the box bounds_min .. bounds_max.",
    &[
        SIGMA_T,
        ALBEDO,
        SIGMA_A,
        SIGMA_S,
        SCALE,
        SAMPLE_EMITTERS,
        MAJORANT,
        MAJORANT_FACTOR,
        BOUNDS_MIN,
        BOUNDS_MAX,
    ],
);

/// The extinction of a heterogeneous medium.
pub fn kind(
    props: &Properties,
    dialect: Dialect,
    sigma_t: Option<Vec3>,
    grid: Option<Grid>,
    const_to_world: Mat4,
    scale: f32,
) -> Result<MediumKind, Error> {
    let factor = props.integer("majorant_resolution_factor", 8)?;
    if !(0..=1024).contains(&factor) {
        return Err(props.error(
            "majorant_resolution_factor",
            format!("majorant_resolution_factor must be in [0, 1024], found {factor}"),
        ));
    }
    props.ignore(&["majorant_factor"]);
    let Some(grid) = grid else {
        return constant(props, dialect, sigma_t, const_to_world, scale);
    };
    let top = (0..grid.channels).fold(0.0f32, |m, c| m.max(grid.max(c)));
    if !(top * scale).is_finite() {
        return Err(props.error(
            "scale",
            format!("scale {scale} times the grid's maximum {top} overflows"),
        ));
    }
    Ok(MediumKind::Grid {
        scale: check_color(props, "sigma_t", Vec3::ONE, None)? * scale,
        grid,
        majorant_factor: factor as u32,
    })
}

/// A constant sigma_t. Mitsuba bounds a heterogeneous medium by its sigma_t volume's
/// box, for a constant too (a constvolume's unit cube under its to_world, [0, 1]³ for
/// a plain value): outside it the medium is empty. So it is a grid of one voxel
/// there. Nori's form fills the box it is given: a homogeneous medium.
fn constant(
    props: &Properties,
    dialect: Dialect,
    sigma_t: Option<Vec3>,
    const_to_world: Mat4,
    scale: f32,
) -> Result<MediumKind, Error> {
    let st = check_color(props, "sigma_t", sigma_t.unwrap_or(Vec3::ONE), None)?;
    if dialect != Dialect::Mitsuba {
        return Ok(MediumKind::Homogeneous {
            sigma_t: st * scale,
        });
    }
    if const_to_world.determinant().abs() < 1e-30 || !const_to_world.is_finite() {
        return Err(props.object_error("the sigma_t volume's to_world is not invertible"));
    }
    Ok(MediumKind::Grid {
        grid: Grid {
            res: [1, 1, 1],
            channels: 3,
            data: st.to_array().to_vec(),
            to_world: const_to_world,
        },
        scale: Vec3::splat(scale),
        majorant_factor: 0,
    })
}
