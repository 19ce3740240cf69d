//! The first-hit integrators: `normals`, `ao` and `simple` (Nori's), `depth` (Mitsuba's).

use super::{Integrator, Param, Params};
use crate::scene::plugin::{Family, Param as Doc, PluginDoc};
use crate::scene::xml::Dialect;

pub const NORMALS: PluginDoc = PluginDoc::new(
    Family::Integrator,
    Dialect::Mitsuba,
    "normals",
    "Debug view of the shading normal, |n| per component (Nori's).",
    &[],
);

pub const AO: PluginDoc = PluginDoc::new(
    Family::Integrator,
    Dialect::Mitsuba,
    "ao",
    "Ambient occlusion over the hemisphere of the shading normal (Nori's).",
    &[
        Doc::new(
            "max_t",
            "float",
            "infinity",
            "occluders farther than this are ignored",
        ),
        Doc::new(
            "sampling",
            "string",
            "cosine",
            "`cosine` or `uniform` hemisphere directions",
        ),
    ],
);

pub const SIMPLE: PluginDoc = PluginDoc::new(
    Family::Integrator,
    Dialect::Mitsuba,
    "simple",
    "Point lights on diffuse surfaces with shadows (Nori's).",
    &[],
);

pub const DEPTH: PluginDoc = PluginDoc::new(
    Family::Integrator,
    Dialect::Mitsuba,
    "depth",
    "The distance along the camera ray to the first surface, 0 where it meets nothing (Mitsuba's).",
    &[],
);

/// `normals`, `ao`, `simple` or `depth`.
pub fn read(name: &str, params: &mut Params) -> Result<Integrator, String> {
    Ok(match name {
        "normals" => Integrator::Normals,
        "simple" => Integrator::Simple,
        "depth" => Integrator::Depth,
        _ => ao(params)?,
    })
}

fn ao(params: &mut Params) -> Result<Integrator, String> {
    let max_t = match params.remove("max_t") {
        None => f32::INFINITY,
        Some(Param::Float(v)) if v > 0.0 => v as f32,
        Some(Param::Integer(v)) if v > 0 => v as f32,
        Some(p) => {
            return Err(format!(
                "integrator 'ao': max_t must be a positive float, got {p:?}"
            ))
        }
    };
    let uniform = match params.remove("sampling") {
        None => false,
        Some(Param::String(s)) if s == "cosine" => false,
        Some(Param::String(s)) if s == "uniform" => true,
        Some(p) => {
            return Err(format!(
                "integrator 'ao': sampling must be \"cosine\" or \"uniform\", got {p:?}"
            ))
        }
    };
    Ok(Integrator::Ao { max_t, uniform })
}
