//! `ptracer`: Mitsuba 3's particle tracer. Light paths leave the emitters and every
//! vertex is connected to the camera and splatted into the film; points on area
//! emitters are connected directly (the emitters the camera sees). The sensor: a
//! perspective camera, a thin lens, or an irradiancemeter, whose connections go to a
//! uniform point of its shape with importance cos θx / d², so its film holds the
//! irradiance its path tracer measures (Mitsuba 3.9.1's ptracer weighs them by π
//! alone, which is not: tests/ptracer.rs). render::plan refuses the sensors Mitsuba's
//! has no sample_direction for.

use super::{path, Integrator, Param, Params};
use crate::scene::plugin::{Family, Param as Doc, PluginDoc};
use crate::scene::xml::Dialect;

pub const PTRACER: PluginDoc = PluginDoc::new(
    Family::Integrator,
    Dialect::Mitsuba,
    "ptracer",
    "Particle tracing: light paths from the emitters, each vertex connected to the camera and splatted into the film (Mitsuba's).",
    &[
        Doc::new(
            "max_depth",
            "integer",
            "-1",
            "longest path in segments; -1 unbounded, 1 emitters only",
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
            "the camera does not see emitters",
        ),
        Doc::new(
            "samples_per_pass",
            "integer",
            "spp",
            "Mitsuba's split of the work into passes; accepted, no effect on the image",
        ),
    ],
);

/// `ptracer`: the path tracers' `max_depth`, `rr_depth` and `hide_emitters`.
pub fn read(params: &mut Params) -> Result<Integrator, String> {
    match params.remove("samples_per_pass") {
        None => {}
        Some(Param::Integer(n)) if n >= 1 || n == -1 => {}
        Some(p) => {
            return Err(format!(
                "integrator 'ptracer': samples_per_pass must be a positive integer, got {p:?}"
            ))
        }
    }
    if params.contains_key("mis_heuristic") {
        return Err("integrator 'ptracer' has no parameter 'mis_heuristic'".into());
    }
    match path::read("path", params)? {
        Integrator::PathMis(p) => Ok(Integrator::Ptracer(super::PathParams {
            power_heuristic: false,
            ..p
        })),
        other => unreachable!("path::read(\"path\") reads a path tracer, not {other:?}"),
    }
}
