//! `dielectric`: a smooth dielectric interface, Fresnel reflection and refraction by
//! Snell's law (Mitsuba 3's `dielectric.cpp`, Nori's `dielectric.cpp`). Both sides
//! (wo below the surface: inside); two delta lobes, chosen by their Fresnel
//! probabilities. GLSL: `shaders/bsdf/dielectric.glsl`.
//!
//! | dialect | parameter | type | default |
//! |---------|-----------|------|---------|
//! | Mitsuba | `int_ior` | number or name ([`IOR_PRESETS`]) | `bk7` = 1.5046 |
//! | Mitsuba | `ext_ior` | number or name | `air` = 1.000277 |
//! | Mitsuba | `specular_reflectance`, `specular_transmittance` | spectrum or texture | 1 |
//! | Nori | `intIOR`, `extIOR` | float | 1.5046, 1.000277 |
//!
//! The record holds the relative index `eta` = int / ext.
//!
//! ```xml
//! <bsdf type="dielectric"><string name="int_ior" value="water"/></bsdf>
//! ```
//!
//! [`IOR_PRESETS`]: super::IOR_PRESETS

use glam::Vec3;

use super::ior::{nori_eta, relative_ior, EXT_IOR, INT_IOR_BK7, NORI_EXT_IOR, NORI_INT_IOR};
use super::kinds::{self, Kind};
use super::{Bsdf, BsdfModel, Plugin, Slot};
use crate::gpu::layout::BsdfRecord;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const KIND: &Kind = kinds::find("dielectric");

/// A smooth interface of relative index `eta` (interior over exterior).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dielectric {
    pub eta: f32,
    pub specular_reflectance: Vec3,
    pub specular_transmittance: Vec3,
}

// The spectra scaling the dielectrics' lobes (thin and rough ones read them too).
pub(super) const SPECULAR_REFLECTANCE: Param = Param::new(
    "specular_reflectance",
    "rgb|texture",
    "1",
    "scales the reflection",
);
pub(super) const SPECULAR_TRANSMITTANCE: Param = Param::new(
    "specular_transmittance",
    "rgb|texture",
    "1",
    "scales the transmission",
);
pub(super) const TEXTURES: &[(&str, Slot)] = &[
    ("specular_reflectance", Slot::Specular),
    ("specular_transmittance", Slot::Transmittance),
];

pub const MITSUBA: Plugin = Plugin::new(
    PluginDoc::new(
        Family::Bsdf,
        Dialect::Mitsuba,
        "dielectric",
        "A smooth dielectric interface (Fresnel reflection and refraction).",
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

pub const NORI: Plugin = Plugin::new(
    PluginDoc::new(
        Family::Bsdf,
        Dialect::Nori,
        "dielectric",
        "A smooth dielectric interface (Fresnel reflection and refraction).",
        &[NORI_INT_IOR, NORI_EXT_IOR],
    ),
    nori,
);

fn mitsuba(props: &Properties) -> Result<Bsdf, Error> {
    Ok(Bsdf::Dielectric(Dielectric {
        eta: relative_ior(props, "int_ior", "ext_ior", "bk7", false)?,
        specular_reflectance: props.color("specular_reflectance", Vec3::ONE)?,
        specular_transmittance: props.color("specular_transmittance", Vec3::ONE)?,
    }))
}

fn nori(props: &Properties) -> Result<Bsdf, Error> {
    Ok(Bsdf::Dielectric(Dielectric {
        eta: nori_eta(props, false)?,
        specular_reflectance: Vec3::ONE,
        specular_transmittance: Vec3::ONE,
    }))
}

impl BsdfModel for Dielectric {
    fn kind(&self) -> &'static Kind {
        KIND
    }

    fn pack(&self, r: &mut BsdfRecord) {
        r.eta = self.eta;
        r.specular = self.specular_reflectance.into();
        r.transmittance = self.specular_transmittance.into();
    }
}
