//! The integrator a scene names: the integrator family, one file per integrator
//! family (its parameters and their checks), and [`REGISTRY`], every integrator type
//! with the parameters it reads. `render::integrator` keeps what a render does with
//! an [`Integrator`] (its schedule).
//!
//! An `<integrator>` is read in two steps: the dialect's walker keeps its parameters
//! unread in an [`IntegratorSpec`] ([`spec`]), and [`read`] reads them once the
//! integrator is known (`--integrator` may name another one).

pub mod aov;
mod direct;
mod first_hit;
mod moment;
mod path;
mod photonmapper;
mod ptracer;
mod single_scatter;
mod sppm;

use std::collections::BTreeMap;

use super::plugin::{Family, PluginDoc, Support};
use super::properties::Properties;
use super::xml::{Dialect, Element};
use super::Error;

/// A parameter value as written in the scene file, before an integrator reads it.
#[derive(Debug, Clone, PartialEq)]
pub enum Param {
    Bool(bool),
    Integer(i64),
    Float(f64),
    String(String),
}

/// The integrator a scene names (`<integrator type="...">`), with its parameters.
///
/// Parameters stay unread here: the renderer knows which integrators exist and reads
/// their parameters with defaults (`render::integrator`), so an unknown key or a name
/// it does not implement is reported there, naming the scene file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct IntegratorSpec {
    /// The type as written (`ao`, `path`, `direct_mis`, ...).
    pub name: String,
    /// Parameters by name; Nori's camelCase names are kept as written.
    pub params: BTreeMap<String, Param>,
    /// Line of the `<integrator>` tag in the scene file, when known.
    pub line: Option<u32>,
    /// The channels a wrapping `aov` or `moment` adds (none for a plain integrator).
    pub outputs: aov::Outputs,
}

/// The parameters of one integrator still unread: each one read is removed, so what
/// is left at the end is a parameter the integrator does not have.
pub type Params = BTreeMap<String, Param>;

/// An integrator with its parameters read.
#[derive(Debug, Clone, PartialEq)]
pub enum Integrator {
    /// Debug view of the shading normal, |n| per component (Nori's `normals`).
    Normals,
    /// Mitsuba's `depth`: the distance along the camera ray to the first surface
    /// (from the ray's origin on the near plane, Mitsuba's `si.t`), 0 where the ray
    /// meets nothing.
    ///
    /// ```xml
    /// <integrator type="depth"/>
    /// ```
    Depth,
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
    /// Direct illumination combining emitter and BSDF sampling: Nori's `direct_mis`
    /// with the balance heuristic, Mitsuba's `direct` with the power heuristic (its
    /// direct.cpp squares both pdfs). Parameter `hide_emitters` (default false):
    /// camera rays do not see emitters.
    DirectMis {
        hide_emitters: bool,
        power_heuristic: bool,
    },
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
    /// Mitsuba 3's particle tracer (`ptracer`): light paths leave the emitters (one
    /// chosen uniformly, as Mitsuba's `Scene::sample_emitter_ray`) and travel by BSDF
    /// sampling; every surface they meet is connected to the pinhole camera and its
    /// light splatted into the pixel it lands in (the adjoint BSDF towards the camera,
    /// the camera's importance, a shadow ray), with Mitsuba's shading-normal
    /// correction (Veach 1997, p. 155) and Russian roulette (from `rr_depth` on,
    /// survival min(max throughput × η², 0.95)). Points on area emitters chosen apart
    /// are connected directly: the emitters the camera sees (unless `hide_emitters`).
    /// A sample per pixel is width × height light paths, as in Mitsuba. Deterministic:
    /// splats are summed as fixed-point integers (`render::photon::ptracer`).
    ///
    /// Parameters as `path` (`max_depth`: 1 shows the emitters only, 2 direct light),
    /// without `mis_heuristic`. Splats go through the film's filter, each over the sum
    /// of its weights (Mitsuba's `ImageBlock::put`). A perspective camera; no media.
    ///
    /// ```xml
    /// <integrator type="ptracer"><integer name="max_depth" value="8"/></integrator>
    /// ```
    Ptracer(PathParams),
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
/// alive then are cut, counted in `render::RenderStats::cut_paths` and
/// reported by `render`. Below it nothing is truncated: a batch records bounces 64 at a
/// time and stops once its ray queue is empty (`Renderer::run_batch`), so the budget
/// costs nothing where Russian roulette ends paths sooner (with survival capped at
/// 0.99, a path outlives 2000 bounces past `rr_depth` with probability < 2e-9).
pub const MAX_BOUNCES: u32 = 1 << 16;

/// Every integrator type: those wavetrace renders (any of them may be named in either
/// dialect; Nori's own are listed again under Nori), then Mitsuba 3's not supported
/// yet.
pub const REGISTRY: &[PluginDoc] = &[
    first_hit::NORMALS,
    first_hit::AO,
    first_hit::SIMPLE,
    first_hit::DEPTH,
    direct::DIRECT_EMS,
    direct::DIRECT_MATS,
    direct::DIRECT_MIS,
    direct::DIRECT,
    path::PATH_MATS,
    path::PATH_MIS,
    path::PATH,
    path::VOL_PATH_SIMPLE,
    path::VOL_PATH_MIS,
    path::VOLPATH,
    path::VOLPATHMIS,
    single_scatter::SINGLE_SCATTER,
    photonmapper::PHOTONMAPPER,
    sppm::SPPM,
    moment::MOMENT,
    ptracer::PTRACER,
    aov::AOV,
    not_yet("stokes"),
    not_yet("prb"),
    not_yet("prb_basic"),
    not_yet("prb_projective"),
    not_yet("direct_projective"),
    not_yet("prbvolpath"),
    nori(first_hit::NORMALS),
    nori(first_hit::AO),
    nori(first_hit::SIMPLE),
    nori(direct::DIRECT_EMS),
    nori(direct::DIRECT_MATS),
    nori(direct::DIRECT_MIS),
    nori(path::PATH_MATS),
    nori(path::PATH_MIS),
    nori(photonmapper::PHOTONMAPPER),
];

const fn not_yet(name: &'static str) -> PluginDoc {
    PluginDoc::not_yet(Family::Integrator, Dialect::Mitsuba, name)
}

/// `doc` as an entry of the Nori dialect.
const fn nori(doc: PluginDoc) -> PluginDoc {
    PluginDoc {
        dialect: Dialect::Nori,
        ..doc
    }
}

/// Names `--integrator` and scenes may use in this version (the renderable types;
/// `moment` and `aov` only wrap one of them).
pub fn names() -> Vec<&'static str> {
    REGISTRY
        .iter()
        .filter(|p| p.dialect == Dialect::Mitsuba && p.support == Support::Yes)
        .filter(|p| p.name != moment::MOMENT.name && p.name != aov::AOV.name)
        .map(|p| p.name)
        .collect()
}

/// The parameters integrator `name` reads.
pub fn parameter_names(name: &str) -> Vec<&'static str> {
    REGISTRY
        .iter()
        .find(|p| p.dialect == Dialect::Mitsuba && p.name == name)
        .map(|p| p.params.iter().map(|q| q.name).collect())
        .unwrap_or_default()
}

/// Why an integrator's parameters could not be read: the message and the line of the
/// `<integrator>` (the renderer names the scene file).
#[derive(Debug, Clone, PartialEq)]
pub struct ReadError {
    pub line: Option<u32>,
    pub message: String,
}

/// Reads the integrator `spec` names, or `override_name` instead (the scene's
/// parameters apply only if the override names the same integrator).
pub fn read(spec: &IntegratorSpec, override_name: Option<&str>) -> Result<Integrator, ReadError> {
    let (name, mut params, line) = match override_name {
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
    let err = |message: String| ReadError { line, message };
    let integrator = match name {
        "normals" | "simple" | "ao" | "depth" => first_hit::read(name, &mut params),
        "direct_ems" | "direct_mats" | "direct_mis" | "direct" => direct::read(name, &mut params),
        "path_mats" | "path_mis" | "path" | "vol_path_simple" | "vol_path_mis" | "volpath"
        | "volpathmis" => path::read(name, &mut params),
        "single_scatter" => single_scatter::read(&mut params),
        "photonmapper" => photonmapper::read(&mut params),
        "sppm" => sppm::read(&mut params),
        "ptracer" => ptracer::read(&mut params),
        "" => Err(format!(
            "the scene names no integrator; choose one with --integrator ({})",
            names().join(", ")
        )),
        other => Err(format!(
            "integrator '{other}' is not implemented in this version; available: {}",
            names().join(", ")
        )),
    }
    .map_err(err)?;
    if let Some(key) = params.keys().next() {
        return Err(err(format!("integrator '{name}' has no parameter '{key}'")));
    }
    Ok(integrator)
}

/// `hide_emitters` (boolean, default false) of integrator `name`.
fn hide_emitters(name: &str, params: &mut Params) -> Result<bool, String> {
    match params.remove("hide_emitters") {
        None => Ok(false),
        Some(Param::Bool(b)) => Ok(b),
        Some(p) => Err(format!(
            "integrator '{name}': hide_emitters must be a boolean, got {p:?}"
        )),
    }
}

/// The parameters of an `<integrator>` element, kept unread (a Mitsuba `moment`
/// stands for the one integrator it wraps).
pub fn spec(el: &Element, dialect: Dialect) -> Result<IntegratorSpec, Error> {
    el.check_attrs(&["type", "id", "name"])?;
    let name = el.require("type")?.to_string();
    let (props, nested) = Properties::read(el, dialect, false)?;
    if dialect == Dialect::Mitsuba && name == moment::MOMENT.name {
        return moment::spec(el, &props, &nested, dialect);
    }
    if dialect == Dialect::Mitsuba && name == aov::AOV.name {
        return aov::spec(el, &props, &nested, dialect);
    }
    if let Some(n) = nested.first() {
        return Err(n.err(format!(
            "<{}> inside an <integrator> is not supported yet",
            n.tag
        )));
    }
    Ok(IntegratorSpec {
        name,
        params: props.into_params()?,
        line: Some(el.line),
        ..Default::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The integrators `--integrator` and the error messages name, in their order.
    #[test]
    fn names_are_the_renderable_integrators() {
        assert_eq!(
            names(),
            [
                "normals",
                "ao",
                "simple",
                "depth",
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
                "ptracer",
            ]
        );
        assert_eq!(
            parameter_names("path"),
            ["max_depth", "rr_depth", "hide_emitters", "mis_heuristic"]
        );
    }
}
