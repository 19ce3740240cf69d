//! `pplastic`: "polarized plastic", Mitsuba 3's `pplastic.cpp` after the pBRDF of Baek
//! et al. 2018 ("Simultaneous Acquisition of Polarimetric SVBRDF and Normals"), as it
//! behaves in Mitsuba's RGB (unpolarized) variants: a rough dielectric microfacet
//! reflection (Walter et al. 2007) added to a Lambertian lobe seen through two smooth
//! refractions. Unlike [`roughplastic`](super::roughplastic) the two are summed ad hoc
//! (no internal scattering, not energy conserving). One-sided, anisotropic.
//! GLSL: `shaders/bsdf/pplastic.glsl`.
//!
//! With wo towards the viewer and wi towards the light (local frame, z the normal):
//!
//! f(wo, wi) cos θi = spec · F(wo·m, η) D(m) G(wo, wi, m) / (4 cos θo)
//!                  + ρ (1 - F(cos θo, η)) (1 - F(cos θi, η)) cos θi / π,
//! m = normalize(wo + wi). Sampling picks the microfacet lobe with probability
//! s / (d + s), d and s the channel means of `diffuse_reflectance` and
//! `specular_reflectance` (1 when absent), else a cosine-weighted direction; the
//! pdf is that mixture.
//!
//! | parameter | type | default |
//! |-----------|------|---------|
//! | `diffuse_reflectance` | spectrum or texture | 0.5 |
//! | `specular_reflectance` | spectrum or texture | 1 |
//! | `int_ior` | number or name | `polypropylene` = 1.49 |
//! | `ext_ior` | number or name | `air` = 1.000277 |
//! | `eta` | float, rgb, spectrum or texture | `int_ior / ext_ior` (instead of the two) |
//! | `distribution` | `beckmann` or `ggx` | `beckmann` |
//! | `alpha` (or `alpha_u` + `alpha_v`) | float or texture | 0.1 |
//! | `sample_visible` | boolean | true |
//!
//! `eta` as Mitsuba 3.9.1 reads it (`get_unbounded_texture("eta")`, then
//! `m_eta->eval_1(si)` wherever eval needs a Fresnel term; pdf and the lobe
//! weights do not read it): a texture (record slot `tex_eta`, looked up at the hit
//! by bsdf_textured.glsl) gives its `eval_1`, a bitmap's the luminance of its RGB, a
//! checkerboard's its squares' values (swapped as `texture_eval_1` says); an `rgb`
//! or `spectrum` value its channels' mean (the unbounded `srgb` texture's `eval_1`).
//! A constant must be positive and not 1 (Mitsuba takes any: 1 turns the Fresnel
//! terms off, 0 gives NaN); a texture's values are used as they are, below 1 too
//! (total reflection past the critical angle, as Mitsuba's `fresnel`). `eta` with
//! `int_ior` or `ext_ior` is an error (Mitsuba refuses `int_ior` and leaves
//! `ext_ior` unread, also an error there).
//!
//! Differences from Mitsuba: Beckmann samples
//! its full normal distribution rather than the visible normals (as every
//! microfacet model here, `shaders/bsdf/microfacet.glsl`), so its pdf is that of
//! Mitsuba's `sample_visible="false"`; the sampled directions and eval agree.
//!
//! ```xml
//! <bsdf type="pplastic"><rgb name="diffuse_reflectance" value="0.05, 0.03, 0.1"/><float name="alpha" value="0.06"/></bsdf>
//! ```

use glam::Vec3;

use super::ior::{relative_ior, EXT_IOR};
use super::kinds::{self, Kind};
use super::microfacet::{self, distribution_id, microfacet_params, Distribution};
use super::plastic::{sampling_weight, DIFFUSE_REFLECTANCE, INT_IOR, SPECULAR_REFLECTANCE};
use super::{Bsdf, BsdfModel, LobeAxis, Plugin, Slot, TestParams, WarpTest};
use crate::gpu::layout::BsdfRecord;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const KIND: &Kind = kinds::find("pplastic");

/// A rough specular reflection of relative index `eta` plus a Lambertian lobe of
/// albedo `diffuse_reflectance` attenuated by two smooth refractions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PPlastic {
    pub distribution: Distribution,
    pub alpha_u: f32,
    pub alpha_v: f32,
    pub diffuse_reflectance: Vec3,
    pub specular_reflectance: Vec3,
    pub eta: f32,
}

pub const MITSUBA: Plugin = Plugin::new(
    PluginDoc::new(
        Family::Bsdf,
        Dialect::Mitsuba,
        "pplastic",
        "Polarized plastic (Baek et al. 2018) as Mitsuba's RGB variants: rough reflection plus a refracted diffuse lobe.",
        &[
            DIFFUSE_REFLECTANCE,
            SPECULAR_REFLECTANCE,
            INT_IOR,
            EXT_IOR,
            Param::new(
                "eta",
                "float",
                "int_ior / ext_ior",
                "relative index of refraction, instead of int_ior and ext_ior",
            ),
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
    ("diffuse_reflectance", Slot::Reflectance),
    ("specular_reflectance", Slot::Specular),
    ("alpha", Slot::Alpha),
    ("alpha_u", Slot::AlphaU),
    ("alpha_v", Slot::AlphaV),
    ("eta", Slot::Eta),
])
.warptest(WarpTest {
    kind: KIND,
    params: &["alpha", "alpha-u", "alpha-v", "distribution", "eta"],
    make: warptest,
});

fn mitsuba(props: &Properties) -> Result<Bsdf, Error> {
    let (distribution, alpha_u, alpha_v) = microfacet_params(props, true)?;
    let eta = if props.has("eta") {
        for key in ["int_ior", "ext_ior"] {
            if props.has(key) {
                return Err(props.error(key, "give either 'eta' or 'int_ior' and 'ext_ior'"));
            }
        }
        let textured = props.textures().iter().any(|(name, _)| name == "eta");
        if textured {
            // The texture's mean luminance; bsdf_textured.glsl replaces it at each hit.
            props.float("eta", 1.49)?
        } else {
            // A float, or the mean of an rgb/spectrum (Mitsuba's srgb eval_1).
            let c = props.color("eta", Vec3::splat(1.49))?;
            let eta = if c.x == c.y && c.y == c.z {
                c.x
            } else {
                c.element_sum() / 3.0
            };
            if !(eta > 0.0 && eta.is_finite() && eta != 1.0) {
                return Err(props.error(
                    "eta",
                    format!("'eta' must be positive and not 1, found {eta}"),
                ));
            }
            eta
        }
    } else {
        relative_ior(props, "int_ior", "ext_ior", "polypropylene", true)?
    };
    Ok(Bsdf::PPlastic(PPlastic {
        distribution,
        alpha_u,
        alpha_v,
        diffuse_reflectance: props.color("diffuse_reflectance", Vec3::splat(0.5))?,
        specular_reflectance: props.color("specular_reflectance", Vec3::ONE)?,
        eta,
    }))
}

fn warptest(p: &TestParams) -> Bsdf {
    Bsdf::PPlastic(PPlastic {
        distribution: p.distribution,
        alpha_u: p.alpha_u,
        alpha_v: p.alpha_v,
        diffuse_reflectance: Vec3::splat(0.5),
        specular_reflectance: Vec3::ONE,
        eta: p.eta,
    })
}

impl BsdfModel for PPlastic {
    fn kind(&self) -> &'static Kind {
        KIND
    }

    fn pack(&self, r: &mut BsdfRecord) {
        r.distribution = distribution_id(self.distribution);
        (r.alpha_u, r.alpha_v) = (self.alpha_u, self.alpha_v);
        r.reflectance = self.diffuse_reflectance.into();
        r.specular = self.specular_reflectance.into();
        r.eta = self.eta;
        r.specular_weight = sampling_weight(self.diffuse_reflectance, self.specular_reflectance);
    }

    fn lobe_axis(&self) -> LobeAxis {
        if self.alpha_u.max(self.alpha_v) < 0.2 {
            LobeAxis::Reflect
        } else {
            LobeAxis::Normal
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::testutil::{error_at, load, mitsuba};

    #[test]
    fn reads_mitsuba_parameters_and_defaults() {
        let body = r#"<bsdf type="pplastic" id="a"/>
<bsdf type="pplastic" id="b"><string name="distribution" value="GGX"/><float name="alpha_u" value="0.05"/><float name="alpha_v" value="0.3"/><float name="eta" value="1.33"/><rgb name="diffuse_reflectance" value="0.05, 0.03, 0.1"/><rgb name="specular_reflectance" value="0.5"/></bsdf>
<bsdf type="pplastic" id="c"><string name="int_ior" value="bk7"/><float name="ext_ior" value="1.0"/><float name="alpha" value="0.2"/></bsdf>"#;
        let s = load(&[("s.xml", &mitsuba(body))], &[]).expect("scene");
        assert_eq!(
            s.bsdfs[0],
            Bsdf::PPlastic(PPlastic {
                distribution: Distribution::Beckmann,
                alpha_u: 0.1,
                alpha_v: 0.1,
                diffuse_reflectance: Vec3::splat(0.5),
                specular_reflectance: Vec3::ONE,
                eta: 1.49 / 1.000277,
            })
        );
        assert_eq!(
            s.bsdfs[1],
            Bsdf::PPlastic(PPlastic {
                distribution: Distribution::Ggx,
                alpha_u: 0.05,
                alpha_v: 0.3,
                diffuse_reflectance: Vec3::new(0.05, 0.03, 0.1),
                specular_reflectance: Vec3::splat(0.5),
                eta: 1.33,
            })
        );
        let Bsdf::PPlastic(c) = s.bsdfs[2] else {
            panic!("{:?}", s.bsdfs[2])
        };
        assert!((c.eta - 1.5046).abs() < 1e-4 && c.alpha_u == 0.2, "{c:?}");
        // The record: Mitsuba's lobe weight s / (d + s) with channel means.
        let r = BsdfRecord::from(&s.bsdfs[1]);
        assert_eq!(r.kind, KIND.id);
        assert!((r.specular_weight - 0.5 / (0.06 + 0.5)).abs() < 1e-6);
        assert_eq!(r.tex_eta, 0);
    }

    #[test]
    fn eta_as_rgb_or_texture() {
        let body = r#"<bsdf type="pplastic" id="a"><rgb name="eta" value="1.2, 1.5, 1.9"/></bsdf>
<bsdf type="pplastic" id="b"><texture type="checkerboard" name="eta"><float name="color0" value="0.75"/><float name="color1" value="1.6"/></texture></bsdf>"#;
        let s = load(&[("s.xml", &mitsuba(body))], &[]).expect("scene");
        // An rgb eta: its mean, as Mitsuba's unbounded srgb texture's eval_1.
        let Bsdf::PPlastic(a) = s.bsdfs[0] else {
            panic!("{:?}", s.bsdfs[0])
        };
        assert!((a.eta - 4.6 / 3.0).abs() < 1e-6, "{a:?}");
        // A texture feeds the record's tex_eta (index + 1) and nothing else.
        let Bsdf::Textured { bsdf, maps } = &s.bsdfs[1] else {
            panic!("{:?}", s.bsdfs[1])
        };
        assert!(matches!(**bsdf, Bsdf::PPlastic(_)));
        assert_eq!(maps.eta, Some(0));
        let r = BsdfRecord::from(&s.bsdfs[1]);
        assert_eq!((r.kind, r.tex_eta, r.tex_cond_eta), (KIND.id, 1, 0));
    }

    #[test]
    fn errors_name_the_parameter() {
        let cases: &[(&str, u32, &str)] = &[
            ("<bsdf type=\"pplastic\"><float name=\"eta\" value=\"1.3\"/>\n<float name=\"int_ior\" value=\"1.5\"/></bsdf>", 4, "either 'eta' or 'int_ior'"),
            ("<bsdf type=\"pplastic\">\n<float name=\"eta\" value=\"1\"/></bsdf>", 4, "'eta' must be positive and not 1"),
            ("<bsdf type=\"pplastic\">\n<float name=\"int_ior\" value=\"1.2\"/><float name=\"ext_ior\" value=\"1.2\"/></bsdf>", 4, "must differ"),
            ("<bsdf type=\"pplastic\">\n<float name=\"eta\" value=\"-1.5\"/></bsdf>", 4, "'eta' must be positive and not 1, found -1.5"),
            ("<bsdf type=\"pplastic\">\n<rgb name=\"eta\" value=\"0.5, -2, 0.5\"/></bsdf>", 4, "'eta' must be positive and not 1, found -0.33"),
            ("<bsdf type=\"pplastic\"><texture type=\"checkerboard\" name=\"eta\"/>\n<float name=\"int_ior\" value=\"1.5\"/></bsdf>", 4, "either 'eta' or 'int_ior'"),
            ("<bsdf type=\"pplastic\">\n<ref name=\"eta\" id=\"no_such_texture\"/></bsdf>", 4, "no_such_texture"),
            ("<bsdf type=\"pplastic\">\n<texture type=\"bitmap\" name=\"eta\"><string name=\"filename\" value=\"missing.exr\"/></texture></bsdf>", 4, "missing.exr"),
        ];
        for (body, line, msg) in cases {
            let e = error_at(load(&[("s.xml", &mitsuba(body))], &[]), "s.xml", *line);
            assert!(e.contains(msg), "{e}\n  wanted: {msg}");
        }
    }
}
