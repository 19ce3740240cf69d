//! Surface scattering models: the BSDF family, one file per plugin type (as Mitsuba
//! 3's `src/bsdfs/`), and [`PLUGINS`], the one list of every BSDF type of both
//! dialects from which the parsers' dispatch and errors, `wavetrace warptest`'s BSDF
//! targets and `docs/plugins.md` ([`REGISTRY`]) are derived.
//!
//! A plugin's file is its manual (parameters, defaults, a scene snippet, citations)
//! and holds everything the host knows of it: its [`PluginDoc`]s, its readers for
//! both dialects (through the one property reader, [`Properties`]), its checks, the
//! parameters that may be textures, and its GPU record packing ([`BsdfModel`]). Its
//! GPU side is `shaders/bsdf/<name>.glsl`, dispatched by GLSL that `build.rs`
//! generates from [`kinds::KINDS`]. `docs/adding-a-bsdf.md` walks through adding one.
//!
//! | file | Mitsuba 3 | Nori |
//! |------|-----------|------|
//! | [`diffuse`] | `diffuse` | `diffuse` |
//! | [`conductor`] | `conductor` | `mirror` |
//! | [`roughconductor`] | `roughconductor` | |
//! | [`dielectric`] | `dielectric` | `dielectric` |
//! | [`thindielectric`] | `thindielectric` | |
//! | [`roughdielectric`] | `roughdielectric` | |
//! | [`plastic`] | `plastic` | |
//! | [`roughplastic`] | `roughplastic` | |
//! | [`pplastic`] | `pplastic` | |
//! | [`principled`] | `principled`, `principledthin` | |
//! | [`nori_microfacet`] | | `microfacet` |
//! | [`measured`] | `measured` | |
//! | [`twosided`], [`normalmap`], [`null`] | wrappers the loader reads (they nest BSDFs or none) | |
//! | [`mask`], [`blendbsdf`], [`bumpmap`] | composites the loader reads, resolved per hit ([`composite`]) | |
//!
//! Shared helpers by topic: [`ior`] (named indices of refraction), [`microfacet`]
//! (`distribution` / `alpha` and reference integrals), [`fresnel`] (reference
//! Fresnel terms).

pub mod blendbsdf;
pub mod bumpmap;
pub mod composite;
pub mod conductor;
#[rustfmt::skip]
mod conductor_presets;
pub mod dielectric;
pub mod diffuse;
pub mod fresnel;
pub mod hair;
pub mod ior;
pub mod kinds;
pub mod mask;
pub mod measured;
pub mod microfacet;
pub mod nori_microfacet;
pub mod normalmap;
pub mod null;
pub mod plastic;
pub mod pplastic;
pub mod principled;
mod rough_coating;
pub mod roughconductor;
pub mod roughdielectric;
pub mod roughplastic;
pub mod thindielectric;
pub mod twosided;

use glam::Vec3;

use super::plugin::{self, Family, PluginDoc, Support};
use super::properties::Properties;
use super::xml::{Dialect, Element};
use super::Error;
use crate::gpu::layout::BsdfRecord;

pub use conductor::Conductor;
pub use dielectric::Dielectric;
pub use diffuse::Diffuse;
pub use fresnel::{
    diffuse_fresnel, fresnel_dielectric, fresnel_diffuse_reflectance_fit,
    thin_dielectric_reflectance,
};
pub use hair::Hair;
pub use ior::{ior_preset, CONDUCTOR_PRESETS, IOR_PRESETS};
pub use kinds::Kind;
pub use measured::Measured;
pub use microfacet::{rough_reflectance, Distribution};
pub use nori_microfacet::NoriMicrofacet;
pub use plastic::Plastic;
pub use pplastic::PPlastic;
pub use principled::Principled;
pub use roughconductor::RoughConductor;
pub use roughdielectric::RoughDielectric;
pub use roughplastic::{rough_coating_tables, RoughPlastic};
pub use thindielectric::ThinDielectric;

/// Every BSDF type of both dialects: Mitsuba 3's 23 (the `add_plugin` lines of its
/// `src/bsdfs/CMakeLists.txt`, August 2026), supported or not yet, then Nori's. A new
/// plugin adds its entries here.
pub const PLUGINS: &[Plugin] = &[
    diffuse::MITSUBA,
    conductor::MITSUBA,
    roughconductor::MITSUBA,
    dielectric::MITSUBA,
    thindielectric::MITSUBA,
    roughdielectric::MITSUBA,
    plastic::MITSUBA,
    roughplastic::MITSUBA,
    pplastic::MITSUBA,
    twosided::MITSUBA,
    normalmap::MITSUBA,
    null::MITSUBA,
    blendbsdf::MITSUBA,
    bumpmap::MITSUBA,
    Plugin::not_yet("circular"),
    hair::MITSUBA,
    mask::MITSUBA,
    measured::MITSUBA,
    Plugin::not_yet("measured_polarized"),
    Plugin::not_yet("polarizer"),
    principled::MITSUBA,
    principled::MITSUBA_THIN,
    Plugin::not_yet("retarder"),
    diffuse::NORI,
    conductor::NORI_MIRROR,
    dielectric::NORI,
    nori_microfacet::NORI,
];

/// The catalogue entries of [`PLUGINS`] (`scene::plugin`'s registry of the family).
pub const REGISTRY: &[PluginDoc] = &registry_docs::<{ PLUGINS.len() }>();

const fn registry_docs<const N: usize>() -> [PluginDoc; N] {
    let mut docs = [PLUGINS[0].doc; N];
    let mut i = 0;
    while i < N {
        docs[i] = PLUGINS[i].doc;
        i += 1;
    }
    docs
}

/// One BSDF type of one dialect: its catalogue entry and how it is read.
#[derive(Debug, Clone, Copy)]
pub struct Plugin {
    pub doc: PluginDoc,
    pub read: Read,
    /// The parameters that may be textures, and the record slots they feed (as
    /// Mitsuba's plugins, which read these with `props.texture`).
    pub textures: &'static [(&'static str, Slot)],
    /// Its `wavetrace warptest` target, if it has one.
    pub warptest: Option<WarpTest>,
}

/// How a BSDF type is read.
#[derive(Debug, Clone, Copy)]
pub enum Read {
    /// From its parameters alone (textures attached by the loader).
    Props(fn(&Properties) -> Result<Bsdf, Error>),
    /// By the Mitsuba loader, which resolves what it nests (`twosided`, `normalmap`,
    /// `null`; see their files).
    Loader,
    /// Not supported yet.
    NotYet,
}

impl Plugin {
    /// A supported type read from its parameters.
    pub const fn new(doc: PluginDoc, read: fn(&Properties) -> Result<Bsdf, Error>) -> Plugin {
        Plugin {
            doc,
            read: Read::Props(read),
            textures: &[],
            warptest: None,
        }
    }

    /// With the parameters that may be textures.
    pub const fn textures(self, textures: &'static [(&'static str, Slot)]) -> Plugin {
        Plugin { textures, ..self }
    }

    /// With a `wavetrace warptest` target.
    pub const fn warptest(self, warptest: WarpTest) -> Plugin {
        Plugin {
            warptest: Some(warptest),
            ..self
        }
    }

    /// A type the Mitsuba loader reads itself: it nests BSDFs, or stands for none.
    pub const fn loader(doc: PluginDoc) -> Plugin {
        Plugin {
            doc,
            read: Read::Loader,
            textures: &[],
            warptest: None,
        }
    }

    /// A Mitsuba 3 type wavetrace lacks.
    pub const fn not_yet(name: &'static str) -> Plugin {
        Plugin {
            doc: PluginDoc::not_yet(Family::Bsdf, Dialect::Mitsuba, name),
            read: Read::NotYet,
            textures: &[],
            warptest: None,
        }
    }

    /// Reads a BSDF of this type from `props` (its nested textures already attached):
    /// the model, wrapped in [`Bsdf::Textured`] when some parameters are textures.
    /// `None` for a type the loader reads itself.
    pub fn read(&self, props: &Properties) -> Option<Result<Bsdf, Error>> {
        let Read::Props(read) = self.read else {
            return None;
        };
        Some(read(props).and_then(|bsdf| {
            Ok(match TextureMaps::from_props(self.textures, props)? {
                Some(maps) => Bsdf::Textured {
                    bsdf: Box::new(bsdf),
                    maps,
                },
                None => bsdf,
            })
        }))
    }
}

/// The supported BSDF type `t` of `dialect`.
pub fn plugin(dialect: Dialect, t: &str) -> Option<&'static Plugin> {
    PLUGINS
        .iter()
        .find(|p| p.doc.dialect == dialect && p.doc.name == t && p.doc.support == Support::Yes)
}

/// "bsdf type 'X' is not supported yet" or "unknown bsdf type 'X'". A Nori scene
/// naming a Mitsuba type wavetrace lacks hears "not supported yet" too.
pub fn unsupported(el: &Element, dialect: Dialect) -> Error {
    let t = el.attr("type").unwrap_or("");
    let not_yet = |p: &&Plugin| p.doc.name == t && p.doc.support == Support::NotYet;
    let dialect = if PLUGINS.iter().any(|p| not_yet(&p)) {
        Dialect::Mitsuba
    } else {
        dialect
    };
    plugin::unsupported(el, Family::Bsdf, dialect, REGISTRY)
}

/// What a BSDF model packs for the GPU: one per kind of [`kinds::KINDS`].
pub trait BsdfModel: std::fmt::Debug {
    /// Its GPU kind.
    fn kind(&self) -> &'static Kind;

    /// Writes its parameters into `r`, whose `kind` is set and whose other fields hold
    /// the defaults of [`BsdfRecord::from`].
    fn pack(&self, r: &mut BsdfRecord);

    /// For `wavetrace warptest`: the direction its lobe gathers around.
    fn lobe_axis(&self) -> LobeAxis {
        LobeAxis::Normal
    }

    /// Whether light can pass through: its kind has a transmission lobe (a model
    /// whose records differ, as `principled`, says so itself).
    fn transmits(&self) -> bool {
        self.kind().lobes & kinds::lobes::TRANSMISSION != 0
    }
}

/// Where a lobe gathers, for the axis of `wavetrace warptest`'s plots.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LobeAxis {
    /// Around the normal (diffuse, or rough).
    Normal,
    /// Around the mirror direction (smooth reflection).
    Reflect,
    /// Around the refracted direction, relative index η (smooth refraction).
    Refract(f32),
}

/// A BSDF. Every shape has one (diffuse 0.5 when the scene names none). The models'
/// parameters and manuals are in their files; `TwoSided`, `Textured` and `NormalMap`
/// wrap a model.
#[derive(Clone, PartialEq)]
pub enum Bsdf {
    Diffuse(Diffuse),
    Conductor(Conductor),
    RoughConductor(RoughConductor),
    Dielectric(Dielectric),
    ThinDielectric(ThinDielectric),
    RoughDielectric(RoughDielectric),
    Plastic(Plastic),
    RoughPlastic(RoughPlastic),
    PPlastic(PPlastic),
    /// `principled` and `principledthin` ([`principled`]).
    Principled(Principled),
    /// Mitsuba `hair` ([`hair`]).
    Hair(Hair),
    NoriMicrofacet(NoriMicrofacet),
    /// Mitsuba `measured`: an RGL `.bsdf` file ([`measured`]).
    Measured(Measured),
    /// Mitsuba `twosided` with one nested BSDF without transmission: both faces use
    /// it ([`twosided`]).
    TwoSided(Box<Bsdf>),
    /// A model whose parameters are partly textures: `maps` says which texture feeds
    /// which parameter; the model's own values are the textures' means (used where a
    /// single number is needed, e.g. the plastics' lobe sampling weights). Any
    /// parameter listed in its plugin's [`Plugin::textures`] may be a nested
    /// `<texture name=...>` or a `<ref name=... id=.../>` to one.
    /// `<bsdf type="diffuse"><texture type="checkerboard" name="reflectance"/></bsdf>`
    Textured {
        bsdf: Box<Bsdf>,
        maps: TextureMaps,
    },
    /// Mitsuba `normalmap`: the nested model shaded with the normal read from the
    /// texture `normal_map` ([`normalmap`]).
    NormalMap {
        bsdf: Box<Bsdf>,
        normal_map: u32,
        flip_invalid_normals: bool,
        use_shadowing_function: bool,
    },
    /// Mitsuba `blendbsdf`: (1 − weight) `bsdfs[0]` + weight `bsdfs[1]` ([`blendbsdf`]).
    Blend {
        weight: composite::Weight,
        bsdfs: Box<[Bsdf; 2]>,
    },
    /// Mitsuba `mask`: opacity · `bsdf` + (1 − opacity) · a pass-through ([`mask`]).
    Mask {
        opacity: composite::Weight,
        bsdf: Box<Bsdf>,
    },
    /// Mitsuba `twosided` with two BSDFs: the front's and the back's ([`twosided`]).
    TwoSidedPair(Box<[Bsdf; 2]>),
    /// Mitsuba `bumpmap`: `bsdf` shaded in the frame of a height field ([`bumpmap`]).
    BumpMap {
        params: bumpmap::BumpParams,
        bsdf: Box<Bsdf>,
    },
}

impl Bsdf {
    /// The model, under any wrappers.
    pub fn model(&self) -> &dyn BsdfModel {
        match self {
            Bsdf::Diffuse(m) => m,
            Bsdf::Conductor(m) => m,
            Bsdf::RoughConductor(m) => m,
            Bsdf::Dielectric(m) => m,
            Bsdf::ThinDielectric(m) => m,
            Bsdf::RoughDielectric(m) => m,
            Bsdf::Plastic(m) => m,
            Bsdf::RoughPlastic(m) => m,
            Bsdf::PPlastic(m) => m,
            Bsdf::Principled(m) => m,
            Bsdf::Hair(m) => m,
            Bsdf::NoriMicrofacet(m) => m,
            Bsdf::Measured(m) => m,
            Bsdf::TwoSided(inner) => inner.model(),
            Bsdf::Textured { bsdf, .. } | Bsdf::NormalMap { bsdf, .. } => bsdf.model(),
            // A composite's first model (what one model stands for it).
            Bsdf::Mask { bsdf, .. } | Bsdf::BumpMap { bsdf, .. } => bsdf.model(),
            Bsdf::Blend { bsdfs, .. } | Bsdf::TwoSidedPair(bsdfs) => bsdfs[0].model(),
        }
    }

    /// Whether light can pass through (dielectrics, and a mask's pass-through, which
    /// Mitsuba counts as transmission).
    pub fn transmits(&self) -> bool {
        match self {
            Bsdf::Mask { .. } => true,
            Bsdf::Blend { .. } | Bsdf::TwoSidedPair(..) | Bsdf::BumpMap { .. } => {
                composite::children(self).iter().any(|b| b.transmits())
            }
            _ => self.model().transmits(),
        }
    }

    /// Whether this is a thin dielectric (crossed as a null surface by the
    /// volumetric path tracers).
    pub fn is_thin_dielectric(&self) -> bool {
        matches!(self, Bsdf::ThinDielectric(_))
    }
}

/// A model prints as its struct (`Diffuse { reflectance: .. }`), as the variants
/// printed before they wrapped one (`wavetrace warptest` shows it).
impl std::fmt::Debug for Bsdf {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Bsdf::TwoSided(inner) => f.debug_tuple("TwoSided").field(inner).finish(),
            Bsdf::Textured { bsdf, maps } => f
                .debug_struct("Textured")
                .field("bsdf", bsdf)
                .field("maps", maps)
                .finish(),
            Bsdf::NormalMap {
                bsdf,
                normal_map,
                flip_invalid_normals,
                use_shadowing_function,
            } => f
                .debug_struct("NormalMap")
                .field("bsdf", bsdf)
                .field("normal_map", normal_map)
                .field("flip_invalid_normals", flip_invalid_normals)
                .field("use_shadowing_function", use_shadowing_function)
                .finish(),
            Bsdf::Blend { weight, bsdfs } => f
                .debug_struct("Blend")
                .field("weight", weight)
                .field("bsdfs", bsdfs)
                .finish(),
            Bsdf::Mask { opacity, bsdf } => f
                .debug_struct("Mask")
                .field("opacity", opacity)
                .field("bsdf", bsdf)
                .finish(),
            Bsdf::TwoSidedPair(pair) => f.debug_tuple("TwoSidedPair").field(pair).finish(),
            Bsdf::BumpMap { params, bsdf } => f
                .debug_struct("BumpMap")
                .field("params", params)
                .field("bsdf", bsdf)
                .finish(),
            model => model.model().fmt(f),
        }
    }
}

impl Default for Bsdf {
    fn default() -> Self {
        Bsdf::Diffuse(Diffuse {
            reflectance: Vec3::splat(0.5),
        })
    }
}

/// The one record of a BSDF; for a composite, that of its first model (the scene's
/// records, nodes and all, are [`composite::records`]).
impl From<&Bsdf> for BsdfRecord {
    fn from(bsdf: &Bsdf) -> BsdfRecord {
        match bsdf {
            Bsdf::Mask { bsdf, .. } | Bsdf::BumpMap { bsdf, .. } => BsdfRecord::from(&**bsdf),
            Bsdf::Blend { bsdfs, .. } | Bsdf::TwoSidedPair(bsdfs) => BsdfRecord::from(&bsdfs[0]),
            Bsdf::TwoSided(inner) => twosided::pack(inner),
            Bsdf::Textured { bsdf, maps } => maps.pack(bsdf),
            Bsdf::NormalMap {
                bsdf,
                normal_map,
                flip_invalid_normals,
                use_shadowing_function,
            } => normalmap::pack(
                bsdf,
                *normal_map,
                *flip_invalid_normals,
                *use_shadowing_function,
            ),
            model => {
                let model = model.model();
                let mut r = BsdfRecord {
                    kind: model.kind().id,
                    specular: [1.0; 3],
                    transmittance: [1.0; 3],
                    eta: 1.0,
                    alpha_u: 1.0,
                    alpha_v: 1.0,
                    ..Default::default()
                };
                model.pack(&mut r);
                r
            }
        }
    }
}

/// Textures feeding parameters of a BSDF record (texture indices).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct TextureMaps {
    pub reflectance: Option<u32>,
    pub specular: Option<u32>,
    pub transmittance: Option<u32>,
    pub alpha_u: Option<u32>,
    pub alpha_v: Option<u32>,
    pub cond_eta: Option<u32>,
    pub cond_k: Option<u32>,
    pub eta: Option<u32>,
    /// Scalar parameters kept in the record's table ([`Slot::Table`]): (entry, texture).
    pub table: Vec<(u8, u32)>,
}

/// A parameter slot of the BSDF record a texture can feed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Slot {
    Reflectance,
    Specular,
    Transmittance,
    AlphaU,
    AlphaV,
    /// `alpha`: both roughnesses.
    Alpha,
    /// A conductor's `eta` and `k` (colors).
    CondEta,
    CondK,
    /// `eta`, read as Mitsuba's `eval_1` reads a texture (pplastic's).
    Eta,
    /// Entry k of the record's table, the texture's luminance (`principled`'s scalars;
    /// looked up where the scene's texture mask has `TEXTURE_FEATURE_TABLE`).
    Table(u8),
}

impl TextureMaps {
    /// The maps of a BSDF whose parameters `slots` may be textures, from the texture
    /// parameters of `props`; a texture given for a parameter that cannot take one is
    /// an error.
    pub fn from_props(
        slots: &[(&'static str, Slot)],
        props: &Properties,
    ) -> Result<Option<TextureMaps>, Error> {
        let given = props.textures();
        if given.is_empty() {
            return Ok(None);
        }
        let mut maps = TextureMaps::default();
        for (name, index) in given {
            let Some((_, slot)) = slots.iter().find(|(n, _)| *n == name) else {
                let ok: Vec<&str> = slots.iter().map(|s| s.0).collect();
                return Err(props.error(
                    &name,
                    format!(
                        "parameter '{name}' of {} cannot be a texture (textures: {})",
                        props.object(),
                        if ok.is_empty() {
                            "none".into()
                        } else {
                            ok.join(", ")
                        }
                    ),
                ));
            };
            match slot {
                Slot::Reflectance => maps.reflectance = Some(index),
                Slot::Specular => maps.specular = Some(index),
                Slot::Transmittance => maps.transmittance = Some(index),
                Slot::AlphaU => maps.alpha_u = Some(index),
                Slot::AlphaV => maps.alpha_v = Some(index),
                Slot::Alpha => {
                    maps.alpha_u = Some(index);
                    maps.alpha_v = Some(index);
                }
                Slot::CondEta => maps.cond_eta = Some(index),
                Slot::CondK => maps.cond_k = Some(index),
                Slot::Eta => maps.eta = Some(index),
                Slot::Table(k) => maps.table.push((*k, index)),
            }
        }
        Ok(Some(maps))
    }

    /// The record of `bsdf` with these textures (ids + 1, 0: none).
    fn pack(&self, bsdf: &Bsdf) -> BsdfRecord {
        let mut r = BsdfRecord::from(bsdf);
        let id = |t: Option<u32>| t.map_or(0, |i| i + 1);
        r.tex_reflectance = id(self.reflectance);
        r.tex_specular = id(self.specular);
        r.tex_transmittance = id(self.transmittance);
        r.tex_alpha_u = id(self.alpha_u);
        r.tex_alpha_v = id(self.alpha_v);
        r.tex_cond_eta = id(self.cond_eta);
        r.tex_cond_k = id(self.cond_k);
        r.tex_eta = id(self.eta);
        for &(k, index) in &self.table {
            principled::pack_table_texture(&mut r, k as usize, index);
        }
        r
    }
}

/// A `wavetrace warptest` target of a model: the knobs it takes and the BSDF they
/// make. Its name is its kind's ([`Kind::name`]).
#[derive(Debug, Clone, Copy)]
pub struct WarpTest {
    pub kind: &'static Kind,
    /// The options it takes besides `theta` and `phi`: `alpha`, `alpha-u` and
    /// `alpha-v` (anisotropic), `distribution`, `eta`.
    pub params: &'static [&'static str],
    pub make: fn(&TestParams) -> Bsdf,
}

/// The knobs of a warptest target, checked by `warptest::target` (roughness
/// positive, η positive and not 1) and defaulted there (α 0.2, GGX, η 1.5).
#[derive(Debug, Clone, Copy)]
pub struct TestParams {
    pub alpha_u: f32,
    pub alpha_v: f32,
    pub distribution: Distribution,
    pub eta: f32,
}

/// Every warptest target of the family, in registry order.
pub fn warptests() -> impl Iterator<Item = &'static WarpTest> {
    PLUGINS.iter().filter_map(|p| p.warptest.as_ref())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_are_numbered_in_order_and_each_has_one_model() {
        for (i, k) in kinds::KINDS.iter().enumerate() {
            assert_eq!(k.id as usize, i, "{}", k.name);
        }
        assert!(
            kinds::KINDS.len() <= kinds::COMPOSITE as usize,
            "the BSDF_KINDS mask has 32 bits, the last for composites"
        );
    }

    #[test]
    fn each_kind_has_its_glsl_file_with_the_functions_the_dispatch_calls() {
        for k in kinds::KINDS {
            let path = format!(
                "{}/shaders/bsdf/{}.glsl",
                env!("CARGO_MANIFEST_DIR"),
                k.name
            );
            let src = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
            let mut functions = vec![format!("BsdfSample bsdf_{}_sample(", k.name)];
            if !k.is_delta() {
                functions.push(format!("vec3 bsdf_{}_eval(", k.name));
                functions.push(format!("float bsdf_{}_pdf(", k.name));
            }
            if k.hooks & kinds::hooks::LOBES != 0 {
                functions.push(format!("uint bsdf_{}_lobes(", k.name));
            }
            if k.hooks & kinds::hooks::TEXTURED != 0 {
                functions.push(format!("BsdfRecord bsdf_{}_textured(", k.name));
            }
            for f in functions {
                assert!(src.contains(&f), "{path} lacks {f}...)");
            }
        }
    }

    #[test]
    fn registry_lists_each_type_once() {
        for (i, a) in REGISTRY.iter().enumerate() {
            assert_eq!(a.family, Family::Bsdf);
            for b in &REGISTRY[i + 1..] {
                assert!(
                    a.name != b.name || a.dialect != b.dialect,
                    "{} twice",
                    a.name
                );
            }
        }
        for p in PLUGINS {
            assert_eq!(
                matches!(p.read, Read::NotYet),
                p.doc.support == Support::NotYet,
                "{}",
                p.doc.name
            );
        }
        // Each warptest target once, and the models `wavetrace warptest` has always had.
        let names: Vec<&str> = warptests().map(|w| w.kind.name).collect();
        for (i, name) in names.iter().enumerate() {
            assert!(!names[i + 1..].contains(name), "warptest {name} twice");
        }
        for name in [
            "diffuse",
            "roughconductor",
            "roughdielectric",
            "plastic",
            "roughplastic",
            "nori_microfacet",
        ] {
            assert!(names.contains(&name), "warptest {name} missing");
        }
    }

    #[test]
    fn twosided_packs_its_model_with_the_flag() {
        use crate::gpu::layout::BSDF_TWOSIDED;
        let r = BsdfRecord::from(&Bsdf::TwoSided(Box::default()));
        assert_eq!(
            (r.kind, r.flags, r.reflectance),
            (diffuse::KIND.id, BSDF_TWOSIDED, [0.5; 3])
        );
    }
}
