//! `roughconductor`: a rough conductor, the microfacet model of Walter et al. 2007
//! ("Microfacet Models for Refraction through Rough Surfaces") with the conductor
//! Fresnel term (Mitsuba 3's `roughconductor.cpp`). One-sided. GLSL:
//! `shaders/bsdf/roughconductor.glsl`.
//!
//! Parameters: those of [`conductor`], plus `distribution`
//! (`beckmann` | `ggx`, default `beckmann`) and `alpha` (0.1) or both `alpha_u` and
//! `alpha_v` (anisotropic), each a float or a texture; `sample_visible` is accepted
//! (GGX always samples visible normals, Heitz 2018; Beckmann never).
//!
//! ```xml
//! <bsdf type="roughconductor"><string name="distribution" value="ggx"/><float name="alpha" value="0.3"/></bsdf>
//! ```

use glam::Vec3;

use super::ior::conductor_ior;
use super::kinds::{self, Kind};
use super::microfacet::{self, distribution_id, microfacet_params, Distribution};
use super::{conductor, Bsdf, BsdfModel, LobeAxis, Plugin, Slot, TestParams, WarpTest};
use crate::gpu::layout::BsdfRecord;
use crate::scene::plugin::{Family, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const KIND: &Kind = kinds::find("roughconductor");

/// A rough conductor of complex index `eta` + i `k`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoughConductor {
    pub distribution: Distribution,
    pub alpha_u: f32,
    pub alpha_v: f32,
    pub eta: Vec3,
    pub k: Vec3,
    pub specular_reflectance: Vec3,
}

pub const MITSUBA: Plugin = Plugin::new(
    PluginDoc::new(
        Family::Bsdf,
        Dialect::Mitsuba,
        "roughconductor",
        "A rough conductor (microfacet model, Walter et al. 2007).",
        &[
            conductor::MATERIAL,
            conductor::ETA,
            conductor::K,
            conductor::SPECULAR_REFLECTANCE,
            microfacet::DISTRIBUTION,
            microfacet::ALPHA,
            microfacet::ALPHA_U,
            microfacet::ALPHA_V,
            microfacet::SAMPLE_VISIBLE,
        ],
    ),
    mitsuba,
)
.textures(&[
    ("specular_reflectance", Slot::Specular),
    ("eta", Slot::CondEta),
    ("k", Slot::CondK),
    ("alpha", Slot::Alpha),
    ("alpha_u", Slot::AlphaU),
    ("alpha_v", Slot::AlphaV),
])
.warptest(WarpTest {
    kind: KIND,
    params: &["alpha", "alpha-u", "alpha-v", "distribution"],
    make: warptest,
});

fn mitsuba(props: &Properties) -> Result<Bsdf, Error> {
    let (distribution, alpha_u, alpha_v) = microfacet_params(props, true)?;
    let (eta, k) = conductor_ior(props)?;
    Ok(Bsdf::RoughConductor(RoughConductor {
        distribution,
        alpha_u,
        alpha_v,
        eta,
        k,
        specular_reflectance: props.color("specular_reflectance", Vec3::ONE)?,
    }))
}

fn warptest(p: &TestParams) -> Bsdf {
    Bsdf::RoughConductor(RoughConductor {
        distribution: p.distribution,
        alpha_u: p.alpha_u,
        alpha_v: p.alpha_v,
        // Copper (Mitsuba's "Cu" at the RGB primaries).
        eta: Vec3::new(0.2, 0.92, 1.1),
        k: Vec3::new(3.9, 2.46, 2.14),
        specular_reflectance: Vec3::ONE,
    })
}

impl BsdfModel for RoughConductor {
    fn kind(&self) -> &'static Kind {
        KIND
    }

    fn pack(&self, r: &mut BsdfRecord) {
        r.distribution = distribution_id(self.distribution);
        (r.alpha_u, r.alpha_v) = (self.alpha_u, self.alpha_v);
        r.cond_eta = self.eta.into();
        r.cond_k = self.k.into();
        r.specular = self.specular_reflectance.into();
    }

    fn lobe_axis(&self) -> LobeAxis {
        if self.alpha_u.max(self.alpha_v) < 0.2 {
            LobeAxis::Reflect
        } else {
            LobeAxis::Normal
        }
    }
}
