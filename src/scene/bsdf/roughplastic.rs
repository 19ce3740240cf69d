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
//! transmittance at 32 angles and its internal reflectance.
//!
//! ```xml
//! <bsdf type="roughplastic"><string name="distribution" value="ggx"/><float name="alpha" value="0.2"/></bsdf>
//! ```

use glam::Vec3;

use super::ior::{relative_ior, EXT_IOR};
use super::kinds::{self, Kind};
use super::microfacet::{
    self, distribution_id, microfacet_params, rough_reflectance, Distribution,
};
use super::plastic::{
    sampling_weight, DIFFUSE_REFLECTANCE, INT_IOR, NONLINEAR, SPECULAR_REFLECTANCE, TEXTURES,
};
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
        for (i, t) in table.iter().enumerate() {
            r.table[i / 4][i % 4] = *t as f32;
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

/// Points Mitsuba's roughplastic.cpp tabulates the coating at
/// (`MI_ROUGH_TRANSMITTANCE_RES`).
const MITSUBA_ROUGH_RES: usize = 64;

/// Rough plastic's tables (Mitsuba's roughplastic.cpp precomputes the same at 64
/// points): the coating's transmittance T(μ_i) = 1 - R(μ_i, η) at μ_i = i / 31 (μ_0 =
/// 1e-6 as Mitsuba), and the internal reflectance R_int ≈ 2 ∫ R(μ, 1/η) μ dμ computed
/// exactly as Mitsuba does: 2 · mean of R(μ_j, 1/η) μ_j over its 64 points μ_j =
/// max(j / 63, 1e-6). That sum weighs the end points fully and divides by 64, so it is
/// 1.5% below the integral (0.59 vs 0.60 at α = 0.1, η = 1.49); the diffuse term
/// ρ / (1 - R_int) is 2.3% darker for it, which Mitsuba's reference images show
/// (test_surf_area_light of its media suite).
pub fn rough_coating_tables(
    d: Distribution,
    alpha: f64,
    eta: f64,
) -> ([f64; BSDF_TABLE_SIZE], f64) {
    let n = BSDF_TABLE_SIZE;
    let mut table = [0.0; BSDF_TABLE_SIZE];
    for (i, t) in table.iter_mut().enumerate() {
        let mu = (i as f64 / (n - 1) as f64).max(1e-6);
        *t = 1.0 - rough_reflectance(d, alpha, mu, eta);
    }
    let m = MITSUBA_ROUGH_RES;
    let internal = (0..m)
        .map(|j| {
            let mu = (j as f64 / (m - 1) as f64).max(1e-6);
            rough_reflectance(d, alpha, mu, 1.0 / eta) * mu
        })
        .sum::<f64>()
        * 2.0
        / m as f64;
    (table, internal)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::bsdf::fresnel::{diffuse_fresnel, fresnel_dielectric};

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
            assert!((t[31] - (1.0 - fresnel_dielectric(1.0, 1.49))).abs() < 1e-3);
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
