//! The sampler a scene asks for (`<sampler type=...>`): which pattern of random numbers
//! the kernels draw (shaders/sampler/), its parameters, and how it rounds a sample
//! count.
//!
//! Types, as in Mitsuba 3 (`sample_count` 4, `seed` 0 for all):
//! - `independent`: independent uniform numbers (a hash of pixel, sample, dimension
//!   and seed).
//! - `stratified` (`jitter` true): each dimension stratified, 2-D ones on an n x n grid;
//!   the count is rounded up to a square.
//! - `multijitter` (`jitter` true): correlated multi-jittered sampling (Kensler 2013);
//!   the count is rounded up to rows x columns, rows = floor(sqrt(count)).
//! - `orthogonal` (`jitter` true, `strength` 2): orthogonal-array sampling (Jarosz et
//!   al. 2019); the count is rounded up to the square of a prime.
//! - `ldsampler`: Mitsuba's low-discrepancy (0,2)-sequence sampler; the count is
//!   rounded up to a power of 4.
//!
//! and, as extra types in the Mitsuba dialect, pbrt-v4's
//! - `zsobol` (`randomization` = `fastowen` (default) | `owen` | `permutedigits` |
//!   `none`): Owen-scrambled Sobol' points in Morton order across pixels (Ahmed and
//!   Wonka 2020), blue-noise error; the count is rounded up to a power of 2 (pbrt-v4
//!   warns and renders the power of 2 below instead).
//!
//! Nori scenes may name any of them (`sampleCount`). The render's `--seed` is added to
//! the sampler's `seed`, as Mitsuba adds its render seed to the sampler's.
//!
//! ```xml
//! <sampler type="multijitter">
//!     <integer name="sample_count" value="64"/>
//!     <boolean name="jitter" value="true"/>
//! </sampler>
//! ```

use super::plugin::{Family, Param, PluginDoc};
use super::properties::Properties;
use super::xml::{Dialect, Element};
use super::Error;

/// Every sampler type, in both dialects (Nori names the count `sampleCount`). One
/// file holds them: a sampler is one or two parameters on the host; its code is
/// `shaders/sampler/`.
pub const REGISTRY: &[PluginDoc] = &[
    sampler(
        Dialect::Mitsuba,
        "independent",
        "Independent uniform numbers.",
        MITSUBA_BASE,
    ),
    sampler(
        Dialect::Mitsuba,
        "stratified",
        "Each dimension stratified; the count rounded up to a square.",
        MITSUBA_JITTER,
    ),
    sampler(
        Dialect::Mitsuba,
        "multijitter",
        "Correlated multi-jittered sampling (Kensler 2013).",
        MITSUBA_JITTER,
    ),
    sampler(
        Dialect::Mitsuba,
        "orthogonal",
        "Orthogonal-array sampling (Jarosz et al. 2019).",
        MITSUBA_ORTHOGONAL,
    ),
    sampler(
        Dialect::Mitsuba,
        "ldsampler",
        "Mitsuba's low-discrepancy (0,2)-sequence sampler.",
        MITSUBA_BASE,
    ),
    sampler(
        Dialect::Mitsuba,
        "zsobol",
        "pbrt-v4's Owen-scrambled Sobol' points in Morton order.",
        MITSUBA_ZSOBOL,
    ),
    sampler(
        Dialect::Nori,
        "independent",
        "Independent uniform numbers.",
        NORI_BASE,
    ),
    sampler(
        Dialect::Nori,
        "stratified",
        "Each dimension stratified; the count rounded up to a square.",
        NORI_JITTER,
    ),
    sampler(
        Dialect::Nori,
        "multijitter",
        "Correlated multi-jittered sampling (Kensler 2013).",
        NORI_JITTER,
    ),
    sampler(
        Dialect::Nori,
        "orthogonal",
        "Orthogonal-array sampling (Jarosz et al. 2019).",
        NORI_ORTHOGONAL,
    ),
    sampler(
        Dialect::Nori,
        "ldsampler",
        "Mitsuba's low-discrepancy (0,2)-sequence sampler.",
        NORI_BASE,
    ),
    sampler(
        Dialect::Nori,
        "zsobol",
        "pbrt-v4's Owen-scrambled Sobol' points in Morton order.",
        NORI_ZSOBOL,
    ),
];

const fn sampler(
    dialect: Dialect,
    name: &'static str,
    summary: &'static str,
    params: &'static [Param],
) -> PluginDoc {
    PluginDoc::new(Family::Sampler, dialect, name, summary, params)
}

const SAMPLE_COUNT: Param = Param::new("sample_count", "integer", "4", "samples per pixel");
const SAMPLE_COUNT_NORI: Param = Param::new("sampleCount", "integer", "1", "samples per pixel");
const SEED: Param = Param::new("seed", "integer", "0", "added to the render's seed");
const JITTER: Param = Param::new(
    "jitter",
    "boolean",
    "true",
    "random positions within strata",
);
const STRENGTH: Param = Param::new(
    "strength",
    "integer",
    "2",
    "strength of the orthogonal array, in [2, 16]",
);
const RANDOMIZATION: Param = Param::new(
    "randomization",
    "string",
    "fastowen",
    "fastowen, owen, permutedigits or none",
);
const MITSUBA_BASE: &[Param] = &[SAMPLE_COUNT, SEED];
const MITSUBA_JITTER: &[Param] = &[SAMPLE_COUNT, SEED, JITTER];
const MITSUBA_ORTHOGONAL: &[Param] = &[SAMPLE_COUNT, SEED, JITTER, STRENGTH];
const MITSUBA_ZSOBOL: &[Param] = &[SAMPLE_COUNT, SEED, RANDOMIZATION];
const NORI_BASE: &[Param] = &[SAMPLE_COUNT_NORI, SEED];
const NORI_JITTER: &[Param] = &[SAMPLE_COUNT_NORI, SEED, JITTER];
const NORI_ORTHOGONAL: &[Param] = &[SAMPLE_COUNT_NORI, SEED, JITTER, STRENGTH];
const NORI_ZSOBOL: &[Param] = &[SAMPLE_COUNT_NORI, SEED, RANDOMIZATION];

/// Reads a `<sampler>` element: its type, parameters and sample count (under
/// `count_key`, `default_count` when absent).
pub(super) fn read(
    el: &Element,
    dialect: Dialect,
    count_key: &str,
    default_count: u32,
) -> Result<(Sampler, u32), Error> {
    let attrs: &[&str] = match dialect {
        Dialect::Mitsuba => &["type", "id", "name"],
        Dialect::Nori => &["type"],
    };
    el.check_attrs(attrs)?;
    let t = el.require("type")?;
    let kind = SamplerKind::from_name(t).ok_or_else(|| {
        el.err(format!(
            "unknown sampler type '{t}' (expected one of {})",
            SamplerKind::NAMES.join(", ")
        ))
    })?;
    let (props, nested) = Properties::read(el, dialect, false)?;
    if let Some(n) = nested.first() {
        return Err(n.err(format!("unexpected <{}> in <sampler>", n.tag)));
    }
    let read = Sampler::from_properties(kind, &props, count_key, default_count)?;
    props.finish()?;
    Ok(read)
}

/// A sampler type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SamplerKind {
    Independent,
    Stratified,
    Multijitter,
    Orthogonal,
    LdSampler,
    ZSobol,
}

/// Randomization of the base-2 digits of Sobol' points (pbrt-v4's `randomization`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Randomization {
    None,
    /// A random digital shift (XOR): pbrt's `permutedigits`.
    PermuteDigits,
    /// Hash-based Owen scrambling (Burley 2020): pbrt's default `fastowen`.
    FastOwen,
    /// Owen scrambling with a hash per digit (Owen 1995).
    Owen,
}

impl Randomization {
    pub const NAMES: &'static [&'static str] = &["none", "permutedigits", "fastowen", "owen"];

    pub fn from_name(name: &str) -> Option<Randomization> {
        Some(match name {
            "none" => Randomization::None,
            "permutedigits" => Randomization::PermuteDigits,
            "fastowen" => Randomization::FastOwen,
            "owen" => Randomization::Owen,
            _ => return None,
        })
    }

    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

impl SamplerKind {
    /// Names scenes and `--sampler` may use.
    pub const NAMES: &'static [&'static str] = &[
        "independent",
        "stratified",
        "multijitter",
        "orthogonal",
        "ldsampler",
        "zsobol",
    ];

    pub fn from_name(name: &str) -> Option<SamplerKind> {
        Some(match name {
            "independent" => SamplerKind::Independent,
            "stratified" => SamplerKind::Stratified,
            "multijitter" => SamplerKind::Multijitter,
            "orthogonal" => SamplerKind::Orthogonal,
            "ldsampler" => SamplerKind::LdSampler,
            "zsobol" => SamplerKind::ZSobol,
            _ => return None,
        })
    }

    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// Parameters of this type besides the sample count and `seed`.
    fn parameters(self) -> &'static [&'static str] {
        match self {
            SamplerKind::Stratified | SamplerKind::Multijitter => &["jitter"],
            SamplerKind::Orthogonal => &["jitter", "strength"],
            SamplerKind::ZSobol => &["randomization"],
            SamplerKind::Independent | SamplerKind::LdSampler => &[],
        }
    }
}

/// A sampler with its parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sampler {
    pub kind: SamplerKind,
    /// Added to the render's seed.
    pub seed: u32,
    /// Random positions within strata (else their centres).
    pub jitter: bool,
    /// Strength of the orthogonal array (2: Bose's construction, more: Bush's).
    pub strength: u32,
    pub randomization: Randomization,
}

impl Default for Sampler {
    fn default() -> Sampler {
        Sampler::new(SamplerKind::Independent)
    }
}

/// The sample count a sampler renders for a requested one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SampleCount {
    pub requested: u32,
    /// Samples of one pass of the sampler's pattern: what a render of `requested`
    /// samples renders.
    pub count: u32,
    /// The pattern's strata: stratified (side, side), multijitter (columns, rows),
    /// orthogonal (prime, prime), zsobol (log2 count, base-4 digits of the Morton
    /// index); (0, 0) otherwise.
    pub res: [u32; 2],
    /// What the sampler says when it rounds (Mitsuba's warning).
    pub warning: Option<String>,
}

/// Largest sample count a sampler may round to.
const MAX_COUNT: u64 = 1 << 30;

fn is_prime(x: u64) -> bool {
    x >= 2
        && (2..)
            .take_while(|i| i * i <= x)
            .all(|i| !x.is_multiple_of(i))
}

impl Sampler {
    /// A sampler of `kind` with the default parameters.
    pub fn new(kind: SamplerKind) -> Sampler {
        Sampler {
            kind,
            seed: 0,
            jitter: true,
            strength: 2,
            randomization: Randomization::FastOwen,
        }
    }

    /// Reads a `<sampler>` of type `kind` from its properties, with the sample count
    /// under `count_key` (Mitsuba `sample_count`, Nori `sampleCount`). Returns the
    /// sampler and its sample count.
    pub fn from_properties(
        kind: SamplerKind,
        props: &Properties,
        count_key: &str,
        default_count: u32,
    ) -> Result<(Sampler, u32), Error> {
        let spp = props.positive(count_key, default_count)?;
        let seed = props.integer("seed", 0)?;
        let seed = u32::try_from(seed).map_err(|_| {
            props.error(
                "seed",
                format!("seed must be in [0, 4294967295], found {seed}"),
            )
        })?;
        let mut s = Sampler {
            seed,
            ..Sampler::new(kind)
        };
        let params = kind.parameters();
        if params.contains(&"jitter") {
            s.jitter = props.boolean("jitter", true)?;
        }
        if params.contains(&"strength") {
            let t = props.integer("strength", 2)?;
            s.strength = u32::try_from(t)
                .ok()
                .filter(|t| (2..=16).contains(t))
                .ok_or_else(|| {
                    props.error(
                        "strength",
                        format!("strength must be in [2, 16], found {t}"),
                    )
                })?;
        }
        if params.contains(&"randomization") {
            let r = props.string("randomization", "fastowen")?;
            s.randomization = Randomization::from_name(&r).ok_or_else(|| {
                props.error(
                    "randomization",
                    format!(
                        "unknown randomization '{r}' (expected one of {})",
                        Randomization::NAMES.join(", ")
                    ),
                )
            })?;
        }
        s.sample_count(spp, 1, 1)
            .map_err(|e| props.error(count_key, e))?;
        Ok((s, spp))
    }

    /// The same parameters under another type (`--sampler`): those the new type has
    /// keep their values.
    pub fn with_kind(self, kind: SamplerKind) -> Sampler {
        Sampler { kind, ..self }
    }

    /// The count this sampler renders when asked for `spp` samples per pixel of a
    /// `width` x `height` film, rounded as the sampler rounds it (Mitsuba's rules for
    /// Mitsuba's types), or why it cannot.
    pub fn sample_count(&self, spp: u32, width: u32, height: u32) -> Result<SampleCount, String> {
        if spp == 0 {
            return Err("the sample count must be at least 1".into());
        }
        let n = spp as u64;
        let (count, res, warning) = match self.kind {
            SamplerKind::Independent => (n, [0, 0], None),
            SamplerKind::Stratified => {
                let r = (1..).find(|r| r * r >= n).unwrap_or(1);
                (
                    r * r,
                    [r, r],
                    "Sample count should be square and power of two, rounding to",
                )
                    .into_warning(n)
            }
            SamplerKind::Multijitter => {
                let rows = ((n as f64).sqrt() as u64).max(1);
                let cols = n.div_ceil(rows);
                (cols * rows, [cols, rows], "Sample count rounded up to").into_warning(n)
            }
            SamplerKind::Orthogonal => {
                let s = (2..).find(|&s| s * s >= n && is_prime(s)).unwrap_or(2);
                if (s as f64).powi(self.strength as i32) > u32::MAX as f64 {
                    return Err(format!(
                        "an orthogonal array of strength {} over {s} symbols has more than 2^32 rows",
                        self.strength
                    ));
                }
                (
                    s * s,
                    [s, s],
                    "Sample count should be the square of a prime number, rounding to",
                )
                    .into_warning(n)
            }
            SamplerKind::LdSampler => {
                let mut r = 2u64;
                while r * r < n {
                    r = (r + 1).next_power_of_two();
                }
                (
                    r * r,
                    [0, 0],
                    "Sample count should be square and power of two, rounding to",
                )
                    .into_warning(n)
            }
            SamplerKind::ZSobol => {
                let c = n.next_power_of_two();
                let log2spp = c.trailing_zeros() as u64;
                let res = (width.max(height).max(1) as u64).next_power_of_two();
                let digits = res.trailing_zeros() as u64 + log2spp.div_ceil(2);
                (
                    c,
                    [log2spp, digits],
                    "Sample count should be a power of two, rounding to",
                )
                    .into_warning(n)
            }
        };
        if count > MAX_COUNT {
            return Err(format!(
                "{} rounds {spp} samples per pixel to {count}, more than {MAX_COUNT}",
                self.kind.name()
            ));
        }
        Ok(SampleCount {
            requested: spp,
            count: count as u32,
            res: res.map(|r| r as u32),
            warning: warning.map(|w| format!("{}: {w}", self.kind.name())),
        })
    }
}

/// (count, res, Mitsuba's message) to a count with a warning when it differs from `n`.
trait IntoWarning {
    fn into_warning(self, n: u64) -> (u64, [u64; 2], Option<String>);
}

impl IntoWarning for (u64, [u64; 2], &str) {
    fn into_warning(self, n: u64) -> (u64, [u64; 2], Option<String>) {
        let (count, res, message) = self;
        let warning = (count != n).then(|| format!("{message} {count}"));
        (count, res, warning)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::testutil::{error_at, load};

    /// The registry lists the types the reader knows, in both dialects.
    #[test]
    fn registry_lists_every_sampler_kind() {
        for dialect in [Dialect::Mitsuba, Dialect::Nori] {
            let names: Vec<&str> = REGISTRY
                .iter()
                .filter(|p| p.dialect == dialect)
                .map(|p| p.name)
                .collect();
            assert_eq!(names, SamplerKind::NAMES);
        }
    }

    /// A Mitsuba scene whose sensor holds `sampler` (on line 3).
    fn with_sampler(sampler: &str) -> String {
        format!(
            "<scene version=\"3.0.0\">\n<sensor type=\"perspective\">\n{sampler}\n</sensor>\n</scene>\n"
        )
    }

    #[test]
    fn scenes_name_samplers_and_their_parameters() {
        let s = load(
            &[(
                "s.xml",
                &with_sampler(
                    r#"<sampler type="orthogonal"><integer name="sample_count" value="30"/><integer name="seed" value="5"/><boolean name="jitter" value="false"/><integer name="strength" value="3"/></sampler>"#,
                ),
            )],
            &[],
        )
        .unwrap();
        assert_eq!(s.spp, 30);
        assert_eq!(
            s.sampler,
            Sampler {
                seed: 5,
                jitter: false,
                strength: 3,
                ..Sampler::new(SamplerKind::Orthogonal)
            }
        );
        let s = load(
            &[(
                "s.xml",
                &with_sampler(r#"<sampler type="zsobol"><string name="randomization" value="owen"/></sampler>"#),
            )],
            &[],
        )
        .unwrap();
        assert_eq!(
            (s.sampler.kind, s.sampler.randomization, s.spp),
            (SamplerKind::ZSobol, Randomization::Owen, 4)
        );
        // Nori scenes may name any type.
        let nori = r#"<scene>
  <integrator type="path_mis"/>
  <sampler type="multijitter"><integer name="sampleCount" value="16"/><boolean name="jitter" value="false"/></sampler>
  <camera type="perspective"/>
</scene>"#;
        let s = load(&[("n.xml", nori)], &[]).unwrap();
        assert_eq!(
            (s.sampler.kind, s.sampler.jitter, s.spp),
            (SamplerKind::Multijitter, false, 16)
        );
    }

    #[test]
    fn bad_samplers_are_errors_at_their_line() {
        let cases: &[(&str, &str)] = &[
            (
                r#"<sampler type="sobolish"/>"#,
                "unknown sampler type 'sobolish'",
            ),
            // A parameter the type does not have is not silently ignored.
            (
                r#"<sampler type="stratified"><integer name="strength" value="3"/></sampler>"#,
                "strength",
            ),
            (
                r#"<sampler type="ldsampler"><boolean name="jitter" value="false"/></sampler>"#,
                "jitter",
            ),
            (
                r#"<sampler type="orthogonal"><integer name="strength" value="1"/></sampler>"#,
                "strength must be in [2, 16]",
            ),
            (
                r#"<sampler type="independent"><integer name="seed" value="-1"/></sampler>"#,
                "seed must be in",
            ),
            (
                r#"<sampler type="zsobol"><string name="randomization" value="sobol"/></sampler>"#,
                "unknown randomization 'sobol'",
            ),
            (
                r#"<sampler type="stratified"><integer name="sample_count" value="0"/></sampler>"#,
                "sample_count",
            ),
        ];
        for (sampler, needle) in cases {
            let e = error_at(load(&[("s.xml", &with_sampler(sampler))], &[]), "s.xml", 3);
            assert!(e.contains(needle), "{sampler}: {e}");
        }
    }

    fn count(kind: SamplerKind, spp: u32) -> SampleCount {
        Sampler::new(kind).sample_count(spp, 256, 256).unwrap()
    }

    #[test]
    fn mitsuba_rounding() {
        // Mitsuba 3.9.1's sample_count() of mi.load_dict({"type": kind,
        // "sample_count": spp}), and its warnings.
        let cases: &[(SamplerKind, u32, u32)] = &[
            (SamplerKind::Independent, 7, 7),
            (SamplerKind::Stratified, 1, 1),
            (SamplerKind::Stratified, 10, 16),
            (SamplerKind::Stratified, 64, 64),
            (SamplerKind::Multijitter, 2, 2),
            (SamplerKind::Multijitter, 5, 6),
            (SamplerKind::Multijitter, 64, 64),
            (SamplerKind::Multijitter, 100, 100),
            (SamplerKind::Multijitter, 101, 110),
            (SamplerKind::Orthogonal, 1, 4),
            (SamplerKind::Orthogonal, 16, 25),
            (SamplerKind::Orthogonal, 64, 121),
            (SamplerKind::Orthogonal, 121, 121),
            (SamplerKind::LdSampler, 1, 4),
            (SamplerKind::LdSampler, 16, 16),
            (SamplerKind::LdSampler, 32, 64),
            (SamplerKind::LdSampler, 100, 256),
            (SamplerKind::ZSobol, 1, 1),
            (SamplerKind::ZSobol, 48, 64),
        ];
        for &(kind, spp, want) in cases {
            let c = count(kind, spp);
            assert_eq!(c.count, want, "{kind:?} {spp}");
            assert_eq!(c.warning.is_some(), spp != want, "{kind:?} {spp}");
        }
        assert_eq!(count(SamplerKind::Multijitter, 101).res, [11, 10]);
        assert_eq!(count(SamplerKind::Stratified, 10).res, [4, 4]);
        assert_eq!(count(SamplerKind::Orthogonal, 64).res, [11, 11]);
        assert_eq!(
            count(SamplerKind::Orthogonal, 64).warning.as_deref(),
            Some(
                "orthogonal: Sample count should be the square of a prime number, rounding to 121"
            )
        );
    }

    #[test]
    fn zsobol_digits() {
        // pbrt-v4: res = next power of 2 of the larger side, digits = log2(res) +
        // ceil(log2(spp) / 2).
        let s = Sampler::new(SamplerKind::ZSobol);
        assert_eq!(s.sample_count(64, 256, 100).unwrap().res, [6, 11]);
        assert_eq!(s.sample_count(32, 300, 10).unwrap().res, [5, 12]);
    }

    #[test]
    fn impossible_counts_are_errors() {
        assert!(Sampler::new(SamplerKind::Stratified)
            .sample_count(0, 8, 8)
            .is_err());
        assert!(Sampler::new(SamplerKind::Stratified)
            .sample_count(u32::MAX, 8, 8)
            .is_err());
        let strong = Sampler {
            strength: 16,
            ..Sampler::new(SamplerKind::Orthogonal)
        };
        assert!(strong.sample_count(64, 8, 8).is_err());
    }

    #[test]
    fn names_round_trip() {
        for name in SamplerKind::NAMES {
            assert_eq!(SamplerKind::from_name(name).unwrap().name(), *name);
        }
        for name in Randomization::NAMES {
            assert_eq!(Randomization::from_name(name).unwrap().name(), *name);
        }
    }
}
