//! `roughplastic`: rough plastic, a diffuse base under a rough dielectric coating
//! (Mitsuba 3's `roughplastic.cpp`: the microfacet reflection of Walter et al. 2007
//! over a diffuse base seen through the coating's transmittance). One-sided,
//! isotropic. GLSL: `shaders/bsdf/roughplastic.glsl`.
//!
//! Parameters: those of [`plastic`](super::plastic) (the two indices must differ),
//! plus `distribution` (`beckmann`) and `alpha` (0.1, a plain float: the coating's
//! tables depend on it, as in Mitsuba).
//!
//! The host packs what Mitsuba precomputes ([`rough_coating_tables`]): the coating's
//! transmittance at 64 angles and its internal reflectance, by Mitsuba's own
//! quadrature (`rough_coating`).
//!
//! ```xml
//! <bsdf type="roughplastic"><string name="distribution" value="ggx"/><float name="alpha" value="0.2"/></bsdf>
//! ```

use std::sync::Mutex;

use glam::Vec3;
use rayon::prelude::*;

use super::ior::{relative_ior, EXT_IOR};
use super::kinds::{self, Kind};
use super::microfacet::{self, distribution_id, microfacet_params, Distribution};
use super::plastic::{
    sampling_weight, DIFFUSE_REFLECTANCE, INT_IOR, NONLINEAR, SPECULAR_REFLECTANCE, TEXTURES,
};
use super::rough_coating::mitsuba_rough_interface;
use super::{Bsdf, BsdfModel, LobeAxis, Plugin, TestParams, WarpTest};
use crate::gpu::layout::{BsdfRecord, BSDF_NONLINEAR, BSDF_TABLE_SIZE};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const KIND: &Kind = kinds::find("roughplastic");

/// A diffuse base of albedo `diffuse_reflectance` under a rough coating of relative
/// index `eta` and roughness `alpha`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoughPlastic {
    pub distribution: Distribution,
    pub alpha: f32,
    pub diffuse_reflectance: Vec3,
    pub specular_reflectance: Vec3,
    pub eta: f32,
    pub nonlinear: bool,
}

pub const MITSUBA: Plugin = Plugin::new(
    PluginDoc::new(
        Family::Bsdf,
        Dialect::Mitsuba,
        "roughplastic",
        "Rough plastic: a diffuse base under a rough dielectric coating.",
        &[
            DIFFUSE_REFLECTANCE,
            SPECULAR_REFLECTANCE,
            INT_IOR,
            EXT_IOR,
            NONLINEAR,
            microfacet::DISTRIBUTION,
            Param::new(
                "alpha",
                "float",
                "0.1",
                "roughness (isotropic; a plain float, as the coating's tables depend on it)",
            ),
            microfacet::SAMPLE_VISIBLE,
        ],
    ),
    mitsuba,
)
.textures(TEXTURES)
.warptest(WarpTest {
    kind: KIND,
    params: &["alpha", "distribution", "eta"],
    make: warptest,
});

fn mitsuba(props: &Properties) -> Result<Bsdf, Error> {
    let (distribution, alpha, _) = microfacet_params(props, false)?;
    Ok(Bsdf::RoughPlastic(RoughPlastic {
        distribution,
        alpha,
        diffuse_reflectance: props.color("diffuse_reflectance", Vec3::splat(0.5))?,
        specular_reflectance: props.color("specular_reflectance", Vec3::ONE)?,
        eta: relative_ior(props, "int_ior", "ext_ior", "polypropylene", true)?,
        nonlinear: props.boolean("nonlinear", false)?,
    }))
}

fn warptest(p: &TestParams) -> Bsdf {
    Bsdf::RoughPlastic(RoughPlastic {
        distribution: p.distribution,
        alpha: p.alpha_u,
        diffuse_reflectance: Vec3::splat(0.5),
        specular_reflectance: Vec3::ONE,
        eta: p.eta,
        nonlinear: false,
    })
}

impl BsdfModel for RoughPlastic {
    fn kind(&self) -> &'static Kind {
        KIND
    }

    fn pack(&self, r: &mut BsdfRecord) {
        r.distribution = distribution_id(self.distribution);
        (r.alpha_u, r.alpha_v) = (self.alpha, self.alpha);
        r.reflectance = self.diffuse_reflectance.into();
        r.specular = self.specular_reflectance.into();
        r.eta = self.eta;
        r.flags |= if self.nonlinear { BSDF_NONLINEAR } else { 0 };
        r.specular_weight = sampling_weight(self.diffuse_reflectance, self.specular_reflectance);
        let (table, internal) =
            rough_coating_tables(self.distribution, self.alpha as f64, self.eta as f64);
        // Two entries a word, as unorm16 (steps of 1.5e-5; T is in [0, 1]).
        for (i, pair) in table.chunks(2).enumerate() {
            let unorm = |t: f64| (t.clamp(0.0, 1.0) * 65535.0).round() as u32;
            r.table[i / 4][i % 4] = unorm(pair[0]) | (unorm(pair[1]) << 16);
        }
        r.internal = internal as f32;
    }

    fn lobe_axis(&self) -> LobeAxis {
        if self.alpha < 0.2 {
            LobeAxis::Reflect
        } else {
            LobeAxis::Normal
        }
    }
}

/// Points Mitsuba's roughplastic.cpp tabulates the coating's transmittance at
/// (`MI_ROUGH_TRANSMITTANCE_RES`), packed two a word into `BsdfRecord::table`.
pub const ROUGH_TABLE_RES: usize = 2 * BSDF_TABLE_SIZE;

/// Rough plastic's tables, as Mitsuba's roughplastic.cpp precomputes them
/// (`parameters_changed`): at its 64 points μ_j = max(j / 63, 1e-6), the coating's
/// transmittance T(μ_j) from outside (`eval_transmittance`: light that enters through
/// a facet and is not shadowed; not 1 - R, shadowing loses light), and the internal
/// reflectance R_int = 2 · mean_j R(μ_j, 1/η) μ_j (`eval_reflectance` from inside).
/// That mean weighs the end points fully and divides by 64, so it is 1.5% below
/// 2 ∫ R μ dμ (0.59 vs 0.60 at α = 0.1, η = 1.49); the diffuse term ρ / (1 - R_int)
/// is 2.3% darker for it, which Mitsuba's reference images show
/// (test_surf_area_light of its media suite). Both integrals use Mitsuba's own
/// visible-normal Gauss-Legendre quadrature (`rough_coating`), whose discretisation
/// is part of the model its images show.
pub fn rough_coating_tables(
    d: Distribution,
    alpha: f64,
    eta: f64,
) -> ([f64; ROUGH_TABLE_RES], f64) {
    type Tables = ([f64; ROUGH_TABLE_RES], f64);
    type Key = (Distribution, u64, u64);
    // Scenes repeat a coating (and packing runs more than once): 64 · (32² + 128²)
    // visible normals per coating, remembered by its parameters.
    static MEMO: Mutex<Vec<(Key, Tables)>> = Mutex::new(Vec::new());
    let key = (d, alpha.to_bits(), eta.to_bits());
    if let Some((_, t)) = MEMO
        .lock()
        .ok()
        .and_then(|m| m.iter().find(|(k, _)| *k == key).copied())
    {
        return t;
    }
    let n = ROUGH_TABLE_RES;
    let mu = |j: usize| (j as f64 / (n - 1) as f64).max(1e-6);
    let rows: Vec<(f64, f64)> = (0..n)
        .into_par_iter()
        .map(|j| {
            (
                mitsuba_rough_interface(d, alpha, mu(j), eta, true),
                mitsuba_rough_interface(d, alpha, mu(j), 1.0 / eta, false) * mu(j),
            )
        })
        .collect();
    let mut table = [0.0; ROUGH_TABLE_RES];
    for (t, row) in table.iter_mut().zip(&rows) {
        *t = row.0;
    }
    let internal = rows.iter().map(|r| r.1).sum::<f64>() * 2.0 / n as f64;
    if let Ok(mut m) = MEMO.lock() {
        m.push((key, (table, internal)));
    }
    (table, internal)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::bsdf::fresnel::{diffuse_fresnel, fresnel_dielectric};
    use crate::scene::bsdf::rough_reflectance;

    /// Mitsuba 3.9.1's diffuse part (scalar_rgb, `ctx.component = 1`, white base,
    /// int_ior 1.5, ext_ior 1, wi = the normal) at cos θo against the one these tables
    /// give: ρ / (1 - R_int) · T(1) T(cos θo) cos θo / (π η²), T interpolated as the
    /// GPU does.
    #[test]
    fn tables_match_mitsuba_diffuse_eval() {
        let cases = [
            (
                Distribution::Ggx,
                1.0,
                [
                    (0.05, 0.002_224_547_3),
                    (0.5, 0.045_990_653),
                    (1.0, 0.124_359_56),
                ],
            ),
            (
                Distribution::Ggx,
                0.05,
                [
                    (0.05, 0.006_880_354_1),
                    (0.5, 0.145_659_70),
                    (1.0, 0.307_546_02),
                ],
            ),
            (
                Distribution::Beckmann,
                1.0,
                [
                    (0.2, 0.025_762_955),
                    (0.5, 0.075_716_078),
                    (1.0, 0.165_731_19),
                ],
            ),
        ];
        for (d, alpha, evals) in cases {
            let (t, internal) = rough_coating_tables(d, alpha, 1.5);
            let lerp = |mu: f64| {
                let x = mu * 63.0;
                let i = (x as usize).min(62);
                t[i] + (t[i + 1] - t[i]) * (x - i as f64)
            };
            for (mu, want) in evals {
                let got =
                    lerp(1.0) * lerp(mu) * mu / (std::f64::consts::PI * 2.25 * (1.0 - internal));
                assert!(
                    (got / want - 1.0).abs() < 2e-5,
                    "{d:?} α = {alpha}, μ = {mu}: {got} vs Mitsuba {want}"
                );
            }
        }
    }

    #[test]
    fn rough_reflectance_tends_to_smooth() {
        // Small roughness: R(μ) approaches the smooth Fresnel reflectance.
        for mu in [0.3, 0.7, 1.0] {
            for d in [Distribution::Beckmann, Distribution::Ggx] {
                let r = rough_reflectance(d, 0.01, mu, 1.5);
                let f = fresnel_dielectric(mu, 1.5);
                assert!((r - f).abs() < 0.01 * f + 1e-3, "{d:?} μ={mu}: {r} vs {f}");
            }
        }
        // Smooth limit of the internal reflectance: the diffuse Fresnel reflectance.
        for d in [Distribution::Beckmann, Distribution::Ggx] {
            let (t, internal) = rough_coating_tables(d, 0.01, 1.49);
            let fdr = diffuse_fresnel(1.0 / 1.49);
            assert!((internal - fdr).abs() < 0.02, "{d:?}: {internal} vs {fdr}");
            assert!((t[63] - (1.0 - fresnel_dielectric(1.0, 1.49))).abs() < 1e-3);
        }
        // Rough: transmittances in [0, 1], less internal reflection (light escapes
        // through tilted facets, and shadowing loses some).
        let (t, internal) = rough_coating_tables(Distribution::Ggx, 0.5, 1.49);
        assert!(t.iter().all(|&v| (0.0..=1.0).contains(&v)));
        println!("GGX 0.5: R_int = {internal}, T = {t:?}");
        assert!(
            internal > 0.1 && internal < diffuse_fresnel(1.0 / 1.49),
            "{internal}"
        );
    }
}
