//! `hair`: Mitsuba 3's hair BSDF (`src/bsdfs/hair.cpp`), the model of Chiang et al.
//! 2016, "A Practical and Controllable Hair and Fur Model for Production Path
//! Tracing" (pbrt-v4's `HairBxDF` is the same): a rough dielectric cylinder whose
//! scattering sums the lobes R, TT, TRT and the rest, each a longitudinal lobe
//! (d'Eon et al. 2011) tilted by the cuticle scales, an attenuation (Fresnel, and
//! absorption along the chords through the fiber) and an azimuthal trimmed logistic.
//! With no absorption it keeps all energy. GLSL: `shaders/bsdf/hair.glsl`.
//!
//! As Mitsuba's: the fiber runs along the shading frame's second axis (n × ∂p/∂u: a
//! curve's length, a cylinder's axis, a sphere's meridians), and the offset h across
//! the fiber is sin γ of the viewer's direction in the fiber's normal plane (from the
//! direction, not from the hit's uv), so any shape may carry it. Both sides scatter.
//!
//! Absorption σ_a (per unit of fiber radius): from the pigment concentrations
//! (eumelanin · (0.419, 0.697, 1.37) + pheomelanin · (0.187, 0.4, 1.05), d'Eon et al.
//! 2011) unless `sigma_a` is given, then `scale` · `sigma_a` (`scale` is read but
//! unused with pigments, as in Mitsuba). Giving `sigma_a` and a pigment is an error.
//!
//! | parameter | type | default | |
//! |-----------|------|---------|-|
//! | `eumelanin`, `pheomelanin` | float | 1.3, 0.2 | pigment concentrations |
//! | `sigma_a` | spectrum or texture | (pigments) | absorption coefficient |
//! | `scale` | float | 1 | factor of `sigma_a` |
//! | `int_ior`, `ext_ior` | float or name | amber (1.55), air | η = int / ext |
//! | `longitudinal_roughness` | float in [0, 1] | 0.3 | β_m |
//! | `azimuthal_roughness` | float in [0, 1] | 0.3 | β_n |
//! | `scale_tilt` | float (degrees) | 2 | α, the cuticle scales' angle |
//!
//! Mitsuba's `eta` and `use_pigmentation` are traversal parameters, not scene ones
//! (its constructor does not read them), so here too they are unknown parameters.
//!
//! Packing: σ_a in [`BsdfRecord::reflectance`] (so a `sigma_a` texture is looked up
//! there), the precomputed constants in [`BsdfRecord::table`] (`T_*`); the record's
//! `eta` stays 1 (light crosses the whole fiber: Mitsuba's `bs.eta = 1`).
//!
//! ```xml
//! <bsdf type="hair"><float name="eumelanin" value="0.2"/><float name="pheomelanin" value="0.4"/></bsdf>
//! ```

use glam::Vec3;

use super::ior::relative_ior;
use super::kinds::{self, Kind};
use super::principled::set_table;
use super::{Bsdf, BsdfModel, LobeAxis, Plugin, Slot, TestParams, WarpTest};
use crate::gpu::layout::BsdfRecord;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const KIND: &Kind = kinds::find("hair");

/// Table entries (hair.glsl's `hair_of`): the longitudinal variances v_0..v_3 ...
pub const T_V: usize = 0;
/// ... the azimuthal logistic scale s ...
pub const T_S: usize = 4;
/// ... sin 2^k α and cos 2^k α (k = 0, 1, 2) ...
pub const T_SIN_2K_ALPHA: usize = 5;
pub const T_COS_2K_ALPHA: usize = 8;
/// ... η ...
pub const T_ETA: usize = 11;
/// ... and the factor of σ_a (`scale`; 1 with pigments).
pub const T_SCALE: usize = 12;

/// d'Eon et al. 2011's absorption of the pigments, per unit concentration.
pub const EUMELANIN_SIGMA_A: Vec3 = Vec3::new(0.419, 0.697, 1.37);
pub const PHEOMELANIN_SIGMA_A: Vec3 = Vec3::new(0.187, 0.4, 1.05);

/// Where the absorption comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Absorption {
    Pigments {
        eumelanin: f32,
        pheomelanin: f32,
    },
    /// `sigma_a` (its mean when textured) and `scale`.
    SigmaA {
        sigma_a: Vec3,
        scale: f32,
    },
}

/// Mitsuba's hair BSDF.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hair {
    pub absorption: Absorption,
    /// int_ior / ext_ior.
    pub eta: f32,
    /// β_m, β_n.
    pub longitudinal_roughness: f32,
    pub azimuthal_roughness: f32,
    /// α in degrees.
    pub scale_tilt: f32,
}

impl Default for Hair {
    fn default() -> Self {
        Hair {
            absorption: Absorption::Pigments {
                eumelanin: 1.3,
                pheomelanin: 0.2,
            },
            eta: 1.55 / 1.000277,
            longitudinal_roughness: 0.3,
            azimuthal_roughness: 0.3,
            scale_tilt: 2.0,
        }
    }
}

impl Hair {
    /// σ_a times its scale (the untextured value).
    pub fn sigma_a(&self) -> Vec3 {
        match self.absorption {
            Absorption::Pigments {
                eumelanin,
                pheomelanin,
            } => eumelanin * EUMELANIN_SIGMA_A + pheomelanin * PHEOMELANIN_SIGMA_A,
            Absorption::SigmaA { sigma_a, scale } => scale * sigma_a,
        }
    }

    /// Mitsuba's `update()`: v_p, s, sin and cos of 2^k α, in f32 as there.
    pub fn constants(&self) -> ([f32; 4], f32, [f32; 3], [f32; 3]) {
        let (bm, bn) = (self.longitudinal_roughness, self.azimuthal_roughness);
        let mut sin2k = [0.0f32; 3];
        let mut cos2k = [0.0f32; 3];
        sin2k[0] = self.scale_tilt.to_radians().sin();
        cos2k[0] = (1.0 - sin2k[0] * sin2k[0]).max(0.0).sqrt();
        for i in 1..3 {
            sin2k[i] = 2.0 * cos2k[i - 1] * sin2k[i - 1];
            cos2k[i] = cos2k[i - 1] * cos2k[i - 1] - sin2k[i - 1] * sin2k[i - 1];
        }
        let s = (std::f32::consts::PI / 8.0).sqrt()
            * (0.265 * bn + 1.194 * bn * bn + 5.372 * bn.powi(22));
        let v0 = (0.726 * bm + 0.812 * bm * bm + 3.7 * bm.powi(20)).powi(2);
        ([v0, 0.25 * v0, 4.0 * v0, 4.0 * v0], s, sin2k, cos2k)
    }
}

const fn p(
    name: &'static str,
    ty: &'static str,
    default: &'static str,
    doc: &'static str,
) -> Param {
    Param::new(name, ty, default, doc)
}

pub const MITSUBA: Plugin = Plugin::new(
    PluginDoc::new(
        Family::Bsdf,
        Dialect::Mitsuba,
        "hair",
        "Hair and fur (Chiang et al. 2016) as Mitsuba 3's: R, TT, TRT and the rest, with pigment absorption.",
        &[
            p("eumelanin", "float", "1.3", "eumelanin concentration"),
            p("pheomelanin", "float", "0.2", "pheomelanin concentration"),
            p("sigma_a", "spectrum or texture", "from the pigments", "absorption coefficient per unit radius, instead of the pigments"),
            p("scale", "float", "1", "factor of sigma_a"),
            p("int_ior", "float or string", "amber", "interior index of refraction"),
            p("ext_ior", "float or string", "air", "exterior index of refraction"),
            p("longitudinal_roughness", "float", "0.3", "roughness along the fiber, in [0, 1]"),
            p("azimuthal_roughness", "float", "0.3", "roughness around the fiber, in [0, 1]"),
            p("scale_tilt", "float", "2", "angle of the cuticle scales, degrees"),
        ],
    ),
    mitsuba,
)
.textures(&[("sigma_a", Slot::Reflectance)])
.warptest(WarpTest {
    kind: KIND,
    params: &["alpha", "alpha-u", "alpha-v", "eta"],
    make: warptest,
});

fn mitsuba(props: &Properties) -> Result<Bsdf, Error> {
    let d = Hair::default();
    let roughness = |key: &str| -> Result<f32, Error> {
        let v = props.float(key, 0.3)?;
        if !(0.0..=1.0).contains(&v) {
            return Err(props.error(key, format!("'{key}' must be in [0, 1], found {v}")));
        }
        Ok(v)
    };
    let longitudinal_roughness = roughness("longitudinal_roughness")?;
    let azimuthal_roughness = roughness("azimuthal_roughness")?;
    let scale_tilt = props.float("scale_tilt", d.scale_tilt)?;
    if !scale_tilt.is_finite() {
        return Err(props.error("scale_tilt", "'scale_tilt' must be finite"));
    }
    let eta = relative_ior(props, "int_ior", "ext_ior", "amber", true)?;
    let eumelanin = props.float("eumelanin", 1.3)?;
    let pheomelanin = props.float("pheomelanin", 0.2)?;
    let scale = props.float("scale", 1.0)?;
    let absorption = if props.has("sigma_a") {
        for key in ["eumelanin", "pheomelanin"] {
            if props.has(key) {
                return Err(props.error(
                    key,
                    format!(
                        "give either the pigments or 'sigma_a', not both ('{key}' and 'sigma_a')"
                    ),
                ));
            }
        }
        Absorption::SigmaA {
            sigma_a: props.color("sigma_a", Vec3::ZERO)?,
            scale,
        }
    } else {
        Absorption::Pigments {
            eumelanin,
            pheomelanin,
        }
    };
    Ok(Bsdf::Hair(Hair {
        absorption,
        eta,
        longitudinal_roughness,
        azimuthal_roughness,
        scale_tilt,
    }))
}

/// warptest: β_m = `alpha-u`, β_n = `alpha-v` (both `alpha`), η = `eta`, the default
/// pigments.
fn warptest(p: &TestParams) -> Bsdf {
    Bsdf::Hair(Hair {
        eta: p.eta,
        longitudinal_roughness: p.alpha_u.min(1.0),
        azimuthal_roughness: p.alpha_v.min(1.0),
        ..Hair::default()
    })
}

impl BsdfModel for Hair {
    fn kind(&self) -> &'static Kind {
        KIND
    }

    fn pack(&self, r: &mut BsdfRecord) {
        let (v, s, sin2k, cos2k) = self.constants();
        match self.absorption {
            Absorption::Pigments { .. } => {
                r.reflectance = self.sigma_a().into();
                set_table(r, T_SCALE, 1.0);
            }
            Absorption::SigmaA { sigma_a, scale } => {
                r.reflectance = sigma_a.into();
                set_table(r, T_SCALE, scale);
            }
        }
        for (k, x) in v.iter().enumerate() {
            set_table(r, T_V + k, *x);
        }
        set_table(r, T_S, s);
        for k in 0..3 {
            set_table(r, T_SIN_2K_ALPHA + k, sin2k[k]);
            set_table(r, T_COS_2K_ALPHA + k, cos2k[k]);
        }
        set_table(r, T_ETA, self.eta);
    }

    fn lobe_axis(&self) -> LobeAxis {
        LobeAxis::Normal
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::testutil::{error_at, load, mitsuba};

    #[test]
    fn reads_mitsuba_parameters_and_defaults() {
        let body = r#"<bsdf type="hair" id="a"/>
<bsdf type="hair" id="b"><rgb name="sigma_a" value="0.2, 0.25, 0.7"/><float name="scale" value="200"/><float name="int_ior" value="1.3"/><float name="longitudinal_roughness" value="0.1"/><float name="azimuthal_roughness" value="0.6"/><float name="scale_tilt" value="-3"/></bsdf>
<bsdf type="hair" id="c"><float name="eumelanin" value="0.2"/><float name="pheomelanin" value="0.4"/><float name="scale" value="5"/></bsdf>
<bsdf type="hair" id="d"><texture type="checkerboard" name="sigma_a"/></bsdf>"#;
        let s = load(&[("s.xml", &mitsuba(body))], &[]).expect("scene");
        assert_eq!(s.bsdfs[0], Bsdf::Hair(Hair::default()));
        let Bsdf::Hair(b) = s.bsdfs[1] else {
            panic!("{:?}", s.bsdfs[1])
        };
        assert_eq!(
            b.absorption,
            Absorption::SigmaA {
                sigma_a: Vec3::new(0.2, 0.25, 0.7),
                scale: 200.0
            }
        );
        assert!((b.eta - 1.3 / 1.000277).abs() < 1e-6);
        assert_eq!(
            (
                b.longitudinal_roughness,
                b.azimuthal_roughness,
                b.scale_tilt
            ),
            (0.1, 0.6, -3.0)
        );
        let Bsdf::Hair(c) = s.bsdfs[2] else {
            panic!("{:?}", s.bsdfs[2])
        };
        // Pigments ignore `scale`, as Mitsuba's.
        assert!(
            (c.sigma_a() - Vec3::new(0.1586, 0.2994, 0.694))
                .abs()
                .max_element()
                < 1e-5
        );
        let r = BsdfRecord::from(&s.bsdfs[2]);
        assert_eq!((r.kind, r.eta), (KIND.id, 1.0));
        assert_eq!(f32::from_bits(r.table[T_SCALE / 4][T_SCALE % 4]), 1.0);
        assert!(matches!(s.bsdfs[3], Bsdf::Textured { .. }));
    }

    #[test]
    fn errors_name_the_parameter() {
        let cases: &[(&str, u32, &str)] = &[
            ("<bsdf type=\"hair\"><rgb name=\"sigma_a\" value=\"1\"/>\n<float name=\"pheomelanin\" value=\"0.5\"/></bsdf>", 4, "either the pigments or 'sigma_a'"),
            ("<bsdf type=\"hair\">\n<float name=\"longitudinal_roughness\" value=\"1.5\"/></bsdf>", 4, "must be in [0, 1]"),
            ("<bsdf type=\"hair\">\n<float name=\"azimuthal_roughness\" value=\"-0.1\"/></bsdf>", 4, "must be in [0, 1]"),
            ("<bsdf type=\"hair\">\n<float name=\"int_ior\" value=\"1.000277\"/></bsdf>", 4, "must differ"),
            ("<bsdf type=\"hair\">\n<float name=\"eta\" value=\"1.5\"/></bsdf>", 4, "eta"),
        ];
        for (body, line, msg) in cases {
            let e = error_at(load(&[("s.xml", &mitsuba(body))], &[]), "s.xml", *line);
            assert!(e.contains(msg), "{e}\n  wanted: {msg}");
        }
    }
}
