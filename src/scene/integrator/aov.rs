//! Mitsuba's `aov` integrator: Arbitrary Output Variables of the first surface each
//! camera ray meets (depth, position, normals, ...), written as named channels beside
//! the radiance of a nested integrator, as Mitsuba 3.9's `src/integrators/aov.cpp`
//! names and lays them out. `render --aov` adds the same channels to any render.
//!
//! Parameter `aovs` (string): comma-separated `<name>:<type>` pairs; each AOV becomes
//! the channels `<name>.<suffix>` of its type ([`AovKind::suffixes`]). A nested
//! `<integrator>` (at most one in wavetrace) is rendered: its image is the film's
//! R, G, B, and again `<its name>.R/G/B/A` (A: its alpha, Mitsuba's valid-ray mask);
//! an unnamed one is called `_arg_0`, as Mitsuba's parser calls it. Without one,
//! R, G, B are 0, as in Mitsuba.
//!
//! Every AOV is filtered by the film's reconstruction filter like the radiance (each
//! pixel Σ w v / Σ w over its samples). A ray that meets nothing gives 0 in every
//! channel (Mitsuba zeroes the invalid interaction).
//!
//! ```xml
//! <integrator type="aov">
//!     <string name="aovs" value="dd:depth,nn:sh_normal"/>
//!     <integrator type="path" name="my_image"/>
//! </integrator>
//! ```

use super::IntegratorSpec;
use crate::scene::plugin::{Family, Param as Doc, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::{Dialect, Element};
use crate::scene::Error;

pub const AOV: PluginDoc = PluginDoc::new(
    Family::Integrator,
    Dialect::Mitsuba,
    "aov",
    "First-hit AOVs (depth, position, uv, normals, albedo, indices) as named channels beside a nested integrator's radiance (Mitsuba's).",
    &[Doc::new(
        "aovs",
        "string",
        "",
        "`<name>:<type>` pairs, comma-separated; types: depth, position, uv, geo_normal, sh_normal, albedo, prim_index, shape_index, dp_du, dp_dv, duv_dx, duv_dy",
    )],
);

/// What one AOV records of the first surface a camera ray meets. The discriminant is
/// its code in the kernels (`AOV_*` of shaders/integrator/aov.glsl; 0 ends a list).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum AovKind {
    /// Distance along the camera ray (Mitsuba's `si.t`).
    Depth = 1,
    /// World-space position.
    Position = 2,
    /// Surface uv.
    Uv = 3,
    /// Geometric normal (Mitsuba's `si.n`).
    GeoNormal = 4,
    /// Shading normal (Mitsuba's `si.sh_frame.n`).
    ShNormal = 5,
    /// The BSDF's diffuse reflectance (Mitsuba's `eval_diffuse_reflectance`).
    Albedo = 6,
    /// The primitive's index within its shape (a triangle's in its mesh; 0 on a
    /// sphere, disk or cylinder), as Mitsuba's `si.prim_index`.
    PrimIndex = 7,
    /// The shape's index, from 1, in wavetrace's order of shapes (the scene's meshes,
    /// then its spheres, disks and cylinders), 0 where the ray meets nothing.
    /// Mitsuba writes an id of its own there (its JIT variants a registry number from
    /// 1, its scalar ones bits of a pointer), so only equal and unequal compare.
    ShapeIndex = 8,
    /// ∂p/∂u (Mitsuba's `si.dp_du`: a triangle's from its uvs, or its edge p1 - p0
    /// without them; a sphere's, disk's, cylinder's from their parameterization; 0 on
    /// curves and SDF grids, as Mitsuba leaves it).
    DpDu = 9,
    /// ∂p/∂v (Mitsuba's `si.dp_dv`, as `dp_du`).
    DpDv = 10,
    /// ∂uv/∂x, the uv change one pixel to the right (Mitsuba's
    /// `SurfaceInteraction::compute_uv_partials` of the camera's ray differentials,
    /// scaled by 1/√spp; 0 for sensors without differentials). Where the ray meets
    /// nothing Mitsuba writes NaN (0/0 on its zeroed interaction), wavetrace 0.
    DuvDx = 11,
    /// ∂uv/∂y, one pixel down (as `duv_dx`).
    DuvDy = 12,
}

/// The types `aovs` accepts, by Mitsuba's names.
const KINDS: &[(&str, AovKind)] = &[
    ("depth", AovKind::Depth),
    ("position", AovKind::Position),
    ("uv", AovKind::Uv),
    ("geo_normal", AovKind::GeoNormal),
    ("sh_normal", AovKind::ShNormal),
    ("albedo", AovKind::Albedo),
    ("prim_index", AovKind::PrimIndex),
    ("shape_index", AovKind::ShapeIndex),
    ("dp_du", AovKind::DpDu),
    ("dp_dv", AovKind::DpDv),
    ("duv_dx", AovKind::DuvDx),
    ("duv_dy", AovKind::DuvDy),
];

/// Most AOVs one render writes (the kernels' constants hold 4 bits each, 8 a word).
pub const MAX_AOVS: usize = 16;

impl AovKind {
    /// The channel suffixes, as Mitsuba names them.
    pub fn suffixes(self) -> &'static [&'static str] {
        match self {
            AovKind::Depth => &["T"],
            AovKind::Position
            | AovKind::GeoNormal
            | AovKind::ShNormal
            | AovKind::DpDu
            | AovKind::DpDv => &["X", "Y", "Z"],
            AovKind::Uv | AovKind::DuvDx | AovKind::DuvDy => &["U", "V"],
            AovKind::Albedo => &["R", "G", "B"],
            AovKind::PrimIndex | AovKind::ShapeIndex => &["I"],
        }
    }

    /// Mitsuba's name of the type.
    pub fn name(self) -> &'static str {
        KINDS
            .iter()
            .find(|(_, k)| *k == self)
            .map_or("", |(n, _)| n)
    }

    /// The type by Mitsuba's name.
    pub fn by_name(name: &str) -> Option<AovKind> {
        KINDS.iter().find(|(n, _)| *n == name).map(|&(_, k)| k)
    }
}

/// One AOV: its channels' prefix and what it records.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Aov {
    pub name: String,
    pub kind: AovKind,
}

impl Aov {
    /// Its channel names (`dd.T`, `nn.X`, ...).
    pub fn channels(&self) -> Vec<String> {
        self.kind
            .suffixes()
            .iter()
            .map(|s| format!("{}.{s}", self.name))
            .collect()
    }
}

/// The extra channels an integrator spec asks for (Mitsuba's `aov` and `moment`).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Outputs {
    /// The AOVs, in order.
    pub aovs: Vec<Aov>,
    /// An `aov` with a nested integrator: the prefix of that integrator's RGBA
    /// channels.
    pub inner_rgba: Option<String>,
    /// An `aov` without a nested integrator: R, G, B are 0 (only the AOVs are made).
    pub no_radiance: bool,
    /// A `moment`: the prefix of its nested integrator's channels (`<name>.X/Y/Z`, the
    /// mean in XYZ, and `m2_<name>.X/Y/Z`, the second moment).
    pub moment: Option<String>,
}

/// The AOVs of an `aovs` string, or why it is wrong (naming the entry). Entries are
/// separated by commas (and spaces, as Mitsuba's tokenizer separates them).
pub fn parse(aovs: &str) -> Result<Vec<Aov>, String> {
    let mut out: Vec<Aov> = Vec::new();
    for token in aovs.split([',', ' ']).filter(|t| !t.is_empty()) {
        let parts: Vec<&str> = token.split(':').collect();
        let (name, ty) = match parts.as_slice() {
            [name, ty] if !name.is_empty() && !ty.is_empty() => (*name, *ty),
            _ => {
                return Err(format!(
                    "aovs entry '{token}' is not a <name>:<type> pair (as in \"dd:depth,nn:sh_normal\")"
                ))
            }
        };
        let kind = match AovKind::by_name(ty) {
            Some(k) => k,
            None => {
                return Err(format!(
                    "aovs entry '{token}': unknown AOV type '{ty}' (one of {})",
                    KINDS.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
                ))
            }
        };
        if out.iter().any(|a| a.name == name) {
            return Err(format!(
                "aovs entry '{token}': the name '{name}' is used twice"
            ));
        }
        out.push(Aov {
            name: name.to_string(),
            kind,
        });
    }
    if out.len() > MAX_AOVS {
        return Err(format!(
            "{} AOVs requested; wavetrace writes at most {MAX_AOVS}",
            out.len()
        ));
    }
    Ok(out)
}

/// The AOVs of `render --aov`: as [`parse`], but an entry may be a type alone, named
/// after it (`depth` is `depth:depth`, channel `depth.T`).
pub fn parse_cli(aovs: &str) -> Result<Vec<Aov>, String> {
    let named: Vec<String> = aovs
        .split([',', ' '])
        .filter(|t| !t.is_empty())
        .map(|t| {
            if t.contains(':') {
                t.to_string()
            } else {
                format!("{t}:{t}")
            }
        })
        .collect();
    parse(&named.join(","))
}

/// `aovs` as [`parse`] reads them back: `name:type` entries, comma-separated.
pub fn list(aovs: &[Aov]) -> String {
    aovs.iter()
        .map(|a| format!("{}:{}", a.name, a.kind.name()))
        .collect::<Vec<_>>()
        .join(",")
}

/// The spec of an `aov` integrator: the nested integrator's (or `depth`, whose
/// radiance is dropped, where there is none) with the AOVs.
pub fn spec(
    el: &Element,
    props: &Properties,
    nested: &[&Element],
    dialect: Dialect,
) -> Result<IntegratorSpec, Error> {
    let aovs = props.string("aovs", "")?;
    let aovs = parse(&aovs).map_err(|m| props.error("aovs", format!("integrator 'aov': {m}")))?;
    props.finish()?;
    let mut spec = match nested {
        [] => IntegratorSpec {
            name: "depth".into(),
            line: Some(el.line),
            ..Default::default()
        },
        [inner] if inner.tag == "integrator" => {
            let mut spec = super::spec(inner, dialect)?;
            if spec.outputs != Outputs::default() {
                return Err(inner.err(
                    "an aov integrator's nested integrator must be a plain one (not aov or moment) in wavetrace",
                ));
            }
            spec.outputs.inner_rgba = Some(inner.attr("name").unwrap_or("_arg_0").to_string());
            spec
        }
        [inner] => {
            return Err(inner.err(format!(
                "<{}> inside an aov integrator: only <integrator> may be nested",
                inner.tag
            )))
        }
        [_, second, ..] => {
            return Err(second.err(
                "an aov integrator with more than one nested <integrator>: wavetrace renders one",
            ))
        }
    };
    spec.outputs.no_radiance = nested.is_empty();
    spec.outputs.aovs = aovs;
    Ok(spec)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_mitsuba_pairs_and_names_channels_as_mitsuba() {
        let aovs = parse("dd:depth, nn:sh_normal,aa:albedo,pp:prim_index,uv:uv").unwrap();
        let names: Vec<String> = aovs.iter().flat_map(Aov::channels).collect();
        assert_eq!(
            names,
            ["dd.T", "nn.X", "nn.Y", "nn.Z", "aa.R", "aa.G", "aa.B", "pp.I", "uv.U", "uv.V"]
        );
        assert!(parse("").unwrap().is_empty());
        assert_eq!(parse(&list(&aovs)).unwrap(), aovs);
        assert_eq!(
            parse_cli("depth,n:sh_normal").unwrap(),
            parse("depth:depth,n:sh_normal").unwrap()
        );
    }

    #[test]
    fn bad_entries_are_named() {
        let e = parse("dd:depth,nn").unwrap_err();
        assert!(e.contains("'nn'") && e.contains("<name>:<type>"), "{e}");
        let e = parse("dd:depth,xx:sheen").unwrap_err();
        assert!(e.contains("'xx:sheen'") && e.contains("'sheen'"), "{e}");
        let e = parse(":depth").unwrap_err();
        assert!(e.contains("':depth'"), "{e}");
        let e = parse("a:b:c").unwrap_err();
        assert!(e.contains("'a:b:c'"), "{e}");
        // Mitsuba 3.9.1 has no boundary_test AOV either.
        let e = parse("d:boundary_test").unwrap_err();
        assert!(e.contains("unknown AOV type 'boundary_test'"), "{e}");
        let e = parse("d:depth,d:uv").unwrap_err();
        assert!(e.contains("twice"), "{e}");
    }
}
