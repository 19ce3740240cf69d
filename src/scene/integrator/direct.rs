//! Direct illumination: `direct_ems`, `direct_mats`, `direct_mis` (Nori's) and
//! Mitsuba's `direct` (`direct_mis` with Mitsuba's power heuristic).

use super::{Integrator, Param, Params};
use crate::scene::plugin::{Family, Param as Doc, PluginDoc};
use crate::scene::xml::Dialect;

const PARAMS: &[Doc] = &[
    Doc::new(
        "hide_emitters",
        "boolean",
        "false",
        "camera rays do not see emitters",
    ),
    Doc::new("emitter_samples", "integer", "1", "only 1 is supported yet"),
    Doc::new("bsdf_samples", "integer", "1", "only 1 is supported yet"),
];

const fn doc(name: &'static str, summary: &'static str) -> PluginDoc {
    PluginDoc::new(Family::Integrator, Dialect::Mitsuba, name, summary, PARAMS)
}

pub const DIRECT_EMS: PluginDoc = doc(
    "direct_ems",
    "Direct illumination by emitter sampling only.",
);
pub const DIRECT_MATS: PluginDoc = doc("direct_mats", "Direct illumination by BSDF sampling only.");
pub const DIRECT_MIS: PluginDoc = doc(
    "direct_mis",
    "Direct illumination by emitter and BSDF sampling, balance heuristic.",
);
pub const DIRECT: PluginDoc = doc(
    "direct",
    "Mitsuba's direct illumination: `direct_mis` with the power heuristic, as Mitsuba's.",
);

/// One of the direct illumination integrators.
pub fn read(name: &str, params: &mut Params) -> Result<Integrator, String> {
    let hide_emitters = super::hide_emitters(name, params)?;
    for key in ["emitter_samples", "bsdf_samples"] {
        match params.remove(key) {
            None | Some(Param::Integer(1)) => {}
            Some(p) => {
                return Err(format!(
                    "integrator '{name}': {key} other than 1 is not supported yet, got {p:?}"
                ))
            }
        }
    }
    Ok(match name {
        "direct_ems" => Integrator::DirectEms { hide_emitters },
        "direct_mats" => Integrator::DirectMats { hide_emitters },
        _ => Integrator::DirectMis {
            hide_emitters,
            // Mitsuba's direct.cpp weighs by the power heuristic, Nori's direct_mis by
            // the balance heuristic.
            power_heuristic: name == "direct",
        },
    })
}
