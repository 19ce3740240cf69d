//! `conductor`: a smooth conductor, a mirror with the Fresnel reflectance of the
//! complex index η + iκ (Mitsuba 3's `conductor.cpp`); Nori's `mirror` is the perfect
//! mirror among them (η = 0, κ = 1: reflectance 1). One-sided, a delta lobe.
//! GLSL: `shaders/bsdf/conductor.glsl`.
//!
//! | parameter | type | default |
//! |-----------|------|---------|
//! | `material` | string: any of Mitsuba's named conductors (`Au`, `Cu`, `a-C`, ... [`CONDUCTOR_PRESETS`]) or `none` | `none` (a perfect mirror) |
//! | `eta`, `k` | float, rgb, spectrum or texture (not with `material`) | 0, 1 |
//! | `specular_reflectance` | spectrum or texture | 1 |
//!
//! Nori `mirror` takes no parameters.
//!
//! ```xml
//! <bsdf type="conductor"><string name="material" value="Au"/></bsdf>
//! ```
//!
//! [`CONDUCTOR_PRESETS`]: super::CONDUCTOR_PRESETS

use glam::Vec3;

use super::ior::conductor_ior;
use super::kinds::{self, Kind};
use super::{Bsdf, BsdfModel, Plugin, Slot};
use crate::gpu::layout::BsdfRecord;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const KIND: &Kind = kinds::find("conductor");

/// A smooth conductor of complex index `eta` + i `k`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Conductor {
    pub eta: Vec3,
    pub k: Vec3,
    pub specular_reflectance: Vec3,
}

// The parameters of Mitsuba's conductors (`roughconductor` reads them too).
pub(super) const MATERIAL: Param = Param::new(
    "material",
    "string",
    "none",
    "named conductor: any of Mitsuba 3's 71 (a-C, Ag, Al, AlAs, AlSb, Au, Be, Cr, CsI, Cu, Cu2O, CuO, d-C, Hg, HgTe, Ir, K, Li, MgO, Mo, Na_palik, Nb, Ni_palik, Rh, Se, SiC, SnTe, Ta, Te, ThF4, TiC, TiN, TiO2, VC, V_palik, VN, W and their _palik / -e variants), or none (a perfect mirror); not with eta, k",
);
pub(super) const ETA: Param = Param::new(
    "eta",
    "float|rgb|spectrum|texture",
    "0",
    "real part of the index of refraction",
);
pub(super) const K: Param = Param::new(
    "k",
    "float|rgb|spectrum|texture",
    "1",
    "imaginary part of the index of refraction",
);
pub(super) const SPECULAR_REFLECTANCE: Param = Param::new(
    "specular_reflectance",
    "rgb|texture",
    "1",
    "scales the reflectance",
);

pub const MITSUBA: Plugin = Plugin::new(
    PluginDoc::new(
        Family::Bsdf,
        Dialect::Mitsuba,
        "conductor",
        "A smooth conductor: a mirror with the Fresnel reflectance of eta + i k.",
        &[MATERIAL, ETA, K, SPECULAR_REFLECTANCE],
    ),
    mitsuba,
)
.textures(&[
    ("specular_reflectance", Slot::Specular),
    ("eta", Slot::CondEta),
    ("k", Slot::CondK),
]);

pub const NORI_MIRROR: Plugin = Plugin::new(
    PluginDoc::new(
        Family::Bsdf,
        Dialect::Nori,
        "mirror",
        "A perfect mirror.",
        &[],
    ),
    nori_mirror,
);

fn mitsuba(props: &Properties) -> Result<Bsdf, Error> {
    let (eta, k) = conductor_ior(props)?;
    Ok(Bsdf::Conductor(Conductor {
        eta,
        k,
        specular_reflectance: props.color("specular_reflectance", Vec3::ONE)?,
    }))
}

fn nori_mirror(_: &Properties) -> Result<Bsdf, Error> {
    Ok(Bsdf::Conductor(Conductor {
        eta: Vec3::ZERO,
        k: Vec3::ONE,
        specular_reflectance: Vec3::ONE,
    }))
}

impl BsdfModel for Conductor {
    fn kind(&self) -> &'static Kind {
        KIND
    }

    fn pack(&self, r: &mut BsdfRecord) {
        r.cond_eta = self.eta.into();
        r.cond_k = self.k.into();
        r.specular = self.specular_reflectance.into();
    }
}
