//! `thindielectric`: a thin dielectric slab, a window pane modelled as one sheet
//! (Mitsuba 3's `thindielectric.cpp`). Light is reflected specularly with the slab's
//! reflectance R' = 2R / (1 + R) (R: Fresnel reflectance of one interface; the sum
//! over inter-reflections R + T²R/(1 - R²), T = 1 - R) and the rest passes straight
//! through, undeflected. The volumetric path tracers cross it as Mitsuba's volpath
//! crosses a null lobe (no path vertex; shadow rays pass it attenuated by 1 - R').
//! GLSL: `shaders/bsdf/thindielectric.glsl`.
//!
//! Parameters as [`dielectric`](super::dielectric)'s Mitsuba ones: `int_ior`
//! (number or name, default `bk7` = 1.5046), `ext_ior` (`air`),
//! `specular_reflectance` (1), `specular_transmittance` (1).
//!
//! ```xml
//! <bsdf type="thindielectric"><string name="int_ior" value="water"/></bsdf>
//! ```

use glam::Vec3;

use super::dielectric::{SPECULAR_REFLECTANCE, SPECULAR_TRANSMITTANCE, TEXTURES};
use super::ior::{relative_ior, EXT_IOR, INT_IOR_BK7};
use super::kinds::{self, Kind};
use super::{Bsdf, BsdfModel, Plugin};
use crate::gpu::layout::BsdfRecord;
use crate::scene::plugin::{Family, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const KIND: &Kind = kinds::find("thindielectric");

/// A thin slab of relative index `eta`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThinDielectric {
    pub eta: f32,
    pub specular_reflectance: Vec3,
    pub specular_transmittance: Vec3,
}

pub const MITSUBA: Plugin = Plugin::new(
    PluginDoc::new(
        Family::Bsdf,
        Dialect::Mitsuba,
        "thindielectric",
        "A thin dielectric slab: specular reflection, and light passing straight through.",
        &[
            INT_IOR_BK7,
            EXT_IOR,
            SPECULAR_REFLECTANCE,
            SPECULAR_TRANSMITTANCE,
        ],
    ),
    mitsuba,
)
.textures(TEXTURES);

fn mitsuba(props: &Properties) -> Result<Bsdf, Error> {
    Ok(Bsdf::ThinDielectric(ThinDielectric {
        eta: relative_ior(props, "int_ior", "ext_ior", "bk7", false)?,
        specular_reflectance: props.color("specular_reflectance", Vec3::ONE)?,
        specular_transmittance: props.color("specular_transmittance", Vec3::ONE)?,
    }))
}

impl BsdfModel for ThinDielectric {
    fn kind(&self) -> &'static Kind {
        KIND
    }

    fn pack(&self, r: &mut BsdfRecord) {
        r.eta = self.eta;
        r.specular = self.specular_reflectance.into();
        r.transmittance = self.specular_transmittance.into();
    }
}
