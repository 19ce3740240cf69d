//! `principled` and `principledthin`: Mitsuba 3's Disney BSDF (Burley 2012, "Physically
//! Based Shading at Disney"; Burley 2015, "Extending the Disney BRDF to a BSDF with
//! Integrated Subsurface Scattering"), as Mitsuba's `principled.cpp`,
//! `principledthin.cpp` and `principledhelpers.h` define it: the same eval, pdf and
//! lobe selection probabilities. GLSL: `shaders/bsdf/principled.glsl`,
//! `shaders/bsdf/principledthin.glsl`.
//!
//! `principled` (a solid surface, both sides: below the surface is inside):
//! - a diffuse lobe with Burley's retro-reflection (and, with `flatness`, the
//!   Hanrahan-Krueger-like fake subsurface), weight (1 - metallic)(1 - spec_trans);
//! - sheen, sheen · (1 - metallic) · Schlick(cos θd), tinted towards `base_color`;
//! - the main GGX lobe (α from roughness² and `anisotropic`, at least 0.001) reflecting
//!   with a Fresnel term that blends the true dielectric (`eta`), a Schlick metal of
//!   `base_color` and a tinted Schlick dielectric (`spec_tint`), and transmitting
//!   sqrt(base_color) (1 - F) with weight (1 - metallic) spec_trans;
//! - clearcoat: GTR1 with α = lerp(0.1, 0.001, clearcoat_gloss), Schlick F0 = 0.04,
//!   separable Smith GGX G with α = 0.25, weight clearcoat / 4.
//!
//! Sampling picks diffuse ∝ (1 - metallic)(1 - spec_trans), clearcoat ∝ clearcoat / 4,
//! transmission ∝ (1 - metallic) spec_trans (1 - F) and reflection ∝ the rest of 1
//! (each times its `*_sampling_rate`), F the dielectric Fresnel term at the sampled
//! GGX visible normal; from inside only reflection (F) and transmission (1 - F).
//! `specular` sets `eta` = 2 / (1 - sqrt(0.08 specular)) - 1 (Mitsuba's coupling);
//! giving both is an error.
//!
//! `principledthin` (a two-sided thin sheet, the same from both sides): diffuse +
//! sheen weighted (1 - spec_trans)(1 - diff_trans / 2), Lambertian transmission
//! (1 - spec_trans) diff_trans / 2 · base_color, GGX reflection spec_trans · F_thin
//! (dielectric Fresnel of `eta` lerped towards a tinted Schlick by `spec_tint`), and a
//! GGX transmission mirrored through the sheet, spec_trans · base_color · (1 - F), its
//! roughness scaled by (0.65 η - 0.35) (Burley 2015, fig. 15). No metallic or
//! clearcoat (Mitsuba's thin model has neither; giving them is an error, as there).
//!
//! | parameter | type | default | |
//! |-----------|------|---------|-|
//! | `base_color` | spectrum or texture | 0.5 | both |
//! | `roughness` | float or texture | 0.5 | both |
//! | `anisotropic` | float or texture | 0 | both |
//! | `metallic` | float or texture | 0 | principled |
//! | `spec_trans` | float or texture | 0 | both |
//! | `eta` | float (texture in principledthin) | from `specular` / 1.5 | both |
//! | `specular` | float | 0.5 | principled, instead of `eta` |
//! | `spec_tint` | float or texture | 0 | both |
//! | `sheen` | float or texture | 0 | both |
//! | `sheen_tint` | float or texture | 0 | both |
//! | `flatness` | float or texture | 0 | both |
//! | `clearcoat` | float or texture | 0 | principled |
//! | `clearcoat_gloss` | float or texture | 0 | principled |
//! | `diff_trans` | float or texture | 0 | principledthin (0 to 2) |
//! | `*_sampling_rate` | float | 1 | Mitsuba's lobe sampling rates |
//!
//! Scalar parameters live in [`BsdfRecord::table`] (entries [`T_ROUGHNESS`] ..
//! [`T_ETA`]; their textures' ids at `T_TEXTURES + entry`, the mask of textured entries
//! at [`T_TEXTURED`], flag [`BSDF_TABLE_TEXTURES`]), so the record does not grow for
//! other models; `bsdf_textured.glsl` looks them up where the scene's texture mask has
//! [`TEXTURE_FEATURE_TABLE`].
//!
//! Differences from Mitsuba: textures are looked up as everywhere in wavetrace
//! (`eval_1` of an RGB texture is its luminance, as Mitsuba's); GGX visible normals
//! are sampled by Heitz 2018 rather than Heitz 2014 (the same density); refraction is
//! in radiance mode only (no importance-mode η² scale, as `roughdielectric` here).
//!
//! ```xml
//! <bsdf type="principled"><rgb name="base_color" value="0.8, 0.2, 0.1"/><float name="metallic" value="0.3"/><float name="clearcoat" value="0.5"/></bsdf>
//! ```

use glam::Vec3;

use super::kinds::{self, Kind};
use super::{Bsdf, BsdfModel, LobeAxis, Plugin, Slot, TestParams, WarpTest};
use crate::gpu::layout::{
    BsdfRecord, BSDF_TABLE_TEXTURES, TEXTURE_FEATURE_BSDF, TEXTURE_FEATURE_TABLE,
};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const KIND: &Kind = kinds::find("principled");
pub const KIND_THIN: &Kind = kinds::find("principledthin");

/// Table entries (`PRINCIPLED_T_*` in principled.glsl): the scalar parameters, which
/// textures may replace ...
pub const T_ROUGHNESS: usize = 0;
pub const T_ANISOTROPIC: usize = 1;
pub const T_METALLIC: usize = 2;
pub const T_SPEC_TRANS: usize = 3;
pub const T_SPEC_TINT: usize = 4;
pub const T_SHEEN: usize = 5;
pub const T_SHEEN_TINT: usize = 6;
pub const T_FLATNESS: usize = 7;
pub const T_CLEARCOAT: usize = 8;
pub const T_CLEARCOAT_GLOSS: usize = 9;
/// principledthin's `diff_trans` as given (0 to 2).
pub const T_DIFF_TRANS: usize = 10;
pub const T_ETA: usize = 11;
/// ... the sampling rates (principled: main specular, clearcoat, diffuse reflection;
/// principledthin: specular reflection, specular transmission, diffuse reflection,
/// diffuse transmission) ...
pub const T_RATES: usize = 12;
/// ... the texture id + 1 of entry k at `T_TEXTURES + k` (as bits) ...
pub const T_TEXTURES: usize = 16;
/// ... the mask of textured entries (bits) ...
pub const T_TEXTURED: usize = 28;
/// ... and the `PRINCIPLED_HAS_*` flags (bits).
pub const T_HAS: usize = 29;
/// [`T_HAS`]: `spec_trans` was given (Mitsuba's `m_has_spec_trans`: the back side
/// samples transmission, and `eta` = 1 / `specular` = 0 are nudged).
pub const HAS_SPEC_TRANS: u32 = 1;
/// [`T_HAS`]: `diff_trans` was given (principledthin).
pub const HAS_DIFF_TRANS: u32 = 2;

/// Mitsuba's principled (`thin` = false) or principledthin BSDF.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Principled {
    pub thin: bool,
    pub base_color: Vec3,
    pub roughness: f32,
    pub anisotropic: f32,
    pub metallic: f32,
    pub spec_trans: f32,
    pub spec_tint: f32,
    pub sheen: f32,
    pub sheen_tint: f32,
    pub flatness: f32,
    pub clearcoat: f32,
    pub clearcoat_gloss: f32,
    /// principledthin: 0 to 2, as given.
    pub diff_trans: f32,
    /// Relative index of refraction (principled: from `specular` unless given).
    pub eta: f32,
    /// The lobe sampling rates, in the order of [`T_RATES`].
    pub rates: [f32; 4],
    /// `PRINCIPLED_HAS_*` ([`HAS_SPEC_TRANS`], [`HAS_DIFF_TRANS`]).
    pub has: u32,
}

impl Default for Principled {
    fn default() -> Self {
        Principled {
            thin: false,
            base_color: Vec3::splat(0.5),
            roughness: 0.5,
            anisotropic: 0.0,
            metallic: 0.0,
            spec_trans: 0.0,
            spec_tint: 0.0,
            sheen: 0.0,
            sheen_tint: 0.0,
            flatness: 0.0,
            clearcoat: 0.0,
            clearcoat_gloss: 0.0,
            diff_trans: 0.0,
            eta: specular_to_eta(0.5),
            rates: [1.0; 4],
            has: 0,
        }
    }
}

/// Mitsuba's coupling of `specular` and `eta` (Schlick's F0 = 0.08 specular).
pub fn specular_to_eta(specular: f32) -> f32 {
    2.0 / (1.0 - (0.08 * specular).sqrt()) - 1.0
}

const fn p(
    name: &'static str,
    ty: &'static str,
    default: &'static str,
    doc: &'static str,
) -> Param {
    Param::new(name, ty, default, doc)
}

const BASE_COLOR: Param = p(
    "base_color",
    "spectrum or texture",
    "0.5",
    "the color of the material",
);
const ROUGHNESS: Param = p(
    "roughness",
    "float or texture",
    "0.5",
    "roughness of the main specular lobes",
);
const ANISOTROPIC: Param = p(
    "anisotropic",
    "float or texture",
    "0",
    "degree of anisotropy",
);
const SPEC_TRANS: Param = p(
    "spec_trans",
    "float or texture",
    "0",
    "weight of specular transmission",
);
const SPEC_TINT: Param = p(
    "spec_tint",
    "float or texture",
    "0",
    "tint of the dielectric specular towards base_color",
);
const SHEEN: Param = p("sheen", "float or texture", "0", "weight of the sheen lobe");
const SHEEN_TINT: Param = p(
    "sheen_tint",
    "float or texture",
    "0",
    "tint of the sheen towards base_color",
);
const FLATNESS: Param = p(
    "flatness",
    "float or texture",
    "0",
    "blend of the diffuse lobe towards fake subsurface",
);

const TEXTURES: &[(&str, Slot)] = &[
    ("base_color", Slot::Reflectance),
    ("roughness", Slot::Table(T_ROUGHNESS as u8)),
    ("anisotropic", Slot::Table(T_ANISOTROPIC as u8)),
    ("metallic", Slot::Table(T_METALLIC as u8)),
    ("spec_trans", Slot::Table(T_SPEC_TRANS as u8)),
    ("spec_tint", Slot::Table(T_SPEC_TINT as u8)),
    ("sheen", Slot::Table(T_SHEEN as u8)),
    ("sheen_tint", Slot::Table(T_SHEEN_TINT as u8)),
    ("flatness", Slot::Table(T_FLATNESS as u8)),
    ("clearcoat", Slot::Table(T_CLEARCOAT as u8)),
    ("clearcoat_gloss", Slot::Table(T_CLEARCOAT_GLOSS as u8)),
];

const TEXTURES_THIN: &[(&str, Slot)] = &[
    ("base_color", Slot::Reflectance),
    ("roughness", Slot::Table(T_ROUGHNESS as u8)),
    ("anisotropic", Slot::Table(T_ANISOTROPIC as u8)),
    ("spec_trans", Slot::Table(T_SPEC_TRANS as u8)),
    ("spec_tint", Slot::Table(T_SPEC_TINT as u8)),
    ("sheen", Slot::Table(T_SHEEN as u8)),
    ("sheen_tint", Slot::Table(T_SHEEN_TINT as u8)),
    ("flatness", Slot::Table(T_FLATNESS as u8)),
    ("diff_trans", Slot::Table(T_DIFF_TRANS as u8)),
    ("eta", Slot::Table(T_ETA as u8)),
];

pub const MITSUBA: Plugin = Plugin::new(
    PluginDoc::new(
        Family::Bsdf,
        Dialect::Mitsuba,
        "principled",
        "Disney's principled BSDF (Burley 2012/2015) as Mitsuba 3's: diffuse, sheen, GGX reflection and transmission, clearcoat.",
        &[
            BASE_COLOR,
            ROUGHNESS,
            ANISOTROPIC,
            p("metallic", "float or texture", "0", "metallicness"),
            SPEC_TRANS,
            p("eta", "float", "from specular", "relative index of refraction, instead of specular"),
            p("specular", "float", "0.5", "Schlick F0 / 0.08, instead of eta"),
            SPEC_TINT,
            SHEEN,
            SHEEN_TINT,
            FLATNESS,
            p("clearcoat", "float or texture", "0", "weight of the clearcoat lobe"),
            p("clearcoat_gloss", "float or texture", "0", "glossiness of the clearcoat"),
            p("main_specular_sampling_rate", "float", "1", "sampling rate of the main specular lobes"),
            p("clearcoat_sampling_rate", "float", "1", "sampling rate of the clearcoat"),
            p("diffuse_reflectance_sampling_rate", "float", "1", "sampling rate of the diffuse lobe"),
        ],
    ),
    mitsuba,
)
.textures(TEXTURES)
.warptest(WarpTest {
    kind: KIND,
    params: &["alpha", "alpha-u", "alpha-v", "eta"],
    make: warptest,
});

pub const MITSUBA_THIN: Plugin = Plugin::new(
    PluginDoc::new(
        Family::Bsdf,
        Dialect::Mitsuba,
        "principledthin",
        "Mitsuba 3's thin principled BSDF: a two-sided sheet with diffuse and specular reflection and transmission.",
        &[
            BASE_COLOR,
            ROUGHNESS,
            ANISOTROPIC,
            SPEC_TRANS,
            p("eta", "float or texture", "1.5", "relative index of refraction of the sheet"),
            SPEC_TINT,
            SHEEN,
            SHEEN_TINT,
            FLATNESS,
            p("diff_trans", "float or texture", "0", "diffuse transmission, 0 to 2"),
            p("specular_reflectance_sampling_rate", "float", "1", "sampling rate of specular reflection"),
            p("specular_transmittance_sampling_rate", "float", "1", "sampling rate of specular transmission"),
            p("diffuse_reflectance_sampling_rate", "float", "1", "sampling rate of diffuse reflection"),
            p("diffuse_transmittance_sampling_rate", "float", "1", "sampling rate of diffuse transmission"),
        ],
    ),
    mitsuba_thin,
)
.textures(TEXTURES_THIN)
.warptest(WarpTest {
    kind: KIND_THIN,
    params: &["alpha", "alpha-u", "alpha-v", "eta"],
    make: warptest_thin,
});

/// Mitsuba's `get_flag`: given, and not the number 0.
fn given(props: &Properties, key: &str) -> Result<bool, Error> {
    Ok(props.has(key) && props.float(key, 0.0)? != 0.0)
}

/// The parameters both models read.
fn common(props: &Properties, thin: bool) -> Result<Principled, Error> {
    let d = Principled::default();
    let unit = |key: &str, default: f32| -> Result<f32, Error> {
        let v = props.float(key, default)?;
        if !v.is_finite() {
            return Err(props.error(key, format!("'{key}' must be finite, found {v}")));
        }
        Ok(v)
    };
    Ok(Principled {
        thin,
        base_color: props.color("base_color", d.base_color)?,
        roughness: unit("roughness", d.roughness)?,
        anisotropic: unit("anisotropic", 0.0)?,
        spec_trans: unit("spec_trans", 0.0)?,
        spec_tint: unit("spec_tint", 0.0)?,
        sheen: unit("sheen", 0.0)?,
        sheen_tint: unit("sheen_tint", 0.0)?,
        flatness: unit("flatness", 0.0)?,
        has: if given(props, "spec_trans")? {
            HAS_SPEC_TRANS
        } else {
            0
        },
        ..d
    })
}

fn mitsuba(props: &Properties) -> Result<Bsdf, Error> {
    let mut b = common(props, false)?;
    b.metallic = props.float("metallic", 0.0)?;
    b.clearcoat = props.float("clearcoat", 0.0)?;
    b.clearcoat_gloss = props.float("clearcoat_gloss", 0.0)?;
    b.rates = [
        props.float("main_specular_sampling_rate", 1.0)?,
        props.float("clearcoat_sampling_rate", 1.0)?,
        props.float("diffuse_reflectance_sampling_rate", 1.0)?,
        1.0,
    ];
    let has_spec_trans = b.has & HAS_SPEC_TRANS != 0;
    b.eta = if props.has("eta") {
        if props.has("specular") {
            return Err(props.error("specular", "give either 'eta' or 'specular', not both"));
        }
        let eta = props.float("eta", 1.5)?;
        if !(eta > 0.0 && eta.is_finite()) {
            return Err(props.error("eta", format!("'eta' must be positive, found {eta}")));
        }
        // As Mitsuba: η = 1 is no interface for transmission.
        if has_spec_trans && eta == 1.0 {
            1.001
        } else {
            eta
        }
    } else {
        let mut specular = props.float("specular", 0.5)?;
        if !(0.0..12.5).contains(&specular) {
            return Err(props.error(
                "specular",
                format!("'specular' must be in [0, 12.5), found {specular}"),
            ));
        }
        if has_spec_trans && specular == 0.0 {
            specular = 1e-3;
        }
        specular_to_eta(specular)
    };
    Ok(Bsdf::Principled(b))
}

fn mitsuba_thin(props: &Properties) -> Result<Bsdf, Error> {
    for key in ["metallic", "clearcoat", "clearcoat_gloss", "specular"] {
        if props.has(key) {
            return Err(props.error(
                key,
                format!("principledthin has no '{key}' (Mitsuba's thin model lacks it)"),
            ));
        }
    }
    let mut b = common(props, true)?;
    b.diff_trans = props.float("diff_trans", 0.0)?;
    if given(props, "diff_trans")? {
        b.has |= HAS_DIFF_TRANS;
    }
    b.eta = props.float("eta", 1.5)?;
    if !(b.eta > 0.0 && b.eta.is_finite()) {
        return Err(props.error("eta", format!("'eta' must be positive, found {}", b.eta)));
    }
    b.rates = [
        props.float("specular_reflectance_sampling_rate", 1.0)?,
        props.float("specular_transmittance_sampling_rate", 1.0)?,
        props.float("diffuse_reflectance_sampling_rate", 1.0)?,
        props.float("diffuse_transmittance_sampling_rate", 1.0)?,
    ];
    Ok(Bsdf::Principled(b))
}

/// warptest: roughness √α (α_u, α_v through `anisotropic`), every lobe on.
fn warptest_params(p: &TestParams, thin: bool) -> Principled {
    let (a, b) = (p.alpha_u.max(p.alpha_v), p.alpha_u.min(p.alpha_v));
    // α_x / α_y = 1 / aspect² with aspect = sqrt(1 - 0.9 anisotropic).
    let aspect = (b / a).sqrt();
    Principled {
        thin,
        base_color: Vec3::new(0.8, 0.5, 0.3),
        roughness: (a * b).sqrt().sqrt(),
        anisotropic: ((1.0 - aspect * aspect) / 0.9).clamp(0.0, 1.0),
        metallic: if thin { 0.0 } else { 0.2 },
        spec_trans: 0.4,
        spec_tint: 0.3,
        sheen: 0.5,
        sheen_tint: 0.5,
        flatness: 0.3,
        clearcoat: if thin { 0.0 } else { 0.7 },
        clearcoat_gloss: 0.5,
        diff_trans: if thin { 0.6 } else { 0.0 },
        eta: p.eta,
        rates: [1.0; 4],
        has: HAS_SPEC_TRANS | if thin { HAS_DIFF_TRANS } else { 0 },
    }
}

fn warptest(p: &TestParams) -> Bsdf {
    Bsdf::Principled(warptest_params(p, false))
}

fn warptest_thin(p: &TestParams) -> Bsdf {
    Bsdf::Principled(warptest_params(p, true))
}

/// Writes entry `i` of the record's table.
pub fn set_table(r: &mut BsdfRecord, i: usize, v: f32) {
    r.table[i / 4][i % 4] = v.to_bits();
}

/// Entry `i` of the record's table.
pub fn table(r: &BsdfRecord, i: usize) -> f32 {
    f32::from_bits(r.table[i / 4][i % 4])
}

/// Makes table entry `entry` of `r` (a principled record) read texture `index`.
pub fn pack_table_texture(r: &mut BsdfRecord, entry: usize, index: u32) {
    set_table(r, T_TEXTURES + entry, f32::from_bits(index + 1));
    let mask = table(r, T_TEXTURED).to_bits() | 1 << entry;
    set_table(r, T_TEXTURED, f32::from_bits(mask));
    r.flags |= BSDF_TABLE_TEXTURES;
}

/// The texture-mask bits a scene with these records needs for table textures
/// ([`TEXTURE_FEATURE_TABLE`], with [`TEXTURE_FEATURE_BSDF`] that guards every BSDF lookup).
pub fn texture_feature(records: &[BsdfRecord]) -> u32 {
    if records.iter().any(|r| r.flags & BSDF_TABLE_TEXTURES != 0) {
        TEXTURE_FEATURE_TABLE | TEXTURE_FEATURE_BSDF
    } else {
        0
    }
}

impl BsdfModel for Principled {
    fn kind(&self) -> &'static Kind {
        if self.thin {
            KIND_THIN
        } else {
            KIND
        }
    }

    fn pack(&self, r: &mut BsdfRecord) {
        r.reflectance = self.base_color.into();
        r.eta = self.eta;
        let entries = [
            (T_ROUGHNESS, self.roughness),
            (T_ANISOTROPIC, self.anisotropic),
            (T_METALLIC, self.metallic),
            (T_SPEC_TRANS, self.spec_trans),
            (T_SPEC_TINT, self.spec_tint),
            (T_SHEEN, self.sheen),
            (T_SHEEN_TINT, self.sheen_tint),
            (T_FLATNESS, self.flatness),
            (T_CLEARCOAT, self.clearcoat),
            (T_CLEARCOAT_GLOSS, self.clearcoat_gloss),
            (T_DIFF_TRANS, self.diff_trans),
            (T_ETA, self.eta),
        ];
        for (i, v) in entries {
            set_table(r, i, v);
        }
        for (k, rate) in self.rates.iter().enumerate() {
            set_table(r, T_RATES + k, *rate);
        }
        set_table(r, T_HAS, f32::from_bits(self.has));
    }

    /// Mitsuba's lobes: transmission only where `spec_trans` (or principledthin's
    /// `diff_trans`) was given, so `twosided` takes the others as Mitsuba's does.
    fn transmits(&self) -> bool {
        self.has & (HAS_SPEC_TRANS | HAS_DIFF_TRANS) != 0
    }

    fn lobe_axis(&self) -> LobeAxis {
        if self.roughness < 0.3 {
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
        let body = r#"<bsdf type="principled" id="a"/>
<bsdf type="principled" id="b"><rgb name="base_color" value="0.2, 0.8, 0.1"/><float name="roughness" value="0.15"/><float name="metallic" value="0.3"/><float name="spec_trans" value="0.2"/><float name="eta" value="1.33"/><float name="clearcoat" value="0.5"/><float name="clearcoat_gloss" value="0.9"/><float name="main_specular_sampling_rate" value="2"/></bsdf>
<bsdf type="principledthin" id="c"><float name="diff_trans" value="1.4"/><float name="eta" value="1.2"/></bsdf>
<bsdf type="principled" id="d"><texture type="checkerboard" name="metallic"/><float name="specular" value="0.7"/></bsdf>"#;
        let s = load(&[("s.xml", &mitsuba(body))], &[]).expect("scene");
        assert_eq!(s.bsdfs[0], Bsdf::Principled(Principled::default()));
        assert!((Principled::default().eta - 1.5).abs() < 1e-6);
        let Bsdf::Principled(b) = s.bsdfs[1] else {
            panic!("{:?}", s.bsdfs[1])
        };
        assert_eq!(
            (b.base_color, b.roughness, b.metallic, b.spec_trans, b.eta),
            (Vec3::new(0.2, 0.8, 0.1), 0.15, 0.3, 0.2, 1.33)
        );
        assert_eq!(
            (b.clearcoat, b.clearcoat_gloss, b.rates[0], b.has),
            (0.5, 0.9, 2.0, HAS_SPEC_TRANS)
        );
        let Bsdf::Principled(c) = s.bsdfs[2] else {
            panic!("{:?}", s.bsdfs[2])
        };
        assert!(c.thin && c.diff_trans == 1.4 && c.eta == 1.2 && c.has == HAS_DIFF_TRANS);
        assert_eq!(BsdfRecord::from(&s.bsdfs[2]).kind, KIND_THIN.id);
        // A textured parameter: its table entry reads texture 0 (id 1).
        let r = BsdfRecord::from(&s.bsdfs[3]);
        assert_eq!(r.kind, KIND.id);
        assert_eq!(r.flags & BSDF_TABLE_TEXTURES, BSDF_TABLE_TEXTURES);
        assert_eq!(table(&r, T_TEXTURES + T_METALLIC).to_bits(), 1);
        assert_eq!(table(&r, T_TEXTURED).to_bits(), 1 << T_METALLIC);
        assert!((r.eta - specular_to_eta(0.7)).abs() < 1e-6);
    }

    #[test]
    fn errors_name_the_parameter() {
        let cases: &[(&str, u32, &str)] = &[
            ("<bsdf type=\"principled\"><float name=\"eta\" value=\"1.3\"/>\n<float name=\"specular\" value=\"0.5\"/></bsdf>", 4, "either 'eta' or 'specular'"),
            ("<bsdf type=\"principled\">\n<float name=\"eta\" value=\"-1\"/></bsdf>", 4, "'eta' must be positive"),
            ("<bsdf type=\"principledthin\">\n<float name=\"metallic\" value=\"0.5\"/></bsdf>", 4, "principledthin has no 'metallic'"),
            ("<bsdf type=\"principled\">\n<texture type=\"checkerboard\" name=\"specular\"/></bsdf>", 4, "cannot be a texture"),
        ];
        for (body, line, msg) in cases {
            let e = error_at(load(&[("s.xml", &mitsuba(body))], &[]), "s.xml", *line);
            assert!(e.contains(msg), "{e}\n  wanted: {msg}");
        }
    }
}
