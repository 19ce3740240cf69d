//! Mitsuba's `moment`: renders its nested integrators and adds each one's second
//! moment as extra channels (for variance estimates); wavetrace renders the one
//! nested integrator, and its image is the mean the wrapper reports.
//!
//! ```xml
//! <integrator type="moment"><integrator type="path"/></integrator>
//! ```

use super::IntegratorSpec;
use crate::scene::plugin::{Family, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::{Dialect, Element};
use crate::scene::Error;

pub const MOMENT: PluginDoc = PluginDoc::new(
    Family::Integrator,
    Dialect::Mitsuba,
    "moment",
    "Wraps one nested `<integrator>`, which is rendered (its image is the mean `moment` reports).",
    &[],
);

/// The spec of the one integrator a `moment` wraps.
pub fn spec(
    el: &Element,
    props: &Properties,
    nested: &[&Element],
    dialect: Dialect,
) -> Result<IntegratorSpec, Error> {
    props.finish()?;
    match nested {
        [inner] if inner.tag == "integrator" => super::spec(inner, dialect),
        _ => Err(el.err(
            "a moment integrator needs exactly one nested <integrator> (wavetrace renders one)",
        )),
    }
}
