//! The path tracers: `path_mats`, `path_mis` (Nori's), Mitsuba's `path`, and the
//! volumetric ones `vol_path_simple`, `vol_path_mis`, Mitsuba's `volpath` and
//! `volpathmis`.

use super::{Integrator, Param, Params, PathParams};
use crate::scene::plugin::{Family, Param as Doc, PluginDoc};
use crate::scene::xml::Dialect;

const PARAMS: &[Doc] = &[
    Doc::new(
        "max_depth",
        "integer",
        "-1",
        "longest path in segments; -1 unbounded",
    ),
    Doc::new(
        "rr_depth",
        "integer",
        "5",
        "Russian roulette from this path length on",
    ),
    Doc::new(
        "hide_emitters",
        "boolean",
        "false",
        "camera rays do not see emitters",
    ),
    Doc::new(
        "mis_heuristic",
        "string",
        "power (path_mis, path) or balance",
        "`power` or `balance`: the MIS weights",
    ),
];

const fn doc(name: &'static str, summary: &'static str) -> PluginDoc {
    PluginDoc::new(Family::Integrator, Dialect::Mitsuba, name, summary, PARAMS)
}

pub const PATH_MATS: PluginDoc = doc("path_mats", "Path tracing by BSDF sampling alone.");
pub const PATH_MIS: PluginDoc = doc(
    "path_mis",
    "Path tracing with emitter sampling at every vertex, combined with BSDF sampling by MIS.",
);
pub const PATH: PluginDoc = doc("path", "Mitsuba's name for `path_mis`.");
pub const VOL_PATH_SIMPLE: PluginDoc = doc(
    "vol_path_simple",
    "Volumetric path tracing by phase-function and BSDF sampling alone.",
);
pub const VOL_PATH_MIS: PluginDoc = doc(
    "vol_path_mis",
    "Volumetric path tracing with emitter sampling at surface and medium vertices, MIS.",
);
pub const VOLPATH: PluginDoc = doc("volpath", "Mitsuba's name for `vol_path_mis`.");
pub const VOLPATHMIS: PluginDoc = doc("volpathmis", "Mitsuba's name for `vol_path_mis`.");

/// One of the path tracers.
pub fn read(name: &str, params: &mut Params) -> Result<Integrator, String> {
    let max_depth = match params.remove("max_depth") {
        None | Some(Param::Integer(-1)) => None,
        Some(Param::Integer(d)) if d >= 1 && d <= u32::MAX as i64 / 2 => Some(d as u32),
        Some(p) => {
            return Err(format!(
                "integrator '{name}': max_depth must be -1 (unbounded) or at least 1, got {p:?}"
            ))
        }
    };
    let rr_depth = match params.remove("rr_depth") {
        None => 5,
        Some(Param::Integer(d)) if d >= 1 && d <= u32::MAX as i64 / 2 => d as u32,
        Some(p) => {
            return Err(format!(
                "integrator '{name}': rr_depth must be at least 1, got {p:?}"
            ))
        }
    };
    let hide_emitters = super::hide_emitters(name, params)?;
    let power_heuristic = match params.remove("mis_heuristic") {
        None => matches!(name, "path_mis" | "path"),
        Some(Param::String(s)) if s == "power" => true,
        Some(Param::String(s)) if s == "balance" => false,
        Some(p) => {
            return Err(format!(
                "integrator '{name}': mis_heuristic must be \"power\" or \"balance\", got {p:?}"
            ))
        }
    };
    let params = PathParams {
        max_depth,
        rr_depth,
        hide_emitters,
        power_heuristic,
    };
    Ok(match name {
        "path_mats" => Integrator::PathMats(params),
        "path_mis" | "path" => Integrator::PathMis(params),
        "vol_path_simple" => Integrator::VolPathSimple(params),
        _ => Integrator::VolPathMis(params),
    })
}
