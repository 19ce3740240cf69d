//! `blendbsdf`: a linear blend of two nested BSDFs (Mitsuba 3's `blendbsdf.cpp`):
//! f = (1 − weight) f₀ + weight f₁, the first nested BSDF at weight 0, the second
//! at 1. As Mitsuba's, eval and pdf mix both children by the weight, and sampling
//! picks one child by its weight and weighs the sample by f / pdf of the mix (a delta
//! sample by its child's own weight; [`super::composite`]). The Mitsuba loader reads
//! it (it resolves the nested `<bsdf>`s or `<ref>`s).
//!
//! | parameter | type | default |
//! |-----------|------|---------|
//! | `weight` | float or texture (its luminance), clamped to [0, 1] | (required) |
//!
//! ```xml
//! <bsdf type="blendbsdf"><float name="weight" value="0.3"/><bsdf type="diffuse"/><bsdf type="conductor"/></bsdf>
//! ```

use super::composite::Weight;
use super::Plugin;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const MITSUBA: Plugin = Plugin::loader(PluginDoc::new(
    Family::Bsdf,
    Dialect::Mitsuba,
    "blendbsdf",
    "A linear blend of two nested BSDFs.",
    &[Param::new(
        "weight",
        "float or texture",
        "",
        "weight of the second BSDF (the first has 1 - weight); required",
    )],
));

/// The blend's `weight`, from `props` with its textures attached.
pub fn params(props: &Properties) -> Result<Weight, Error> {
    Weight::read(props, "weight")?
        .ok_or_else(|| props.object_error("blendbsdf needs a 'weight' (a float or a texture)"))
}
