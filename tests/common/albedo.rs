//! Directional albedos a(wo) = ∫ f(wo, wi) |cos θi| dωi of the microfacet BSDFs by f64
//! quadrature of their formulas as published, written here and sharing nothing with the
//! crate's BSDF code (GLSL or Rust), so the GPU furnace has an independent reference.
//!
//! Sources: Walter, Marschner, Li, Torrance 2007, "Microfacet Models for Refraction
//! through Rough Surfaces": Beckmann and GGX D (eq. 25, 33), Smith G1 (GGX eq. 34,
//! Beckmann's rational approximation eq. 27), reflection and transmission (eq. 20, 21)
//! with the half-vector Jacobians (eq. 14, 17). Mitsuba 3: include/mitsuba/render/
//! microfacet.h (separable G = G1(wi, m) G1(wo, m), G1 = 0 where (v·m) cos θv <= 0),
//! fresnel.h (unpolarized dielectric Fresnel), src/bsdfs/roughconductor.cpp,
//! roughdielectric.cpp, plastic.cpp and roughplastic.cpp (the diffuse base under a rough
//! coating: ρ / (1 - R_int) · T(μi) T(μo) / (π η²), T the coating's rough transmittance
//! and R_int its hemispherical internal reflectance, both integrated over visible
//! normals). Nori's microfacet (Nori 2015, PA4): kd/π + ks D F G / (4 cos θi cos θo),
//! ks = 1 - max(kd), Beckmann D with the same G1 approximation.
//!
//! Energy, not radiance: transmitted light is counted without the 1/η² radiance
//! scaling, as the furnace counts it. Integrating Walter's f_t over wi with the Jacobian
//! eq. 17 cancels the η factors: every albedo here is ∫ D(m) (wo·m)/cos θo · G1(wo, m) ·
//! [F G1(r, m) + (1 - F) G1(t, m)] dm over microfacet normals m, with r and t the
//! mirrored and refracted wo, each counted only on its side of the surface.
//!
//! The quadrature: m by θm = atan(α tan(π w / 2)) (the lobe's width spread over w in
//! [0, 1)) and φm, both by composite Gauss-Legendre. The cut-offs (horizon, G1's sign
//! test, total internal reflection) make the integrand jump, so the rule converges at
//! first order in the panel width; `Quadrature::error` is the change when both grids are
//! doubled, a bound on the finer result's error at that rate.

use std::f64::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ndf {
    Beckmann,
    Ggx,
}

type V3 = [f64; 3];

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The direction in the xz-plane with cos θ = `mu` (> 0).
pub fn dir(mu: f64) -> V3 {
    [(1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu]
}

/// Microfacet distribution D(m), per steradian of m (Walter 2007 eq. 25 and 33).
pub fn ndf(kind: Ndf, alpha: f64, m: V3) -> f64 {
    let c2 = m[2] * m[2];
    if c2 <= 0.0 {
        return 0.0;
    }
    let t2 = (1.0 - c2) / c2;
    let a2 = alpha * alpha;
    match kind {
        Ndf::Beckmann => (-t2 / a2).exp() / (PI * a2 * c2 * c2),
        Ndf::Ggx => 1.0 / (PI * a2 * c2 * c2 * (1.0 + t2 / a2).powi(2)),
    }
}

/// Smith's masking G1(v, m) (Walter 2007 eq. 27 and 34), zero where v sees m's back.
pub fn smith_g1(kind: Ndf, alpha: f64, v: V3, m: V3) -> f64 {
    if dot(v, m) * v[2] <= 0.0 {
        return 0.0;
    }
    let t2 = (1.0 - v[2] * v[2]).max(0.0) / (v[2] * v[2]);
    if t2 == 0.0 {
        return 1.0;
    }
    match kind {
        Ndf::Ggx => 2.0 / (1.0 + (1.0 + alpha * alpha * t2).sqrt()),
        Ndf::Beckmann => {
            let a = 1.0 / (alpha * t2.sqrt());
            if a >= 1.6 {
                1.0
            } else {
                (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a)
            }
        }
    }
}

/// Unpolarized Fresnel reflectance of a dielectric interface for cos θi > 0 on the
/// incident side and `eta` = η_transmitted / η_incident; 1 under total internal
/// reflection.
pub fn fresnel(cos_i: f64, eta: f64) -> f64 {
    let sin_t2 = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin_t2 >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin_t2).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// wo mirrored about m.
fn reflect(v: V3, m: V3) -> V3 {
    let c = 2.0 * dot(v, m);
    [c * m[0] - v[0], c * m[1] - v[1], c * m[2] - v[2]]
}

/// wo refracted through m (v·m > 0, no total internal reflection), Snell's law.
fn refract(v: V3, m: V3, eta: f64) -> V3 {
    let c = dot(v, m);
    let cos_t = (1.0 - (1.0 - c * c) / (eta * eta)).sqrt();
    let k = c / eta - cos_t;
    [
        k * m[0] - v[0] / eta,
        k * m[1] - v[1] / eta,
        k * m[2] - v[2] / eta,
    ]
}

/// Gauss-Legendre nodes and weights on [0, 1], `panels` panels of 8 nodes.
fn gauss_legendre(panels: usize) -> Vec<(f64, f64)> {
    const X: [f64; 4] = [
        0.183_434_642_495_649_8,
        0.525_532_409_916_329,
        0.796_666_477_413_626_7,
        0.960_289_856_497_536_3,
    ];
    const W: [f64; 4] = [
        0.362_683_783_378_362,
        0.313_706_645_877_887_3,
        0.222_381_034_453_374_5,
        0.101_228_536_290_376_3,
    ];
    let h = 1.0 / panels as f64;
    let mut out = Vec::with_capacity(panels * 8);
    for p in 0..panels {
        let mid = (p as f64 + 0.5) * h;
        for (x, w) in X.iter().zip(W) {
            out.push((mid - 0.5 * h * x, 0.5 * h * w));
            out.push((mid + 0.5 * h * x, 0.5 * h * w));
        }
    }
    out
}

/// A quadrature's value and the bound on its error (the change from half the grid).
#[derive(Clone, Copy, Debug)]
pub struct Quadrature {
    pub value: f64,
    pub error: f64,
}

/// ∫ D(m) g(m) dm over the hemisphere of m, at `panels` panels per variable.
fn over_normals(kind: Ndf, alpha: f64, panels: usize, g: &dyn Fn(V3) -> f64) -> f64 {
    let w_nodes = gauss_legendre(panels);
    // The integrands here are even in m_y (wo lies in the xz-plane): φ over [0, π], x2.
    let phi_nodes = gauss_legendre(panels);
    let mut sum = 0.0;
    for &(w, ww) in &w_nodes {
        let s = (0.5 * PI * w).tan();
        let theta = (alpha * s).atan();
        // dθ/dw of θ = atan(α tan(π w / 2)).
        let jac = alpha * 0.5 * PI * (1.0 + s * s) / (1.0 + alpha * alpha * s * s);
        let (sin_t, cos_t) = theta.sin_cos();
        for &(u, wu) in &phi_nodes {
            let (sin_p, cos_p) = (PI * u).sin_cos();
            let m = [sin_t * cos_p, sin_t * sin_p, cos_t];
            let f = g(m);
            if f != 0.0 {
                sum += ww * wu * jac * PI * 2.0 * sin_t * ndf(kind, alpha, m) * f;
            }
        }
    }
    sum
}

fn refine(panels: usize, f: impl Fn(usize) -> f64) -> Quadrature {
    let coarse = f(panels);
    let value = f(2 * panels);
    Quadrature {
        value,
        error: (value - coarse).abs(),
    }
}

/// Energy a rough interface with relative index `eta` (η beyond / η on wo's side;
/// `None` for a perfect mirror, F = 1) reflects (`reflect`) or transmits from wo with
/// cos θo = `mu` > 0, at `panels` panels per variable.
fn interface(
    kind: Ndf,
    alpha: f64,
    eta: Option<f64>,
    mu: f64,
    panels: usize,
    reflected: bool,
) -> f64 {
    let v = dir(mu);
    over_normals(kind, alpha, panels, &|m| {
        let c = dot(v, m);
        let g1 = smith_g1(kind, alpha, v, m);
        if c <= 0.0 || g1 == 0.0 {
            return 0.0;
        }
        let f = eta.map_or(1.0, |eta| fresnel(c, eta));
        let share = if reflected {
            let r = reflect(v, m);
            if r[2] <= 0.0 {
                return 0.0;
            }
            f * smith_g1(kind, alpha, r, m)
        } else {
            if f >= 1.0 {
                return 0.0;
            }
            let t = refract(v, m, eta.expect("a transmitting interface has an index"));
            if t[2] >= 0.0 {
                return 0.0;
            }
            (1.0 - f) * smith_g1(kind, alpha, t, m)
        };
        c / mu * g1 * share
    })
}

/// Panels per variable of the base grid (the error estimate doubles it).
const PANELS: usize = 12;

/// Rough conductor with F = 1 (Mitsuba's roughconductor, material "none").
pub fn rough_conductor_white(kind: Ndf, alpha: f64, mu: f64) -> Quadrature {
    refine(PANELS, |p| interface(kind, alpha, None, mu, p, true))
}

/// Rough dielectric, white, from the side where the index beyond is `eta` times wo's:
/// reflected plus transmitted energy (Mitsuba's roughdielectric).
pub fn rough_dielectric_white(kind: Ndf, alpha: f64, eta: f64, mu: f64) -> Quadrature {
    refine(PANELS, |p| {
        interface(kind, alpha, Some(eta), mu, p, true)
            + interface(kind, alpha, Some(eta), mu, p, false)
    })
}

/// 2 ∫₀¹ g(μ) μ dμ (a hemispherical cosine-weighted mean), `panels` panels over μ.
fn cosine_mean(panels: usize, g: impl Fn(f64) -> f64) -> f64 {
    gauss_legendre(panels)
        .iter()
        .map(|&(mu, w)| 2.0 * w * mu * g(mu))
        .sum()
}

/// Smooth plastic (Mitsuba's plastic): the specular F(μo) plus the diffuse base seen
/// through the interface, ρ (1 - F(μo)) (1 - F_dr,ext) / (η² (1 - ρ' F_dr,int)) with
/// ρ' = ρ when `nonlinear`, else 1, and F_dr the hemispherical mean of F from outside
/// (η) and inside (1/η). Mitsuba approximates F_dr by fits (Egan and Hilgeman 1973,
/// d'Eon and Irving 2011, within 0.1% for η in [1, 2]); this integrates it.
pub fn plastic(rho: f64, eta: f64, nonlinear: bool, mu: f64) -> Quadrature {
    let at = |panels: usize| {
        let fdr_ext = cosine_mean(panels, |m| fresnel(m, eta));
        let fdr_int = cosine_mean(panels, |m| fresnel(m, 1.0 / eta));
        let f = fresnel(mu, eta);
        let internal = if nonlinear { rho * fdr_int } else { fdr_int };
        f + rho * (1.0 - f) * (1.0 - fdr_ext) / (eta * eta * (1.0 - internal))
    };
    refine(64, at)
}

/// The parts of rough plastic's albedo (Mitsuba's roughplastic), white coating.
#[derive(Clone, Copy, Debug)]
pub struct RoughPlastic {
    /// The coating's glossy reflection.
    pub specular: Quadrature,
    /// The diffuse base seen through the coating.
    pub diffuse: Quadrature,
}

impl RoughPlastic {
    pub fn total(&self) -> Quadrature {
        Quadrature {
            value: self.specular.value + self.diffuse.value,
            error: self.specular.error + self.diffuse.error,
        }
    }
}

/// Rough plastic with diffuse reflectance `rho` and coating index `eta`:
/// specular R(μo) and diffuse ρ / (1 - ρ' R_int) · T(μo) · T̄ / η², with T(μ) the
/// coating's transmittance from outside, T̄ its cosine mean (the 1/π of the base's
/// Lambertian lobe and the cos θi of the albedo integrate to 2 ∫ T μ dμ), R_int the
/// cosine mean of the reflectance from inside (η → 1/η, with total internal
/// reflection) and ρ' = ρ when `nonlinear`, else 1.
pub fn rough_plastic(
    kind: Ndf,
    alpha: f64,
    rho: f64,
    eta: f64,
    nonlinear: bool,
    mu: f64,
) -> RoughPlastic {
    let specular = refine(PANELS, |p| interface(kind, alpha, Some(eta), mu, p, true));
    // The hemispherical means: fewer panels per direction, more directions.
    let diffuse = refine(6, |p| {
        let t_o = interface(kind, alpha, Some(eta), mu, p, false);
        let t_mean = cosine_mean(p, |m| interface(kind, alpha, Some(eta), m, p, false));
        let r_int = cosine_mean(p, |m| interface(kind, alpha, Some(1.0 / eta), m, p, true));
        let internal = if nonlinear { rho * r_int } else { r_int };
        rho / (1.0 - internal) * t_o * t_mean / (eta * eta)
    });
    RoughPlastic { specular, diffuse }
}

/// Mitsuba's `pplastic` (RGB variants) with grey diffuse `rho` and index `eta`: the
/// rough interface's reflection plus ρ (1 - F(μo)) · 2 ∫ (1 - F(μ)) μ dμ (the
/// Lambertian lobe seen through a smooth refraction in and one out, no internal
/// scattering).
pub fn pplastic(kind: Ndf, alpha: f64, rho: f64, eta: f64, mu: f64) -> Quadrature {
    let specular = refine(PANELS, |p| interface(kind, alpha, Some(eta), mu, p, true));
    let diffuse = refine(64, |p| {
        rho * (1.0 - fresnel(mu, eta)) * cosine_mean(p, |m| 1.0 - fresnel(m, eta))
    });
    Quadrature {
        value: specular.value + diffuse.value,
        error: specular.error + diffuse.error,
    }
}

/// Nori's microfacet (Beckmann) with diffuse `kd` (grey) and relative index `eta`:
/// kd + ks ∫ D F G (wo·m) / cos θo dm over the upper hemisphere, ks = 1 - kd.
pub fn nori_microfacet(alpha: f64, kd: f64, eta: f64, mu: f64) -> Quadrature {
    let ks = 1.0 - kd;
    let spec = refine(PANELS, |p| {
        interface(Ndf::Beckmann, alpha, Some(eta), mu, p, true)
    });
    Quadrature {
        value: kd + ks * spec.value,
        error: ks * spec.error,
    }
}
