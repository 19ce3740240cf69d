//! `diffuse`: Lambertian reflection, f = ρ / π (Mitsuba 3's `diffuse.cpp`, Nori's
//! `diffuse.cpp`). One-sided; sampled cosine-weighted. GLSL: `shaders/bsdf/diffuse.glsl`.
//!
//! | dialect | parameter | type | default |
//! |---------|-----------|------|---------|
//! | Mitsuba | `reflectance` | spectrum or texture | 0.5 |
//! | Nori | `albedo` | color | 0.5 |
//!
//! ```xml
//! <bsdf type="diffuse"><rgb name="reflectance" value="0.2, 0.25, 0.7"/></bsdf>
//! ```

use glam::Vec3;

use super::kinds::{self, Kind};
use super::{Bsdf, BsdfModel, Plugin, Slot, TestParams, WarpTest};
use crate::gpu::layout::BsdfRecord;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const KIND: &Kind = kinds::find("diffuse");

/// Lambertian reflection with albedo `reflectance`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Diffuse {
    pub reflectance: Vec3,
}

pub const MITSUBA: Plugin = Plugin::new(
    PluginDoc::new(
        Family::Bsdf,
        Dialect::Mitsuba,
        "diffuse",
        "Lambertian reflection.",
        &[Param::new("reflectance", "rgb|texture", "0.5", "albedo")],
    ),
    mitsuba,
)
.textures(&[("reflectance", Slot::Reflectance)])
.warptest(WarpTest {
    kind: KIND,
    params: &[],
    make: warptest,
});

pub const NORI: Plugin = Plugin::new(
    PluginDoc::new(
        Family::Bsdf,
        Dialect::Nori,
        "diffuse",
        "Lambertian reflection.",
        &[Param::new("albedo", "color", "0.5", "albedo")],
    ),
    nori,
);

fn mitsuba(props: &Properties) -> Result<Bsdf, Error> {
    Ok(Bsdf::Diffuse(Diffuse {
        reflectance: props.color("reflectance", Vec3::splat(0.5))?,
    }))
}

fn nori(props: &Properties) -> Result<Bsdf, Error> {
    Ok(Bsdf::Diffuse(Diffuse {
        reflectance: props.color("albedo", Vec3::splat(0.5))?,
    }))
}

fn warptest(_: &TestParams) -> Bsdf {
    Bsdf::Diffuse(Diffuse {
        reflectance: Vec3::splat(0.5),
    })
}

impl BsdfModel for Diffuse {
    fn kind(&self) -> &'static Kind {
        KIND
    }

    fn pack(&self, r: &mut BsdfRecord) {
        r.reflectance = self.reflectance.into();
    }
}
