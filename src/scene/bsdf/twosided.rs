//! `twosided`: one nested BSDF used on both faces, or two, the first for the front
//! and the second for the back (Mitsuba 3's `twosided.cpp`): where wo lies below the
//! surface the shading frame is mirrored, so the back face scatters as a front one.
//! The nested BSDFs must not transmit (nor be masks, whose pass-through Mitsuba counts
//! as transmission). The Mitsuba loader reads it (it resolves the nested `<bsdf>`s or
//! `<ref>`s). Around one model the record is the model's with `BSDF_TWOSIDED` set
//! (`bsdf_flip` in `shaders/bsdf/bsdf.glsl`); two sides, or a composite inside, make a
//! node of [`super::composite`] that picks the side at each hit.
//!
//! ```xml
//! <bsdf type="twosided"><bsdf type="diffuse"/></bsdf>
//! <bsdf type="twosided"><bsdf type="diffuse"/><bsdf type="roughconductor"/></bsdf>
//! ```

use super::{Bsdf, Plugin};
use crate::gpu::layout::{BsdfRecord, BSDF_TWOSIDED};
use crate::scene::plugin::{Family, PluginDoc};
use crate::scene::xml::Dialect;

pub const MITSUBA: Plugin = Plugin::loader(PluginDoc::new(
    Family::Bsdf,
    Dialect::Mitsuba,
    "twosided",
    "One nested BSDF (without transmission) used on both faces, or one per face.",
    &[],
));

/// The record of `inner` used on both faces.
pub(super) fn pack(inner: &Bsdf) -> BsdfRecord {
    let mut r = BsdfRecord::from(inner);
    r.flags |= BSDF_TWOSIDED;
    r
}
