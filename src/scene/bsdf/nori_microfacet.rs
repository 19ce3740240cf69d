//! Nori's `microfacet` (the course's assignment 5): a Lambertian term of albedo `kd`
//! plus a Beckmann specular lobe of weight ks = 1 - max(kd), roughness `alpha` and
//! the dielectric Fresnel term of `intIOR` / `extIOR`, with the Smith shadowing of
//! Walter et al. 2007 (eq. 27). One-sided. GLSL: `shaders/bsdf/nori_microfacet.glsl`
//! (kind `nori_microfacet`, as Mitsuba has no such plugin).
//!
//! | parameter | type | default |
//! |-----------|------|---------|
//! | `alpha` | float | 0.1 |
//! | `kd` | color, each channel at most 1 | 0.5 |
//! | `intIOR`, `extIOR` | float, must differ | 1.5046, 1.000277 |
//!
//! ```xml
//! <bsdf type="microfacet"><float name="alpha" value="0.28"/><color name="kd" value="0.2,0.2,0.4"/></bsdf>
//! ```

use glam::Vec3;

use super::ior::{nori_eta, NORI_EXT_IOR, NORI_INT_IOR};
use super::kinds::{self, Kind};
use super::microfacet::check_alpha;
use super::{Bsdf, BsdfModel, LobeAxis, Plugin, TestParams, WarpTest};
use crate::gpu::layout::BsdfRecord;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const KIND: &Kind = kinds::find("nori_microfacet");

/// Diffuse `kd` plus a Beckmann lobe of roughness `alpha` and relative index `eta`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NoriMicrofacet {
    pub alpha: f32,
    pub eta: f32,
    pub kd: Vec3,
}

pub const NORI: Plugin = Plugin::new(
    PluginDoc::new(
        Family::Bsdf,
        Dialect::Nori,
        "microfacet",
        "Diffuse plus a Beckmann specular lobe of weight 1 - max(kd).",
        &[
            Param::new("alpha", "float", "0.1", "Beckmann roughness"),
            Param::new(
                "kd",
                "color",
                "0.5",
                "diffuse albedo, each channel at most 1",
            ),
            NORI_INT_IOR,
            NORI_EXT_IOR,
        ],
    ),
    nori,
)
.warptest(WarpTest {
    kind: KIND,
    params: &["alpha", "eta"],
    make: warptest,
});

fn nori(props: &Properties) -> Result<Bsdf, Error> {
    let alpha = props.float("alpha", 0.1)?;
    check_alpha(props, "alpha", alpha)?;
    let kd = props.color("kd", Vec3::splat(0.5))?;
    if kd.max_element() > 1.0 {
        return Err(props.error("kd", "microfacet 'kd' must not exceed 1 (ks = 1 - max(kd))"));
    }
    Ok(Bsdf::NoriMicrofacet(NoriMicrofacet {
        alpha: alpha.max(1e-4),
        eta: nori_eta(props, true)?,
        kd,
    }))
}

fn warptest(p: &TestParams) -> Bsdf {
    Bsdf::NoriMicrofacet(NoriMicrofacet {
        alpha: p.alpha_u,
        eta: p.eta,
        kd: Vec3::splat(0.5),
    })
}

impl BsdfModel for NoriMicrofacet {
    fn kind(&self) -> &'static Kind {
        KIND
    }

    fn pack(&self, r: &mut BsdfRecord) {
        r.reflectance = self.kd.into();
        r.specular_weight = 1.0 - self.kd.max_element();
        (r.alpha_u, r.alpha_v) = (self.alpha, self.alpha);
        r.eta = self.eta;
    }

    fn lobe_axis(&self) -> LobeAxis {
        if self.alpha < 0.2 {
            LobeAxis::Reflect
        } else {
            LobeAxis::Normal
        }
    }
}
