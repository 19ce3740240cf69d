//! `photonmapper`: Nori's photon mapper (Jensen 1996).

use super::{Integrator, Param, Params, PhotonMapperParams};
use crate::scene::plugin::{Family, Param as Doc, PluginDoc};
use crate::scene::xml::Dialect;

pub const PHOTONMAPPER: PluginDoc = PluginDoc::new(
    Family::Integrator,
    Dialect::Mitsuba,
    "photonmapper",
    "Nori's photon mapper: a photon map gathered at the first non-delta camera vertex.",
    &[
        Doc::new("photonCount", "integer", "1000000", "photons stored"),
        Doc::new(
            "photonRadius",
            "float",
            "0",
            "gather radius; 0: the scene's bounding-box diagonal / 500",
        ),
    ],
);

/// `photonmapper`.
pub fn read(params: &mut Params) -> Result<Integrator, String> {
    let photon_count = match params.remove("photonCount") {
        None => 1_000_000,
        Some(Param::Integer(n)) if n >= 1 && n <= u32::MAX as i64 => n as u32,
        Some(p) => {
            return Err(format!(
                "integrator 'photonmapper': photonCount must be a positive integer (photons to store), got {p:?}"
            ))
        }
    };
    let radius = match params.remove("photonRadius") {
        None | Some(Param::Integer(0)) => None,
        Some(Param::Float(0.0)) => None,
        Some(Param::Float(r)) if r > 0.0 && r.is_finite() => Some(r as f32),
        Some(Param::Integer(r)) if r > 0 => Some(r as f32),
        Some(p) => {
            return Err(format!(
                "integrator 'photonmapper': photonRadius must be positive, or 0 for automatic, got {p:?}"
            ))
        }
    };
    Ok(Integrator::PhotonMapper(PhotonMapperParams {
        photon_count,
        radius,
    }))
}
