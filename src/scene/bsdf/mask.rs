//! `mask`: a BSDF made partly transparent (Mitsuba 3's `mask.cpp`): with probability
//! `opacity` the nested BSDF scatters, otherwise light passes straight through
//! (Mitsuba's null lobe). f = opacity · f_nested, and the pass-through carries
//! 1 − opacity. As in Mitsuba's `path` integrator the pass-through is a delta lobe
//! that counts as a bounce, and shadow rays do not see through a mask (Mitsuba's
//! `ray_test` treats every surface as opaque). As in Mitsuba's `volpath`, the
//! volumetric integrators cross a mask at the root of a shape's BSDF as a null
//! surface with probability 1 − opacity (no bounce, the MIS state kept), and their
//! shadow rays pass it scaled by 1 − opacity (`shaders/bsdf/mask_crossing.glsl`).
//! A mask nested in another composite (a blend's child, a mask's, a bump map's) is
//! crossed likewise with the weight of the tree's pass-throughs, shadow rays seeing
//! none below a bump map (Mitsuba's `eval_null_transmission`, which `bumpmap` does not
//! forward); `twosided` refuses masks, as Mitsuba's. On the GPU the mask is a blend of the
//! pass-through and its nested BSDF by the opacity ([`super::composite`]): eval and
//! pdf are opacity times the nested BSDF's, and sampling picks the pass-through with
//! probability 1 − opacity, as Mitsuba's `mask::sample`. The
//! Mitsuba loader reads it (it resolves the nested `<bsdf>` or `<ref>`).
//!
//! | parameter | type | default |
//! |-----------|------|---------|
//! | `opacity` | float or texture (its luminance), clamped to [0, 1] | (required here; Mitsuba takes 0.5) |
//!
//! ```xml
//! <bsdf type="mask"><texture type="bitmap" name="opacity"><string name="filename" value="leaf.png"/></texture><bsdf type="diffuse"/></bsdf>
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
    "mask",
    "One nested BSDF made partly transparent by an opacity.",
    &[Param::new(
        "opacity",
        "float or texture",
        "",
        "probability of the nested BSDF (else light passes through); required",
    )],
));

/// The mask's `opacity`, from `props` with its textures attached.
pub fn params(props: &Properties) -> Result<Weight, Error> {
    Weight::read(props, "opacity")?
        .ok_or_else(|| props.object_error("mask needs an 'opacity' (a float or a texture)"))
}
