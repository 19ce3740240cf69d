//! Integrators: which wavefront schedule and shading code a render runs, and their
//! parameters as read from the scene.

use std::path::Path;

use crate::scene::integrator::{IntegratorSpec, Param};

use super::error::{Error, Result};

/// An integrator with its parameters read.
#[derive(Debug, Clone, PartialEq)]
pub enum Integrator {
    /// Debug view of the shading normal, |n| per component (Nori's `normals`).
    Normals,
    /// Ambient occlusion (1/π)∫V(x,ω)cosθ dω over the hemisphere of the shading
    /// normal (Nori's `ao`). Camera rays that hit nothing are black, as in Nori.
    ///
    /// Parameters: `max_t` (float, default infinity): occluders farther than this are
    /// ignored, so a closed room is not black; `sampling` (string, `cosine` (default)
    /// or `uniform`): how hemisphere directions are drawn.
    ///
    /// ```xml
    /// <integrator type="ao"><float name="max_t" value="2"/></integrator>
    /// ```
    Ao { max_t: f32, uniform: bool },
    /// Point lights on diffuse surfaces with shadows (Nori's `simple`): one point
    /// light chosen uniformly per sample, L = (ρ/π) I cosθ / d². Uses the surface's
    /// diffuse reflectance where Nori's assignment assumes ρ = 1.
    Simple,
    /// Direct illumination by emitter sampling only (Nori's `direct_ems`).
    DirectEms { hide_emitters: bool },
    /// Direct illumination by BSDF sampling only (Nori's `direct_mats`).
    DirectMats { hide_emitters: bool },
    /// Direct illumination combining emitter and BSDF sampling with the balance
    /// heuristic (Nori's `direct_mis`; Mitsuba's `direct`). Parameter
    /// `hide_emitters` (default false): camera rays do not see emitters.
    DirectMis { hide_emitters: bool },
    /// Path tracing by BSDF sampling alone (Nori's `path_mats`).
    PathMats(PathParams),
    /// Path tracing with emitter sampling at every vertex, combined with BSDF
    /// sampling by multiple importance sampling (Nori's `path_mis`; Mitsuba's `path`).
    ///
    /// Parameters: `max_depth` (integer, default -1 = unbounded; 1 shows emitters
    /// only, 2 direct light), `rr_depth` (integer, default 5: Russian roulette from
    /// that path length on, survival probability min(max throughput, 0.99)),
    /// `hide_emitters` (boolean, default false), `mis_heuristic` (string, `power`
    /// (default, as Mitsuba's `path` and pbrt-v4) or `balance` (Nori's)): the weights
    /// of the two strategies (Veach 1997, sec. 9.2). Both are unbiased; on the shipped
    /// Cornell box the power heuristic's relMSE at equal spp is 4% lower.
    ///
    /// ```xml
    /// <integrator type="path"><integer name="max_depth" value="8"/></integrator>
    /// ```
    PathMis(PathParams),
    /// Volumetric path tracing by phase-function and BSDF sampling alone: free-flight
    /// distances by delta tracking (closed form in homogeneous media), null surfaces
    /// passed straight through. Parameters as `path_mis`.
    VolPathSimple(PathParams),
    /// Volumetric path tracing with emitter sampling at surface and medium vertices
    /// (transmittance of the shadow ray by ratio tracking, closed form in homogeneous
    /// media), combined with BSDF and phase sampling by the balance heuristic
    /// (Mitsuba's `volpath` and `volpathmis`). Parameters as `path_mis`, but
    /// `mis_heuristic` defaults to `balance`.
    ///
    /// ```xml
    /// <integrator type="volpath"><integer name="max_depth" value="16"/></integrator>
    /// ```
    VolPathMis(PathParams),
    /// Single scattering: light reaching the camera after at most one scattering event
    /// (in a medium, or direct lighting at the first surface with BSDF/emitter MIS),
    /// attenuated by every medium on the way; the same expectation as `vol_path_mis`
    /// with max_depth 2. Parameter `sampling`: `distance` (default; free-flight
    /// sampling) or `equiangular` (Kulla and Fajardo 2012: camera-ray distances
    /// towards the point of light chosen for the scattering point, for point, spot
    /// and mesh lights; others get equiangular towards the point first sampled);
    /// `hide_emitters` (default false).
    ///
    /// ```xml
    /// <integrator type="single_scatter"><string name="sampling" value="equiangular"/></integrator>
    /// ```
    SingleScatter {
        equiangular: bool,
        hide_emitters: bool,
    },
    /// Nori's photon mapper (`photonmapper`; Jensen 1996, "Global Illumination using
    /// Photon Maps"): photon paths leave the emitters (one chosen uniformly, as Nori's
    /// `Scene::getRandomEmitter`), travel by BSDF sampling with Russian roulette and
    /// store a photon at every surface whose BSDF is not a delta, the first included,
    /// until `photonCount` photons are stored. Camera paths add the emission they
    /// find, follow delta BSDFs (mirror, dielectric) by sampling, and at the first
    /// other surface return the density estimate Σ f(wo, wi_p) Φ_p / (π r² N) over the
    /// photons within r, N the photon paths emitted. Photons are stored in a hash grid
    /// built on the GPU (`render::photon`).
    ///
    /// Parameters: `photonCount` (integer, default 1,000,000: photons stored),
    /// `photonRadius` (float, default 0 = automatic: the scene's bounding-box diagonal
    /// / 500, as Nori).
    ///
    /// ```xml
    /// <integrator type="photonmapper"><integer name="photonCount" value="2000000"/></integrator>
    /// ```
    PhotonMapper(PhotonMapperParams),
    /// Stochastic progressive photon mapping (Hachisuka and Jensen 2009, "Stochastic
    /// Progressive Photon Mapping"), as pbrt-v4's `SPPMIntegrator`: each iteration (one
    /// per sample per pixel) traces one camera path per pixel, adding the light it
    /// finds by emitter and BSDF sampling (power heuristic) to the pixel, to a visible
    /// point at the first surface with a diffuse part (or any non-delta one at the last
    /// depth); then photon paths leave the emitters (chosen by power) and the photons
    /// they store from their second surface on are gathered at each pixel's visible
    /// point within the pixel's radius r; then N' = N + αM, r' = r √(N'/(N+M)),
    /// τ' = (τ + Φ)(r'/r)². The pixel is Ld / iterations + τ / (N_p π r²), N_p the photon
    /// paths emitted in all. Consistent: the error keeps falling with iterations.
    ///
    /// Parameters, by pbrt-v4's names or Mitsuba 0.6's: `maxdepth` / `maxDepth`
    /// (integer, default 5; -1 unbounded): camera vertices that sample light and photon
    /// bounces; `radius` / `initialRadius` (float, default automatic, Mitsuba's rule:
    /// 5 × the scene's bounding-sphere radius / the film's larger side); photons per
    /// iteration, either `photonsperiteration` (integer, photon paths emitted; default
    /// and -1: the pixel count) or `photonCount` (integer, photons stored, as Mitsuba
    /// 0.6 counts them); `alpha` (float in (0, 1), default 2/3).
    ///
    /// ```xml
    /// <integrator type="sppm"><integer name="maxdepth" value="8"/><float name="radius" value="0.05"/></integrator>
    /// ```
    Sppm(SppmParams),
}

/// Parameters of the photon mapper.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhotonMapperParams {
    /// Photons to store.
    pub photon_count: u32,
    /// Gather radius; `None`: the scene's bounding-box diagonal / 500.
    pub radius: Option<f32>,
}

/// How many photons an iteration of SPPM shoots.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PhotonBudget {
    /// Photon paths emitted (pbrt-v4's `photonsperiteration`); `None`: the pixel count.
    Emitted(Option<u32>),
    /// Photons stored (Mitsuba 0.6's `photonCount`): paths are emitted until that many
    /// photons are stored.
    Stored(u32),
}

/// Parameters of SPPM.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SppmParams {
    /// pbrt-v4's `maxdepth`: camera vertices that sample light and photon bounces;
    /// `None`: unbounded.
    pub max_depth: Option<u32>,
    /// Initial gather radius; `None`: automatic.
    pub radius: Option<f32>,
    pub photons: PhotonBudget,
    /// Fraction of new photons kept per iteration (α).
    pub alpha: f32,
}

/// Parameters of the path tracers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathParams {
    /// Longest path in segments, `None` for unbounded.
    pub max_depth: Option<u32>,
    pub rr_depth: u32,
    pub hide_emitters: bool,
    /// MIS weights by the power heuristic (β = 2) instead of the balance heuristic.
    pub power_heuristic: bool,
}

/// Most bounces the host records for one batch: a safety net for paths that would
/// never end (a closed mirror box with Russian roulette put off by a huge `rr_depth`).
/// Unbounded paths (`max_depth` -1) and longer `max_depth`s stop here; paths still
/// alive then are cut, counted in [`RenderStats::cut_paths`](super::RenderStats) and
/// reported by `render`. Below it nothing is truncated: a batch records bounces 64 at a
/// time and stops once its ray queue is empty (`Renderer::run_batch`), so the budget
/// costs nothing where Russian roulette ends paths sooner (with survival capped at
/// 0.99, a path outlives 2000 bounces past `rr_depth` with probability < 2e-9).
pub const MAX_BOUNCES: u32 = 1 << 16;

/// Camera paths of the photon mappers play Russian roulette from this depth on, as
/// the path tracers do by default.
pub const PHOTON_CAMERA_RR_DEPTH: u32 = 5;

/// The parameters an integrator reads.
fn parameter_names(name: &str) -> &'static [&'static str] {
    match name {
        "ao" => &["max_t", "sampling"],
        "direct_ems" | "direct_mats" | "direct_mis" | "direct" => {
            &["hide_emitters", "emitter_samples", "bsdf_samples"]
        }
        "path_mats" | "path_mis" | "path" | "vol_path_simple" | "vol_path_mis" | "volpath"
        | "volpathmis" => &["max_depth", "rr_depth", "hide_emitters", "mis_heuristic"],
        "single_scatter" => &["sampling", "hide_emitters"],
        "photonmapper" => &["photonCount", "photonRadius"],
        "sppm" => &[
            "maxdepth",
            "maxDepth",
            "radius",
            "initialRadius",
            "photonsperiteration",
            "photonCount",
            "alpha",
        ],
        _ => &[],
    }
}

/// Names `--integrator` and scenes may use in this version.
pub const NAMES: &[&str] = &[
    "normals",
    "ao",
    "simple",
    "direct_ems",
    "direct_mats",
    "direct_mis",
    "direct",
    "path_mats",
    "path_mis",
    "path",
    "vol_path_simple",
    "vol_path_mis",
    "volpath",
    "volpathmis",
    "single_scatter",
    "photonmapper",
    "sppm",
];

impl Integrator {
    /// The id of the shading code (`INTEGRATOR_*` in shaders/integrator/integrator.glsl).
    pub fn id(&self) -> u32 {
        match self {
            Integrator::Normals => 0,
            Integrator::Ao { .. } => 1,
            Integrator::Simple => 2,
            Integrator::DirectEms { .. } => 3,
            Integrator::DirectMats { .. } => 4,
            Integrator::DirectMis { .. } => 5,
            Integrator::PathMats(_) => 6,
            Integrator::PathMis(_) => 7,
            Integrator::VolPathSimple(_) => 8,
            Integrator::VolPathMis(_) => 9,
            Integrator::SingleScatter {
                equiangular: false, ..
            } => 10,
            Integrator::SingleScatter { .. } => 11,
            Integrator::PhotonMapper(_) => 12,
            Integrator::Sppm(_) => 13,
        }
    }

    /// Whether the integrator follows light through media.
    pub fn is_volumetric(&self) -> bool {
        matches!(
            self,
            Integrator::VolPathSimple(_)
                | Integrator::VolPathMis(_)
                | Integrator::SingleScatter { .. }
        )
    }

    pub fn name(&self) -> &'static str {
        match self {
            Integrator::Normals => "normals",
            Integrator::Ao { .. } => "ao",
            Integrator::Simple => "simple",
            Integrator::DirectEms { .. } => "direct_ems",
            Integrator::DirectMats { .. } => "direct_mats",
            Integrator::DirectMis { .. } => "direct_mis",
            Integrator::PathMats(_) => "path_mats",
            Integrator::PathMis(_) => "path_mis",
            Integrator::VolPathSimple(_) => "vol_path_simple",
            Integrator::VolPathMis(_) => "vol_path_mis",
            Integrator::SingleScatter { .. } => "single_scatter",
            Integrator::PhotonMapper(_) => "photonmapper",
            Integrator::Sppm(_) => "sppm",
        }
    }

    /// Longest path in segments (`u32::MAX`: unbounded), as the kernels see it.
    pub fn max_depth(&self) -> u32 {
        match self {
            Integrator::Normals | Integrator::Ao { .. } | Integrator::Simple => 1,
            Integrator::DirectEms { .. }
            | Integrator::DirectMats { .. }
            | Integrator::DirectMis { .. }
            | Integrator::SingleScatter { .. } => 2,
            Integrator::PathMats(p)
            | Integrator::PathMis(p)
            | Integrator::VolPathSimple(p)
            | Integrator::VolPathMis(p) => p.max_depth.unwrap_or(u32::MAX),
            Integrator::PhotonMapper(_) => u32::MAX,
            // pbrt's maxdepth d samples light at camera vertices 0 .. d-1: d + 1 segments.
            Integrator::Sppm(p) => p.max_depth.map_or(u32::MAX, |d| d + 1),
        }
    }

    /// Bounces the host dispatches: one per path vertex that can still add light.
    pub fn bounces(&self) -> u32 {
        match self {
            Integrator::Normals
            | Integrator::Ao { .. }
            | Integrator::Simple
            | Integrator::DirectEms { .. } => 1,
            Integrator::DirectMats { .. }
            | Integrator::DirectMis { .. }
            | Integrator::SingleScatter { .. } => 2,
            Integrator::PathMats(p)
            | Integrator::PathMis(p)
            | Integrator::VolPathSimple(p)
            | Integrator::VolPathMis(p) => p.max_depth.unwrap_or(MAX_BOUNCES).min(MAX_BOUNCES),
            Integrator::PhotonMapper(_) => MAX_BOUNCES,
            Integrator::Sppm(p) => p
                .max_depth
                .map_or(MAX_BOUNCES, |d| (d + 1).min(MAX_BOUNCES)),
        }
    }

    /// Whether bounce `depth` of a path batch only ends paths: `shade` (path.glsl)
    /// adds the emission its rays find and spawns nothing, since a further vertex
    /// would exceed max_depth (depth + 2 > max_depth). The renderer runs such
    /// bounces with `shade_last`, whose BSDF and sampling code compiles away. Only
    /// where `shade` runs path vertices ([`Self::shades_paths`]).
    pub fn ends_paths_at(&self, depth: u32) -> bool {
        self.shades_paths() && depth.saturating_add(2) > self.max_depth()
    }

    /// Whether `shade` runs the path vertices of path.glsl (direct lighting, path
    /// tracers, volumetric ones): not the first-hit integrators (first_hit.glsl) nor
    /// the photon mappers (their own kernels).
    pub fn shades_paths(&self) -> bool {
        let first_hit = matches!(
            self,
            Integrator::Normals | Integrator::Ao { .. } | Integrator::Simple
        );
        !first_hit && !self.is_photon_mapper()
    }

    /// Whether the integrator is a photon mapper (`render::photon` runs it).
    pub fn is_photon_mapper(&self) -> bool {
        matches!(self, Integrator::PhotonMapper(_) | Integrator::Sppm(_))
    }

    /// Russian roulette start depth (segments); never for non-path integrators.
    pub fn rr_depth(&self) -> u32 {
        match self {
            Integrator::PathMats(p)
            | Integrator::PathMis(p)
            | Integrator::VolPathSimple(p)
            | Integrator::VolPathMis(p) => p.rr_depth,
            Integrator::PhotonMapper(_) | Integrator::Sppm(_) => PHOTON_CAMERA_RR_DEPTH,
            _ => u32::MAX,
        }
    }

    /// Whether the image comes from emitters (everything but the `normals` and `ao`
    /// views): a scene without any renders black.
    pub fn needs_emitters(&self) -> bool {
        !matches!(self, Integrator::Normals | Integrator::Ao { .. })
    }

    /// Whether MIS weighs by the power heuristic (else the balance heuristic).
    pub fn power_heuristic(&self) -> bool {
        match self {
            Integrator::PathMis(p) | Integrator::VolPathMis(p) => p.power_heuristic,
            // pbrt-v4's SPPM weighs emitter and BSDF sampling by the power heuristic.
            Integrator::Sppm(_) => true,
            _ => false,
        }
    }

    /// Whether a visible environment makes every camera path count as covered for the
    /// film's alpha: Mitsuba's `path` and `volpath` start `valid_ray` as "emitters
    /// visible and an environment present"; its `direct` and first-hit integrators
    /// count only camera rays that hit something.
    pub fn counts_environment_coverage(&self) -> bool {
        matches!(
            self,
            Integrator::PathMats(_)
                | Integrator::PathMis(_)
                | Integrator::VolPathSimple(_)
                | Integrator::VolPathMis(_)
                | Integrator::SingleScatter { .. }
        )
    }

    /// Whether camera rays skip the emission of the emitters they hit.
    pub fn hide_emitters(&self) -> bool {
        match self {
            Integrator::DirectEms { hide_emitters }
            | Integrator::DirectMats { hide_emitters }
            | Integrator::DirectMis { hide_emitters }
            | Integrator::SingleScatter { hide_emitters, .. } => *hide_emitters,
            Integrator::PathMats(p)
            | Integrator::PathMis(p)
            | Integrator::VolPathSimple(p)
            | Integrator::VolPathMis(p) => p.hide_emitters,
            _ => false,
        }
    }

    /// Reads the integrator the scene names, or `override_name` instead (the scene's
    /// parameters apply only if the override names the same integrator).
    pub fn from_spec(
        spec: &IntegratorSpec,
        override_name: Option<&str>,
        scene_file: &Path,
    ) -> Result<Integrator> {
        let err = |line: Option<u32>, message: String| Error::Integrator {
            file: scene_file.to_path_buf(),
            line,
            message,
        };
        let (name, params, line) = match override_name {
            // Another integrator keeps the scene's parameters it understands (a
            // Mitsuba `path` scene's max_depth for `path_mats`), and drops the rest.
            Some(n) if n != spec.name => {
                let keep = parameter_names(n);
                let params = spec
                    .params
                    .iter()
                    .filter(|(k, _)| keep.contains(&k.as_str()))
                    .map(|(k, v)| (k.clone(), v.clone()))
                    .collect();
                (n, params, spec.line)
            }
            _ => (spec.name.as_str(), spec.params.clone(), spec.line),
        };
        let mut params = params;
        let mut take = |key: &str| params.remove(key);
        let not_boolean = |key: &str, p: Param| {
            err(
                line,
                format!("integrator '{name}': {key} must be a boolean, got {p:?}"),
            )
        };
        let integrator = match name {
            "normals" => Integrator::Normals,
            "simple" => Integrator::Simple,
            "ao" => {
                let max_t = match take("max_t") {
                    None => f32::INFINITY,
                    Some(Param::Float(v)) if v > 0.0 => v as f32,
                    Some(Param::Integer(v)) if v > 0 => v as f32,
                    Some(p) => {
                        return Err(err(
                            line,
                            format!("integrator 'ao': max_t must be a positive float, got {p:?}"),
                        ))
                    }
                };
                let uniform = match take("sampling") {
                    None => false,
                    Some(Param::String(s)) if s == "cosine" => false,
                    Some(Param::String(s)) if s == "uniform" => true,
                    Some(p) => {
                        return Err(err(
                            line,
                            format!("integrator 'ao': sampling must be \"cosine\" or \"uniform\", got {p:?}"),
                        ))
                    }
                };
                Integrator::Ao { max_t, uniform }
            }
            "direct_ems" | "direct_mats" | "direct_mis" | "direct" => {
                let hide_emitters = match take("hide_emitters") {
                    None => false,
                    Some(Param::Bool(b)) => b,
                    Some(p) => return Err(not_boolean("hide_emitters", p)),
                };
                for key in ["emitter_samples", "bsdf_samples"] {
                    match take(key) {
                        None | Some(Param::Integer(1)) => {}
                        Some(p) => {
                            return Err(err(
                                line,
                                format!("integrator '{name}': {key} other than 1 is not supported yet, got {p:?}"),
                            ))
                        }
                    }
                }
                match name {
                    "direct_ems" => Integrator::DirectEms { hide_emitters },
                    "direct_mats" => Integrator::DirectMats { hide_emitters },
                    _ => Integrator::DirectMis { hide_emitters },
                }
            }
            "path_mats" | "path_mis" | "path" | "vol_path_simple" | "vol_path_mis" | "volpath"
            | "volpathmis" => {
                let max_depth = match take("max_depth") {
                    None | Some(Param::Integer(-1)) => None,
                    Some(Param::Integer(d)) if d >= 1 && d <= u32::MAX as i64 / 2 => Some(d as u32),
                    Some(p) => {
                        return Err(err(
                            line,
                            format!("integrator '{name}': max_depth must be -1 (unbounded) or at least 1, got {p:?}"),
                        ))
                    }
                };
                let rr_depth = match take("rr_depth") {
                    None => 5,
                    Some(Param::Integer(d)) if d >= 1 && d <= u32::MAX as i64 / 2 => d as u32,
                    Some(p) => {
                        return Err(err(
                            line,
                            format!("integrator '{name}': rr_depth must be at least 1, got {p:?}"),
                        ))
                    }
                };
                let hide_emitters = match take("hide_emitters") {
                    None => false,
                    Some(Param::Bool(b)) => b,
                    Some(p) => return Err(not_boolean("hide_emitters", p)),
                };
                let power_heuristic = match take("mis_heuristic") {
                    None => matches!(name, "path_mis" | "path"),
                    Some(Param::String(s)) if s == "power" => true,
                    Some(Param::String(s)) if s == "balance" => false,
                    Some(p) => {
                        return Err(err(
                            line,
                            format!("integrator '{name}': mis_heuristic must be \"power\" or \"balance\", got {p:?}"),
                        ))
                    }
                };
                let params = PathParams {
                    max_depth,
                    rr_depth,
                    hide_emitters,
                    power_heuristic,
                };
                match name {
                    "path_mats" => Integrator::PathMats(params),
                    "path_mis" | "path" => Integrator::PathMis(params),
                    "vol_path_simple" => Integrator::VolPathSimple(params),
                    _ => Integrator::VolPathMis(params),
                }
            }
            "single_scatter" => {
                let equiangular = match take("sampling") {
                    None => false,
                    Some(Param::String(s)) if s == "distance" => false,
                    Some(Param::String(s)) if s == "equiangular" => true,
                    Some(p) => {
                        return Err(err(
                            line,
                            format!("integrator 'single_scatter': sampling must be \"distance\" or \"equiangular\", got {p:?}"),
                        ))
                    }
                };
                let hide_emitters = match take("hide_emitters") {
                    None => false,
                    Some(Param::Bool(b)) => b,
                    Some(p) => return Err(not_boolean("hide_emitters", p)),
                };
                Integrator::SingleScatter {
                    equiangular,
                    hide_emitters,
                }
            }
            "photonmapper" => {
                let photon_count = match take("photonCount") {
                    None => 1_000_000,
                    Some(Param::Integer(n)) if n >= 1 && n <= u32::MAX as i64 => n as u32,
                    Some(p) => {
                        return Err(err(
                            line,
                            format!("integrator 'photonmapper': photonCount must be a positive integer (photons to store), got {p:?}"),
                        ))
                    }
                };
                let radius = match take("photonRadius") {
                    None | Some(Param::Integer(0)) => None,
                    Some(Param::Float(0.0)) => None,
                    Some(Param::Float(r)) if r > 0.0 && r.is_finite() => Some(r as f32),
                    Some(Param::Integer(r)) if r > 0 => Some(r as f32),
                    Some(p) => {
                        return Err(err(
                            line,
                            format!("integrator 'photonmapper': photonRadius must be positive, or 0 for automatic, got {p:?}"),
                        ))
                    }
                };
                Integrator::PhotonMapper(PhotonMapperParams {
                    photon_count,
                    radius,
                })
            }
            "sppm" => {
                // pbrt-v4 and Mitsuba 0.6 name the same parameters differently; a scene
                // may use either name, not both.
                let mut either = |a: &str, b: &str| -> Result<Option<(String, Param)>> {
                    match (take(a), take(b)) {
                        (Some(_), Some(_)) => Err(err(
                            line,
                            format!("integrator 'sppm': give either {a} or {b}, not both"),
                        )),
                        (Some(p), None) => Ok(Some((a.to_string(), p))),
                        (None, Some(p)) => Ok(Some((b.to_string(), p))),
                        (None, None) => Ok(None),
                    }
                };
                let depth = either("maxdepth", "maxDepth")?;
                let radius = either("radius", "initialRadius")?;
                let photons = either("photonsperiteration", "photonCount")?;
                let alpha = take("alpha");
                let max_depth = match depth {
                    None => Some(5),
                    Some((_, Param::Integer(-1))) => None,
                    Some((_, Param::Integer(d))) if d >= 1 && d < MAX_BOUNCES as i64 => Some(d as u32),
                    Some((k, p)) => {
                        return Err(err(
                            line,
                            format!("integrator 'sppm': {k} must be -1 (unbounded) or at least 1, got {p:?}"),
                        ))
                    }
                };
                let radius = match radius {
                    None => None,
                    // Mitsuba's initialRadius 0: decide automatically.
                    Some((k, Param::Float(r))) if r == 0.0 && k == "initialRadius" => None,
                    Some((k, Param::Integer(0))) if k == "initialRadius" => None,
                    Some((_, Param::Float(r))) if r > 0.0 && r.is_finite() => Some(r as f32),
                    Some((_, Param::Integer(r))) if r > 0 => Some(r as f32),
                    Some((k, p)) => {
                        return Err(err(
                            line,
                            format!("integrator 'sppm': {k} must be positive, got {p:?}"),
                        ))
                    }
                };
                let photons = match photons {
                    None => PhotonBudget::Emitted(None),
                    Some((k, Param::Integer(-1))) if k == "photonsperiteration" => {
                        PhotonBudget::Emitted(None)
                    }
                    Some((k, Param::Integer(n))) if n >= 1 && n <= u32::MAX as i64 => {
                        if k == "photonCount" {
                            PhotonBudget::Stored(n as u32)
                        } else {
                            PhotonBudget::Emitted(Some(n as u32))
                        }
                    }
                    Some((k, p)) => {
                        return Err(err(
                            line,
                            format!("integrator 'sppm': {k} must be a positive integer, got {p:?}"),
                        ))
                    }
                };
                let alpha = match alpha {
                    None => 2.0 / 3.0,
                    Some(Param::Float(a)) if a > 0.0 && a < 1.0 => a as f32,
                    Some(p) => {
                        return Err(err(
                            line,
                            format!(
                            "integrator 'sppm': alpha must lie strictly between 0 and 1, got {p:?}"
                        ),
                        ))
                    }
                };
                Integrator::Sppm(SppmParams {
                    max_depth,
                    radius,
                    photons,
                    alpha,
                })
            }
            "" => {
                return Err(err(
                    line,
                    format!(
                        "the scene names no integrator; choose one with --integrator ({})",
                        NAMES.join(", ")
                    ),
                ))
            }
            other => {
                return Err(err(
                    line,
                    format!(
                        "integrator '{other}' is not implemented in this version; available: {}",
                        NAMES.join(", ")
                    ),
                ))
            }
        };
        if let Some(key) = params.keys().next() {
            return Err(err(
                line,
                format!("integrator '{name}' has no parameter '{key}'"),
            ));
        }
        Ok(integrator)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(name: &str, params: &[(&str, Param)]) -> IntegratorSpec {
        IntegratorSpec {
            name: name.into(),
            params: params
                .iter()
                .map(|(k, v)| (k.to_string(), v.clone()))
                .collect(),
            line: Some(7),
        }
    }

    #[test]
    fn reads_ao_parameters() {
        let s = spec(
            "ao",
            &[
                ("max_t", Param::Float(2.5)),
                ("sampling", Param::String("uniform".into())),
            ],
        );
        let i = Integrator::from_spec(&s, None, Path::new("a.xml")).unwrap();
        assert_eq!(
            i,
            Integrator::Ao {
                max_t: 2.5,
                uniform: true
            }
        );
        let d = Integrator::from_spec(&spec("ao", &[]), None, Path::new("a.xml")).unwrap();
        assert_eq!(
            d,
            Integrator::Ao {
                max_t: f32::INFINITY,
                uniform: false
            }
        );
    }

    #[test]
    fn bounces_that_only_end_paths() {
        let path = |max_depth| {
            Integrator::PathMis(PathParams {
                max_depth,
                rr_depth: 5,
                hide_emitters: false,
                power_heuristic: true,
            })
        };
        // max_depth 3: vertices at depths 0 and 1 sample further segments, 2 ends.
        let p = path(Some(3));
        assert_eq!(p.bounces(), 3);
        assert_eq!(
            (0..3).map(|d| p.ends_paths_at(d)).collect::<Vec<_>>(),
            [false, false, true]
        );
        assert!(path(Some(1)).ends_paths_at(0));
        assert!(!(0..MAX_BOUNCES).any(|d| path(None).ends_paths_at(d)));
        // direct_*: the BSDF-sampled ray's vertex only adds emission.
        let direct = Integrator::DirectMis {
            hide_emitters: false,
        };
        assert!(!direct.ends_paths_at(0) && direct.ends_paths_at(1));
        assert!(!Integrator::DirectEms {
            hide_emitters: false
        }
        .ends_paths_at(0));
        // First-hit integrators and photon mappers shade in their own ways.
        assert!(!Integrator::Simple.ends_paths_at(0));
        assert!(!Integrator::Normals.ends_paths_at(5));
    }

    #[test]
    fn unknown_key_and_bad_values_name_file_and_line() {
        let e = Integrator::from_spec(
            &spec("ao", &[("maxt", Param::Float(1.0))]),
            None,
            Path::new("s.xml"),
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "s.xml:7: integrator 'ao' has no parameter 'maxt'"
        );
        let e = Integrator::from_spec(
            &spec("ao", &[("max_t", Param::Float(-1.0))]),
            None,
            Path::new("s.xml"),
        )
        .unwrap_err();
        assert!(e
            .to_string()
            .starts_with("s.xml:7: integrator 'ao': max_t must be a positive float"));
        let e = Integrator::from_spec(&spec("bdpt", &[]), None, Path::new("s.xml")).unwrap_err();
        assert!(e.to_string().contains("'bdpt' is not implemented"), "{e}");
        let e = Integrator::from_spec(
            &spec("path", &[("max_depth", Param::Integer(0))]),
            None,
            Path::new("s.xml"),
        )
        .unwrap_err();
        assert!(e.to_string().contains("max_depth must be -1"), "{e}");
    }

    #[test]
    fn mitsuba_names_map_to_the_mis_integrators() {
        let i = Integrator::from_spec(
            &spec("path", &[("max_depth", Param::Integer(6))]),
            None,
            Path::new("a"),
        )
        .unwrap();
        assert_eq!(
            i,
            Integrator::PathMis(PathParams {
                max_depth: Some(6),
                rr_depth: 5,
                hide_emitters: false,
                power_heuristic: true,
            })
        );
        assert_eq!((i.max_depth(), i.bounces()), (6, 6));
        assert!(i.power_heuristic());
        let d = Integrator::from_spec(&spec("direct", &[]), None, Path::new("a")).unwrap();
        assert_eq!(
            d,
            Integrator::DirectMis {
                hide_emitters: false
            }
        );
        let u = Integrator::from_spec(&spec("path_mats", &[]), None, Path::new("a")).unwrap();
        assert_eq!((u.max_depth(), u.bounces()), (u32::MAX, MAX_BOUNCES));
    }

    #[test]
    fn mis_heuristic_defaults_per_integrator_and_is_checked() {
        let read = |name: &str, params: &[(&str, Param)]| {
            Integrator::from_spec(&spec(name, params), None, Path::new("s.xml"))
        };
        assert!(read("path_mis", &[]).unwrap().power_heuristic());
        assert!(!read("volpath", &[]).unwrap().power_heuristic());
        assert!(!read("direct_mis", &[]).unwrap().power_heuristic());
        let balance = [("mis_heuristic", Param::String("balance".into()))];
        assert!(!read("path", &balance).unwrap().power_heuristic());
        let power = [("mis_heuristic", Param::String("power".into()))];
        assert!(read("vol_path_mis", &power).unwrap().power_heuristic());
        let bad = [("mis_heuristic", Param::String("maximum".into()))];
        let e = read("path", &bad).unwrap_err();
        assert!(e.to_string().contains("mis_heuristic must be"), "{e}");
        assert!(
            read("direct", &power).is_err(),
            "direct_mis takes no mis_heuristic"
        );
    }

    #[test]
    fn override_replaces_the_scene_integrator_and_keeps_only_parameters_it_reads() {
        let s = spec("path", &[("max_depth", Param::Integer(5))]);
        let i = Integrator::from_spec(&s, Some("ao"), Path::new("s.xml")).unwrap();
        assert_eq!(
            i,
            Integrator::Ao {
                max_t: f32::INFINITY,
                uniform: false
            }
        );
        let e = Integrator::from_spec(&s, Some("bogus"), Path::new("s.xml")).unwrap_err();
        assert!(e.to_string().contains("'bogus' is not implemented"));
        // A path tracer keeps the depth of the scene's path tracer.
        let p = Integrator::from_spec(&s, Some("path_mats"), Path::new("s.xml")).unwrap();
        assert_eq!(p.max_depth(), 5);
    }

    #[test]
    fn reads_the_photon_mappers_parameters_by_either_name() {
        let read = |name: &str, params: &[(&str, Param)]| {
            Integrator::from_spec(&spec(name, params), None, Path::new("s.xml"))
        };
        assert_eq!(
            read("photonmapper", &[]).unwrap(),
            Integrator::PhotonMapper(PhotonMapperParams {
                photon_count: 1_000_000,
                radius: None
            })
        );
        let pm = read(
            "photonmapper",
            &[
                ("photonCount", Param::Integer(5_000_000)),
                ("photonRadius", Param::Float(1.0)),
            ],
        )
        .unwrap();
        assert_eq!(
            pm,
            Integrator::PhotonMapper(PhotonMapperParams {
                photon_count: 5_000_000,
                radius: Some(1.0)
            })
        );
        assert!(pm.is_photon_mapper());
        assert_eq!((pm.max_depth(), pm.bounces()), (u32::MAX, MAX_BOUNCES));
        assert_eq!(
            read("photonmapper", &[("photonRadius", Param::Float(0.0))]).unwrap(),
            read("photonmapper", &[]).unwrap()
        );
        for bad in [
            ("photonCount", Param::Integer(0)),
            ("photonRadius", Param::Float(-1.0)),
            ("photonRadius", Param::String("big".into())),
        ] {
            let e = read("photonmapper", std::slice::from_ref(&bad)).unwrap_err();
            assert!(e.to_string().contains(bad.0), "{e}");
        }

        let d = read("sppm", &[]).unwrap();
        assert_eq!(
            d,
            Integrator::Sppm(SppmParams {
                max_depth: Some(5),
                radius: None,
                photons: PhotonBudget::Emitted(None),
                alpha: 2.0 / 3.0,
            })
        );
        // pbrt's maxdepth 5: light sampled at camera vertices 0-4, 6 segments.
        assert_eq!((d.max_depth(), d.bounces()), (6, 6));
        assert!(d.power_heuristic());
        let pbrt = read(
            "sppm",
            &[
                ("maxdepth", Param::Integer(8)),
                ("radius", Param::Float(0.25)),
                ("photonsperiteration", Param::Integer(10_000)),
                ("alpha", Param::Float(0.7)),
            ],
        )
        .unwrap();
        let mitsuba = read(
            "sppm",
            &[
                ("maxDepth", Param::Integer(8)),
                ("initialRadius", Param::Float(0.25)),
                ("photonCount", Param::Integer(10_000)),
                ("alpha", Param::Float(0.7)),
            ],
        )
        .unwrap();
        let Integrator::Sppm(p) = pbrt else {
            panic!("sppm")
        };
        let Integrator::Sppm(m) = mitsuba else {
            panic!("sppm")
        };
        assert_eq!(
            (p.max_depth, p.radius, p.alpha),
            (m.max_depth, m.radius, m.alpha)
        );
        assert_eq!(p.photons, PhotonBudget::Emitted(Some(10_000)));
        assert_eq!(m.photons, PhotonBudget::Stored(10_000));
        // Mitsuba's initialRadius 0 is automatic; pbrt's radius must be positive.
        assert!(matches!(
            read("sppm", &[("initialRadius", Param::Float(0.0))]).unwrap(),
            Integrator::Sppm(SppmParams { radius: None, .. })
        ));
        assert!(read("sppm", &[("radius", Param::Float(0.0))]).is_err());
        let both = read(
            "sppm",
            &[
                ("maxdepth", Param::Integer(3)),
                ("maxDepth", Param::Integer(4)),
            ],
        )
        .unwrap_err();
        assert!(
            both.to_string().contains("either maxdepth or maxDepth"),
            "{both}"
        );
        for bad in [
            ("alpha", Param::Float(1.0)),
            ("maxdepth", Param::Integer(0)),
            ("photonsperiteration", Param::Integer(0)),
            ("granularity", Param::Integer(100)),
        ] {
            let e = read("sppm", std::slice::from_ref(&bad)).unwrap_err();
            assert!(e.to_string().contains(bad.0), "{e}");
        }
        assert!(
            read("sppm", &[("maxdepth", Param::Integer(-1))])
                .unwrap()
                .max_depth()
                == u32::MAX
        );
    }
}
