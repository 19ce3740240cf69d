//! `twosided`: one nested BSDF used on both faces (Mitsuba 3's `twosided.cpp`): where
//! wo lies below the surface the shading frame is mirrored, so the back face
//! scatters as the front one. The nested BSDF must not transmit; two different
//! sides are not supported yet. The Mitsuba loader reads it (it resolves the nested
//! `<bsdf>` or `<ref>`); the record is the nested model's with `BSDF_TWOSIDED` set
//! (`bsdf_flip` in `shaders/bsdf/bsdf.glsl`).
//!
//! ```xml
//! <bsdf type="twosided"><bsdf type="diffuse"/></bsdf>
//! ```

use super::{Bsdf, Plugin};
use crate::gpu::layout::{BsdfRecord, BSDF_TWOSIDED};
use crate::scene::plugin::{Family, PluginDoc};
use crate::scene::xml::Dialect;

pub const MITSUBA: Plugin = Plugin::loader(PluginDoc::new(
    Family::Bsdf,
    Dialect::Mitsuba,
    "twosided",
    "One nested BSDF (without transmission) used on both faces.",
    &[],
));

/// The record of `inner` used on both faces.
pub(super) fn pack(inner: &Bsdf) -> BsdfRecord {
    let mut r = BsdfRecord::from(inner);
    r.flags |= BSDF_TWOSIDED;
    r
}
