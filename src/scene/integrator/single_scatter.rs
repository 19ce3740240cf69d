//! `single_scatter`: light reaching the camera after at most one scattering event.

use super::{Integrator, Param, Params};
use crate::scene::plugin::{Family, Param as Doc, PluginDoc};
use crate::scene::xml::Dialect;

pub const SINGLE_SCATTER: PluginDoc = PluginDoc::new(
    Family::Integrator,
    Dialect::Mitsuba,
    "single_scatter",
    "Single scattering: at most one scattering event, in a medium or at the first surface.",
    &[
        Doc::new(
            "sampling",
            "string",
            "distance",
            "`distance` (free flight) or `equiangular` (Kulla and Fajardo 2012)",
        ),
        Doc::new(
            "hide_emitters",
            "boolean",
            "false",
            "camera rays do not see emitters",
        ),
    ],
);

/// `single_scatter`.
pub fn read(params: &mut Params) -> Result<Integrator, String> {
    let equiangular = match params.remove("sampling") {
        None => false,
        Some(Param::String(s)) if s == "distance" => false,
        Some(Param::String(s)) if s == "equiangular" => true,
        Some(p) => {
            return Err(format!(
                "integrator 'single_scatter': sampling must be \"distance\" or \"equiangular\", got {p:?}"
            ))
        }
    };
    let hide_emitters = super::hide_emitters("single_scatter", params)?;
    Ok(Integrator::SingleScatter {
        equiangular,
        hide_emitters,
    })
}
