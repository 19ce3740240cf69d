//! `null`: no surface at all (Mitsuba 3's `null.cpp`): a shape carrying it only
//! bounds media, and rays pass it unchanged. The Mitsuba loader reads it and flags
//! the shapes that carry it (`null_bsdf`); their BSDF record is a diffuse stand-in
//! that is never evaluated.
//!
//! ```xml
//! <shape type="sphere"><bsdf type="null"/><ref name="interior" id="fog"/></shape>
//! ```

use super::Plugin;
use crate::scene::plugin::{Family, PluginDoc};
use crate::scene::xml::Dialect;

pub const MITSUBA: Plugin = Plugin::loader(PluginDoc::new(
    Family::Bsdf,
    Dialect::Mitsuba,
    "null",
    "No surface: the shape only bounds media.",
    &[],
));
