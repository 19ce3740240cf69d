//! `plastic`: smooth plastic, a diffuse base under a smooth dielectric coating with
//! internal scattering (Mitsuba 3's `plastic.cpp`, after Weidlich and Wilkie 2007,
//! "Arbitrarily layered micro-facet surfaces"). One-sided; a delta lobe (the
//! coating's reflection) and a diffuse one. GLSL: `shaders/bsdf/plastic.glsl`.
//!
//! | parameter | type | default |
//! |-----------|------|---------|
//! | `diffuse_reflectance` | spectrum or texture | 0.5 |
//! | `specular_reflectance` | spectrum or texture | 1 |
//! | `int_ior` | number or name | `polypropylene` = 1.49 |
//! | `ext_ior` | number or name | `air` = 1.000277 |
//! | `nonlinear` | boolean | false |
//!
//! The host packs what Mitsuba precomputes: the lobe sampling weight and the internal
//! diffuse Fresnel reflectance (its polynomial fit, [`fresnel_diffuse_reflectance_fit`]).
//!
//! ```xml
//! <bsdf type="plastic"><rgb name="diffuse_reflectance" value="0.1, 0.27, 0.36"/><float name="int_ior" value="1.9"/></bsdf>
//! ```

use glam::Vec3;

use super::fresnel::fresnel_diffuse_reflectance_fit;
use super::ior::{relative_ior, EXT_IOR};
use super::kinds::{self, Kind};
use super::{Bsdf, BsdfModel, Plugin, Slot, TestParams, WarpTest};
use crate::gpu::layout::{BsdfRecord, BSDF_NONLINEAR};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const KIND: &Kind = kinds::find("plastic");

/// A diffuse base of albedo `diffuse_reflectance` under a smooth coating of relative
/// index `eta`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plastic {
    pub diffuse_reflectance: Vec3,
    pub specular_reflectance: Vec3,
    pub eta: f32,
    pub nonlinear: bool,
}

// The parameters of the plastics (`roughplastic` reads them too).
pub(super) const DIFFUSE_REFLECTANCE: Param = Param::new(
    "diffuse_reflectance",
    "rgb|texture",
    "0.5",
    "albedo of the diffuse base",
);
pub(super) const SPECULAR_REFLECTANCE: Param = Param::new(
    "specular_reflectance",
    "rgb|texture",
    "1",
    "scales the coating's reflection",
);
pub(super) const INT_IOR: Param = Param::new(
    "int_ior",
    "float|string",
    "polypropylene",
    "interior index of refraction, a number or a name",
);
pub(super) const NONLINEAR: Param = Param::new(
    "nonlinear",
    "boolean",
    "false",
    "account for the color shift of internal scattering (Mitsuba's nonlinear)",
);
pub(super) const TEXTURES: &[(&str, Slot)] = &[
    ("diffuse_reflectance", Slot::Reflectance),
    ("specular_reflectance", Slot::Specular),
];

pub const MITSUBA: Plugin = Plugin::new(
    PluginDoc::new(
        Family::Bsdf,
        Dialect::Mitsuba,
        "plastic",
        "Smooth plastic: a diffuse base under a smooth dielectric coating.",
        &[
            DIFFUSE_REFLECTANCE,
            SPECULAR_REFLECTANCE,
            INT_IOR,
            EXT_IOR,
            NONLINEAR,
        ],
    ),
    mitsuba,
)
.textures(TEXTURES)
.warptest(WarpTest {
    kind: KIND,
    params: &["eta"],
    make: warptest,
});

fn mitsuba(props: &Properties) -> Result<Bsdf, Error> {
    Ok(Bsdf::Plastic(Plastic {
        diffuse_reflectance: props.color("diffuse_reflectance", Vec3::splat(0.5))?,
        specular_reflectance: props.color("specular_reflectance", Vec3::ONE)?,
        eta: relative_ior(props, "int_ior", "ext_ior", "polypropylene", false)?,
        nonlinear: props.boolean("nonlinear", false)?,
    }))
}

fn warptest(p: &TestParams) -> Bsdf {
    Bsdf::Plastic(Plastic {
        diffuse_reflectance: Vec3::splat(0.5),
        specular_reflectance: Vec3::ONE,
        eta: p.eta,
        nonlinear: false,
    })
}

impl BsdfModel for Plastic {
    fn kind(&self) -> &'static Kind {
        KIND
    }

    fn pack(&self, r: &mut BsdfRecord) {
        r.reflectance = self.diffuse_reflectance.into();
        r.specular = self.specular_reflectance.into();
        r.eta = self.eta;
        r.flags |= if self.nonlinear { BSDF_NONLINEAR } else { 0 };
        r.specular_weight = sampling_weight(self.diffuse_reflectance, self.specular_reflectance);
        r.internal = fresnel_diffuse_reflectance_fit(1.0 / self.eta as f64) as f32;
    }
}

/// Plastics: probability weight of the specular lobe, s / (d + s) with d, s the
/// channel means of the diffuse and specular reflectances (Mitsuba's plastic.cpp).
pub(super) fn sampling_weight(diffuse: Vec3, specular: Vec3) -> f32 {
    let d = diffuse.element_sum() / 3.0;
    let s = specular.element_sum() / 3.0;
    if d + s > 0.0 {
        s / (d + s)
    } else {
        0.5
    }
}
