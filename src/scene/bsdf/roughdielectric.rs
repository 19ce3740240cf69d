//! `roughdielectric`: a rough dielectric interface, the microfacet model of Walter et
//! al. 2007 ("Microfacet Models for Refraction through Rough Surfaces"), reflection
//! and refraction (Mitsuba 3's `roughdielectric.cpp`). Both sides. GLSL:
//! `shaders/bsdf/roughdielectric.glsl`.
//!
//! Parameters: those of [`dielectric`](super::dielectric) (the two indices must
//! differ), plus `distribution` and `alpha` / `alpha_u` + `alpha_v` as
//! [`roughconductor`](super::roughconductor).
//!
//! ```xml
//! <bsdf type="roughdielectric"><string name="distribution" value="ggx"/><float name="alpha" value="0.1"/></bsdf>
//! ```

use glam::Vec3;

use super::dielectric::{SPECULAR_REFLECTANCE, SPECULAR_TRANSMITTANCE};
use super::ior::{relative_ior, EXT_IOR, INT_IOR_BK7};
use super::kinds::{self, Kind};
use super::microfacet::{self, distribution_id, microfacet_params, Distribution};
use super::{Bsdf, BsdfModel, LobeAxis, Plugin, Slot, TestParams, WarpTest};
use crate::gpu::layout::BsdfRecord;
use crate::scene::plugin::{Family, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const KIND: &Kind = kinds::find("roughdielectric");

/// A rough interface of relative index `eta` (interior over exterior).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoughDielectric {
    pub distribution: Distribution,
    pub alpha_u: f32,
    pub alpha_v: f32,
    pub eta: f32,
    pub specular_reflectance: Vec3,
    pub specular_transmittance: Vec3,
}

pub const MITSUBA: Plugin = Plugin::new(
    PluginDoc::new(
        Family::Bsdf,
        Dialect::Mitsuba,
        "roughdielectric",
        "A rough dielectric interface (microfacet model, Walter et al. 2007).",
        &[
            INT_IOR_BK7,
            EXT_IOR,
            SPECULAR_REFLECTANCE,
            SPECULAR_TRANSMITTANCE,
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
    ("specular_transmittance", Slot::Transmittance),
    ("alpha", Slot::Alpha),
    ("alpha_u", Slot::AlphaU),
    ("alpha_v", Slot::AlphaV),
])
.warptest(WarpTest {
    kind: KIND,
    params: &["alpha", "alpha-u", "alpha-v", "distribution", "eta"],
    make: warptest,
});

fn mitsuba(props: &Properties) -> Result<Bsdf, Error> {
    let (distribution, alpha_u, alpha_v) = microfacet_params(props, true)?;
    Ok(Bsdf::RoughDielectric(RoughDielectric {
        distribution,
        alpha_u,
        alpha_v,
        eta: relative_ior(props, "int_ior", "ext_ior", "bk7", true)?,
        specular_reflectance: props.color("specular_reflectance", Vec3::ONE)?,
        specular_transmittance: props.color("specular_transmittance", Vec3::ONE)?,
    }))
}

fn warptest(p: &TestParams) -> Bsdf {
    Bsdf::RoughDielectric(RoughDielectric {
        distribution: p.distribution,
        alpha_u: p.alpha_u,
        alpha_v: p.alpha_v,
        eta: p.eta,
        specular_reflectance: Vec3::ONE,
        specular_transmittance: Vec3::ONE,
    })
}

impl BsdfModel for RoughDielectric {
    fn kind(&self) -> &'static Kind {
        KIND
    }

    fn pack(&self, r: &mut BsdfRecord) {
        r.distribution = distribution_id(self.distribution);
        (r.alpha_u, r.alpha_v) = (self.alpha_u, self.alpha_v);
        r.eta = self.eta;
        r.specular = self.specular_reflectance.into();
        r.transmittance = self.specular_transmittance.into();
    }

    fn lobe_axis(&self) -> LobeAxis {
        if self.alpha_u.max(self.alpha_v) < 0.2 {
            LobeAxis::Refract(self.eta)
        } else {
            LobeAxis::Normal
        }
    }
}
