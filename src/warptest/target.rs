//! Naming what `wavetrace warptest` tests: a warp, microfacet normals, a BSDF or a
//! phase function by name, with its parameters (what the command line gives).

use glam::Vec3;

use super::{AreaLight, AreaShape, Axis, Target, Test, Warp};
use crate::scene::bsdf::composite::Weight;
use crate::scene::bsdf::{self, Bsdf, Distribution, TestParams};

/// The warps, microfacet distributions and phase functions [`parse`] knows; its BSDFs
/// are those of `scene::bsdf`'s registry with a warptest ([`bsdf::warptests`]).
const NAMES: &[&str] = &[
    "square_to_disk",
    "uniform_triangle",
    "uniform_hemisphere",
    "cosine_hemisphere",
    "uniform_sphere",
    "uniform_cap",
    "beckmann",
    "ggx",
    "blendbsdf",
    "hg",
    "isotropic",
    "mismatched_cosine",
    "thinlens_aperture",
    "projector",
    "directionalarea",
    "directionalarea_disk",
    "directionalarea_sphere",
    "mismatched_directionalarea",
];

/// Every name [`parse`] knows, for help and error messages: the warps and
/// distributions, the BSDFs, the phase functions.
pub fn names() -> Vec<&'static str> {
    let (before, after) = NAMES.split_at(8);
    let (blend, after) = after.split_at(1);
    let bsdfs = bsdf::warptests().map(|w| w.kind.name);
    before
        .iter()
        .copied()
        .chain(bsdfs)
        .chain(blend.iter().copied())
        .chain(after.iter().copied())
        .collect()
}

/// The command line's help for the target: every name, by what it samples.
pub fn help() -> String {
    let bsdfs: Vec<&str> = bsdf::warptests().map(|w| w.kind.name).collect();
    format!(
        "What to sample: a warp (square_to_disk, uniform_triangle, uniform_hemisphere, \
         cosine_hemisphere, uniform_sphere, uniform_cap), microfacet normals (beckmann, ggx), \
         a BSDF ({}), blendbsdf (0.7 diffuse + 0.3 roughconductor of --alpha, \
         sampled as a one-sample mixture), a phase function (hg, isotropic), an emitter's or sensor's \
         sampling (thinlens_aperture; projector: tan of the half fields of view 1.2 x 0.8; \
         directionalarea: the light rays' points on a mesh of four uneven triangles, \
         directionalarea_disk, directionalarea_sphere: on a disk, a sphere), or \
         mismatched_cosine, mismatched_directionalarea (deliberately wrong pdfs: they fail)",
        bsdfs.join(", ")
    )
}

/// Parameters of a test target; `None` takes the default, and a parameter the
/// target does not have is an error.
#[derive(Debug, Clone, Default)]
pub struct Params {
    /// Isotropic roughness (microfacet distributions and rough BSDFs); default 0.2.
    pub alpha: Option<f32>,
    /// Anisotropic roughness, both or neither (roughconductor, roughdielectric,
    /// beckmann, ggx).
    pub alpha_u: Option<f32>,
    pub alpha_v: Option<f32>,
    /// `beckmann` or `ggx` for rough BSDFs; default ggx.
    pub distribution: Option<String>,
    /// Relative index of refraction (dielectrics, plastics, nori_microfacet); default
    /// 1.5.
    pub eta: Option<f32>,
    /// Incident direction in degrees: angle from the normal (above 90: from below the
    /// surface) and azimuth; default 30 and 0.
    pub theta: Option<f32>,
    pub phi: Option<f32>,
    /// Henyey-Greenstein asymmetry in (-1, 1); default 0.7.
    pub g: Option<f32>,
    /// Cosine of the cap's half angle in (-1, 1); default 0.5.
    pub cos_max: Option<f32>,
}

/// `v` when it is a positive number, else the error for option `--what`.
fn positive(what: &str, v: f32) -> Result<f32, String> {
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(format!("--{what} must be a positive number, found {v}"))
    }
}

/// The incident direction of `--theta` and `--phi` (degrees; default 30 and 0).
fn incident(p: &Params) -> Result<Vec3, String> {
    let (t, f) = (p.theta.unwrap_or(30.0), p.phi.unwrap_or(0.0));
    if !(0.0..=180.0).contains(&t) || !f.is_finite() {
        return Err(format!(
            "--theta must lie in [0, 180] degrees (and --phi be finite), found {t}, {f}"
        ));
    }
    let (t, f) = (t.to_radians(), f.to_radians());
    Ok(Vec3::new(t.sin() * f.cos(), t.sin() * f.sin(), t.cos()))
}

/// `w` as its polar and azimuthal angles, for the description.
fn angle(w: Vec3) -> String {
    format!(
        "wo at θ = {:.1}°, φ = {:.1}°",
        w.z.clamp(-1.0, 1.0).acos().to_degrees(),
        w.y.atan2(w.x).to_degrees()
    )
}

/// An error naming the first option given in `p` that is not in `allowed` (the
/// options of target `name`).
fn options_apply(name: &str, p: &Params, allowed: &[&str]) -> Result<(), String> {
    let given = [
        ("alpha", p.alpha.is_some()),
        ("alpha-u", p.alpha_u.is_some()),
        ("alpha-v", p.alpha_v.is_some()),
        ("distribution", p.distribution.is_some()),
        ("eta", p.eta.is_some()),
        ("theta", p.theta.is_some()),
        ("phi", p.phi.is_some()),
        ("g", p.g.is_some()),
        ("cos-max", p.cos_max.is_some()),
    ];
    match given.iter().find(|(k, set)| *set && !allowed.contains(k)) {
        Some((k, _)) => Err(format!("--{k} does not apply to '{name}'")),
        None => Ok(()),
    }
}

/// The test called `name` with `p`, and a one-line description of it.
pub fn parse(name: &str, p: &Params) -> Result<(Test, String), String> {
    let used = |allowed: &[&str]| options_apply(name, p, allowed);
    let roughness = |anisotropic: bool| -> Result<(f32, f32), String> {
        match (p.alpha, p.alpha_u, p.alpha_v) {
            (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
                Err("give either --alpha or --alpha-u and --alpha-v".into())
            }
            (_, Some(u), Some(v)) if anisotropic => {
                Ok((positive("alpha-u", u)?, positive("alpha-v", v)?))
            }
            (_, Some(_), None) | (_, None, Some(_)) => {
                Err("give both --alpha-u and --alpha-v".into())
            }
            (_, Some(_), Some(_)) => Err(format!("'{name}' is isotropic: use --alpha")),
            (a, None, None) => {
                let a = positive("alpha", a.unwrap_or(0.2))?;
                Ok((a, a))
            }
        }
    };
    let distribution = || match p.distribution.as_deref().unwrap_or("ggx") {
        "ggx" => Ok(Distribution::Ggx),
        "beckmann" => Ok(Distribution::Beckmann),
        d => Err(format!(
            "--distribution must be beckmann or ggx, found '{d}'"
        )),
    };
    let eta = || -> Result<f32, String> {
        let e = positive("eta", p.eta.unwrap_or(1.5))?;
        if e == 1.0 {
            return Err("--eta must differ from 1".into());
        }
        Ok(e)
    };
    if let Some((light, what)) = area_light(name) {
        used(&[])?;
        return Ok((Test::DirectionalArea(light), what));
    }
    let warp = |w: Warp, what: &str| Ok((Target::Warp(w), what.to_string()));
    let target = match name {
        "square_to_disk" | "uniform_triangle" | "uniform_hemisphere" | "cosine_hemisphere"
        | "uniform_sphere" | "mismatched_cosine" => {
            used(&[])?;
            match name {
                "square_to_disk" => warp(Warp::Disk, "concentric map to the unit disk"),
                "uniform_triangle" => warp(Warp::Triangle, "uniform barycentrics"),
                "uniform_hemisphere" => warp(Warp::UniformHemisphere, "uniform hemisphere"),
                "cosine_hemisphere" => warp(Warp::CosineHemisphere, "cosine-weighted hemisphere"),
                "uniform_sphere" => warp(Warp::UniformSphere, "uniform sphere"),
                _ => warp(
                    Warp::MismatchedCosine,
                    "cosine-weighted samples against the uniform hemisphere's pdf (deliberately wrong)",
                ),
            }
        }
        "thinlens_aperture" | "projector" => {
            used(&[])?;
            Ok(endpoint_warp(name))
        }
        "uniform_cap" => {
            used(&["cos-max"])?;
            let c = p.cos_max.unwrap_or(0.5);
            if !(c > -1.0 && c < 1.0) {
                return Err(format!("--cos-max must lie in (-1, 1), found {c}"));
            }
            warp(
                Warp::Cap { cos_max: c },
                &format!("uniform cap, cos θmax = {c}"),
            )
        }
        "beckmann" | "ggx" => {
            used(&["alpha", "alpha-u", "alpha-v", "theta", "phi"])?;
            let (au, av) = roughness(true)?;
            let wo = incident(p)?;
            let what = format!("{name} microfacet normals, α = ({au}, {av}), {}", angle(wo));
            warp(
                Warp::Microfacet {
                    distribution: (name == "ggx") as u32,
                    alpha_u: au,
                    alpha_v: av,
                    wo,
                },
                &what,
            )
        }
        "blendbsdf" => blend_target(used(BLEND).and(roughness(false))?.0, incident(p)?),
        "hg" | "isotropic" => {
            used(if name == "hg" {
                &["g", "theta", "phi"]
            } else {
                &["theta", "phi"]
            })?;
            let g = if name == "hg" {
                p.g.unwrap_or(0.7)
            } else {
                0.0
            };
            if !(g > -1.0 && g < 1.0) {
                return Err(format!("--g must lie in (-1, 1), found {g}"));
            }
            let wo = incident(p)?;
            Ok((
                Target::Phase { g, wo },
                format!("Henyey-Greenstein g = {g}, {}", angle(wo)),
            ))
        }
        _ => match bsdf::warptests().find(|w| w.kind.name == name) {
            Some(test) => {
                let mut allowed = vec!["theta", "phi"];
                allowed.extend(test.params);
                used(&allowed)?;
                let anisotropic = test.params.contains(&"alpha-u");
                let (alpha_u, alpha_v) = if test.params.contains(&"alpha") {
                    roughness(anisotropic)?
                } else {
                    (0.2, 0.2)
                };
                let bsdf = (test.make)(&TestParams {
                    alpha_u,
                    alpha_v,
                    distribution: distribution()?,
                    eta: if test.params.contains(&"eta") {
                        eta()?
                    } else {
                        1.5
                    },
                });
                let wo = incident(p)?;
                let axis = Axis::for_bsdf(&bsdf);
                let what = format!("{name} {bsdf:?}, {}", angle(wo));
                Ok((Target::Bsdf { bsdf, wo, axis }, what))
            }
            None => Err(format!(
                "unknown warptest target '{name}'; one of: {}",
                names().join(", ")
            )),
        },
    };
    target.map(|(t, what)| (Test::Kernel(t), what))
}

/// The options of the `blendbsdf` target.
const BLEND: &[&str] = &["alpha", "theta", "phi"];

/// The `blendbsdf` target: 0.7 diffuse + 0.3 GGX copper of roughness `alpha`, sampled
/// as the path tracers sample a blend (`shaders/bsdf/mixture.glsl`).
fn blend_target(alpha: f32, wo: Vec3) -> Result<(Target, String), String> {
    let tp = TestParams {
        alpha_u: alpha,
        alpha_v: alpha,
        distribution: Distribution::Ggx,
        eta: 1.5,
    };
    let make = |name: &str| {
        bsdf::warptests()
            .find(|w| w.kind.name == name)
            .map(|w| (w.make)(&tp))
            .ok_or_else(|| format!("no warptest model '{name}'"))
    };
    let bsdf = Bsdf::Blend {
        weight: Weight::constant(0.3),
        bsdfs: Box::new([make("diffuse")?, make("roughconductor")?]),
    };
    let what = format!(
        "blendbsdf 0.7 diffuse + 0.3 roughconductor (GGX, α = {alpha}), {}",
        angle(wo)
    );
    let axis = Axis::Reflect;
    Ok((Target::Bsdf { bsdf, wo, axis }, what))
}

/// The sampling routines of sensors and emitters: the thin lens's aperture, a
/// projector's photon directions (a fixed frustum, tan of the half fields of view
/// 1.2 x 0.8).
fn endpoint_warp(name: &str) -> (Target, String) {
    if name == "thinlens_aperture" {
        (
            Target::Warp(Warp::ThinLensAperture),
            "the thin lens's aperture (unit disk)".into(),
        )
    } else {
        (
            Target::Warp(Warp::Projector {
                tan_x: 1.2,
                tan_y: 0.8,
            }),
            "a projector's photon directions, tan of the half fields of view 1.2 x 0.8".into(),
        )
    }
}

/// A directionalarea emitter's light rays (`shaders/emitter/directionalarea.glsl`):
/// their points on the emitter's shape against the density the rays' weight divides
/// by; `None` for any other name.
fn area_light(name: &str) -> Option<(AreaLight, String)> {
    let (shape, mismatched, what) = match name {
        "directionalarea" => (AreaShape::Fan, false, "on a mesh of four uneven triangles"),
        "directionalarea_disk" => (AreaShape::Disk, false, "on a disk"),
        "directionalarea_sphere" => (AreaShape::Sphere, false, "on a sphere"),
        "mismatched_directionalarea" => (
            AreaShape::Fan,
            true,
            "on a mesh of four uneven triangles against the density of choosing its \
             triangles uniformly (deliberately wrong)",
        ),
        _ => return None,
    };
    Some((
        AreaLight { shape, mismatched },
        format!("a directionalarea emitter's light rays, their points {what}"),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::bsdf::{Bsdf, RoughConductor};

    #[test]
    fn names_parameters_and_errors() {
        for name in names() {
            assert!(parse(name, &Params::default()).is_ok(), "{name}");
        }
        let p = Params {
            alpha_u: Some(0.1),
            alpha_v: Some(0.4),
            theta: Some(60.0),
            ..Params::default()
        };
        let (t, _) = parse("roughconductor", &p).unwrap();
        let Test::Kernel(Target::Bsdf { bsdf, wo, .. }) = t else {
            panic!("{t:?}")
        };
        assert!(
            matches!(bsdf, Bsdf::RoughConductor(RoughConductor { alpha_u, alpha_v, .. }) if alpha_u == 0.1 && alpha_v == 0.4)
        );
        assert!((wo.z - 0.5).abs() < 1e-6);
        let err = |name: &str, p: Params| parse(name, &p).unwrap_err();
        assert!(err(
            "diffuse",
            Params {
                g: Some(0.1),
                ..Params::default()
            }
        )
        .contains("--g does not apply"));
        assert!(err(
            "hg",
            Params {
                g: Some(1.0),
                ..Params::default()
            }
        )
        .contains("(-1, 1)"));
        assert!(err(
            "roughplastic",
            Params {
                alpha_u: Some(0.1),
                alpha_v: Some(0.2),
                ..Params::default()
            }
        )
        .contains("does not apply"));
        assert!(err(
            "ggx",
            Params {
                alpha: Some(-1.0),
                ..Params::default()
            }
        )
        .contains("positive"));
        assert!(err(
            "roughdielectric",
            Params {
                eta: Some(1.0),
                ..Params::default()
            }
        )
        .contains("differ from 1"));
        assert!(err(
            "ggx",
            Params {
                alpha_u: Some(0.1),
                ..Params::default()
            }
        )
        .contains("both"));
        assert!(err("teapot", Params::default()).contains("unknown warptest target"));
    }
}
