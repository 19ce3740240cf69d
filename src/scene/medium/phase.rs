//! Phase functions, nested in a `<medium>`: `isotropic` (the default) and `hg`
//! (Henyey-Greenstein), each reduced to its asymmetry g (0 for isotropic).
//!
//! ```xml
//! <phase type="hg"><float name="g" value="0.7"/></phase>
//! ```

use crate::scene::plugin::{self, Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::{Dialect, Element};
use crate::scene::Error;

pub const ISOTROPIC: PluginDoc = PluginDoc::new(
    Family::Phase,
    Dialect::Mitsuba,
    "isotropic",
    "Scatters uniformly over the sphere (the default).",
    &[],
);

pub const HG: PluginDoc = PluginDoc::new(
    Family::Phase,
    Dialect::Mitsuba,
    "hg",
    "Henyey-Greenstein.",
    &[Param::new("g", "float", "0.8", "asymmetry, in (-1, 1)")],
);

pub const fn not_yet(name: &'static str) -> PluginDoc {
    PluginDoc::not_yet(Family::Phase, Dialect::Mitsuba, name)
}

/// The asymmetry g of a nested `<phase>`.
pub fn read(el: &Element) -> Result<f32, Error> {
    el.check_attrs(&["type", "id", "name"])?;
    let t = el.require("type")?;
    let (props, nested) = Properties::read(el, Dialect::Mitsuba, false)?;
    if let Some(n) = nested.first() {
        return Err(n.err(format!("unexpected <{}> in a <phase>", n.tag)));
    }
    let g = match t {
        "isotropic" => 0.0,
        "hg" => {
            let g = props.float("g", 0.8)?;
            if !(g > -1.0 && g < 1.0) {
                return Err(props.error("g", format!("hg: g must lie in (-1, 1), found {g}")));
            }
            g
        }
        _ => {
            return Err(plugin::unsupported(
                el,
                Family::Phase,
                Dialect::Mitsuba,
                super::REGISTRY,
            ))
        }
    };
    props.finish()?;
    Ok(g)
}
