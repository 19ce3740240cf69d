//! `sppm`: stochastic progressive photon mapping (Hachisuka and Jensen 2009), as
//! pbrt-v4's `SPPMIntegrator`; parameters by pbrt-v4's names or Mitsuba 0.6's.

use super::{Integrator, Param, Params, PhotonBudget, SppmParams, MAX_BOUNCES};
use crate::scene::plugin::{Family, Param as Doc, PluginDoc};
use crate::scene::xml::Dialect;

pub const SPPM: PluginDoc = PluginDoc::new(
    Family::Integrator,
    Dialect::Mitsuba,
    "sppm",
    "Stochastic progressive photon mapping, as pbrt-v4's (names of pbrt-v4 or Mitsuba 0.6).",
    &[
        Doc::new(
            "maxdepth",
            "integer",
            "5",
            "camera vertices that sample light and photon bounces; -1 unbounded",
        ),
        Doc::new(
            "maxDepth",
            "integer",
            "5",
            "Mitsuba 0.6's name for maxdepth",
        ),
        Doc::new("radius", "float", "automatic", "initial gather radius"),
        Doc::new(
            "initialRadius",
            "float",
            "0",
            "Mitsuba 0.6's name for radius; 0: automatic",
        ),
        Doc::new(
            "photonsperiteration",
            "integer",
            "-1",
            "photon paths per iteration; -1: the pixel count",
        ),
        Doc::new(
            "photonCount",
            "integer",
            "",
            "photons stored per iteration (Mitsuba 0.6)",
        ),
        Doc::new(
            "alpha",
            "float",
            "2/3",
            "fraction of new photons kept per iteration, in (0, 1)",
        ),
    ],
);

/// A parameter of two names (pbrt-v4's `a`, Mitsuba 0.6's `b`): either, not both.
type Named = Option<(String, Param)>;

fn either(params: &mut Params, a: &str, b: &str) -> Result<Named, String> {
    match (params.remove(a), params.remove(b)) {
        (Some(_), Some(_)) => Err(format!(
            "integrator 'sppm': give either {a} or {b}, not both"
        )),
        (Some(p), None) => Ok(Some((a.to_string(), p))),
        (None, Some(p)) => Ok(Some((b.to_string(), p))),
        (None, None) => Ok(None),
    }
}

/// `sppm`.
pub fn read(params: &mut Params) -> Result<Integrator, String> {
    // pbrt-v4 and Mitsuba 0.6 name the same parameters differently; a scene may use
    // either name, not both.
    let depth = either(params, "maxdepth", "maxDepth")?;
    let radius = either(params, "radius", "initialRadius")?;
    let photons = either(params, "photonsperiteration", "photonCount")?;
    let alpha = params.remove("alpha");
    Ok(Integrator::Sppm(SppmParams {
        max_depth: max_depth(depth)?,
        radius: radius_of(radius)?,
        photons: photons_of(photons)?,
        alpha: alpha_of(alpha)?,
    }))
}

fn max_depth(depth: Named) -> Result<Option<u32>, String> {
    Ok(match depth {
        None => Some(5),
        Some((_, Param::Integer(-1))) => None,
        Some((_, Param::Integer(d))) if d >= 1 && d < MAX_BOUNCES as i64 => Some(d as u32),
        Some((k, p)) => {
            return Err(format!(
                "integrator 'sppm': {k} must be -1 (unbounded) or at least 1, got {p:?}"
            ))
        }
    })
}

fn radius_of(radius: Named) -> Result<Option<f32>, String> {
    Ok(match radius {
        None => None,
        // Mitsuba's initialRadius 0: decide automatically.
        Some((k, Param::Float(r))) if r == 0.0 && k == "initialRadius" => None,
        Some((k, Param::Integer(0))) if k == "initialRadius" => None,
        Some((_, Param::Float(r))) if r > 0.0 && r.is_finite() => Some(r as f32),
        Some((_, Param::Integer(r))) if r > 0 => Some(r as f32),
        Some((k, p)) => {
            return Err(format!(
                "integrator 'sppm': {k} must be positive, got {p:?}"
            ))
        }
    })
}

fn photons_of(photons: Named) -> Result<PhotonBudget, String> {
    Ok(match photons {
        None => PhotonBudget::Emitted(None),
        Some((k, Param::Integer(-1))) if k == "photonsperiteration" => PhotonBudget::Emitted(None),
        Some((k, Param::Integer(n))) if n >= 1 && n <= u32::MAX as i64 => {
            if k == "photonCount" {
                PhotonBudget::Stored(n as u32)
            } else {
                PhotonBudget::Emitted(Some(n as u32))
            }
        }
        Some((k, p)) => {
            return Err(format!(
                "integrator 'sppm': {k} must be a positive integer, got {p:?}"
            ))
        }
    })
}

fn alpha_of(alpha: Option<Param>) -> Result<f32, String> {
    match alpha {
        None => Ok(2.0 / 3.0),
        Some(Param::Float(a)) if a > 0.0 && a < 1.0 => Ok(a as f32),
        Some(p) => Err(format!(
            "integrator 'sppm': alpha must lie strictly between 0 and 1, got {p:?}"
        )),
    }
}
