//! Mitsuba's `moment`: renders its nested integrator and adds its mean and second
//! moment as extra channels (for variance estimates), as Mitsuba 3.9's
//! `src/integrators/moment.cpp` names them: `<name>.X/Y/Z`, the nested integrator's
//! image in CIE XYZ, and `m2_<name>.X/Y/Z`, the filter-weighted mean of each sample's
//! XYZ squared (Σ w X² / Σ w per pixel); `<name>` is the nested integrator's `name`
//! (an unnamed one is `_arg_0`, as Mitsuba's parser calls it). The film's R, G, B are
//! the nested integrator's image. wavetrace renders one nested integrator.
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
    "Wraps one nested `<integrator>`, which is rendered, and adds its mean (`<name>.X/Y/Z`) and second moment (`m2_<name>.X/Y/Z`) channels.",
    &[],
);

/// The spec of the one integrator a `moment` wraps, with the moment channels.
pub fn spec(
    el: &Element,
    props: &Properties,
    nested: &[&Element],
    dialect: Dialect,
) -> Result<IntegratorSpec, Error> {
    props.finish()?;
    match nested {
        [inner] if inner.tag == "integrator" => {
            let mut spec = super::spec(inner, dialect)?;
            if spec.outputs != super::aov::Outputs::default() {
                return Err(inner.err(
                    "a moment integrator's nested integrator must be a plain one (not aov or moment) in wavetrace",
                ));
            }
            spec.outputs.moment = Some(inner.attr("name").unwrap_or("_arg_0").to_string());
            Ok(spec)
        }
        _ => Err(el.err(
            "a moment integrator needs exactly one nested <integrator> (wavetrace renders one)",
        )),
    }
}
