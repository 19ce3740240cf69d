//! The BSDF models the GPU knows: one [`Kind`] per file in `shaders/bsdf/`, with its
//! id in `BsdfRecord::kind` and its lobes (pbrt-v4's `BxDFFlags`).
//!
//! Plain data with no imports: `build.rs` includes this file too
//! (`build/bsdf_dispatch.rs`), and generates from [`KINDS`] the GLSL dispatch
//! `generated/bsdf_dispatch.glsl`: a `#define BSDF_<NAME> id` per kind, the include of each
//! model's file, the switches of `bsdf_eval`, `bsdf_pdf` and `bsdf_sample`,
//! `bsdf_is_delta` and `bsdf_lobes`. A model's file `shaders/bsdf/<name>.glsl` defines
//! `bsdf_<name>_sample(b, wo, u)`, and unless every lobe is a delta,
//! `bsdf_<name>_eval(b, wo, wi)` and `bsdf_<name>_pdf(b, wo, wi)`; the [`hooks`] it
//! declares add functions the dispatch calls.

/// One BSDF model of the GPU side.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Kind {
    /// `BsdfRecord::kind`: its position in [`KINDS`], and its bit in the
    /// `BSDF_KINDS` specialization mask (so at most 32 kinds).
    pub id: u32,
    /// Its GLSL name: the file `shaders/bsdf/<name>.glsl`, the functions
    /// `bsdf_<name>_*`, the constant `BSDF_<NAME>`; also its `wavetrace warptest`
    /// target name.
    pub name: &'static str,
    /// Its lobes, a union of [`lobes`] flags, for every record of the kind; a kind
    /// whose lobes depend on the record declares [`hooks::LOBES`] and narrows them.
    pub lobes: u32,
    /// The optional GLSL functions its file defines ([`hooks`] flags).
    pub hooks: u32,
}

/// Lobe flags (`BSDF_LOBE_*` in GLSL), as pbrt-v4's `BxDFFlags`.
pub mod lobes {
    /// Scatters into the hemisphere of wo.
    pub const REFLECTION: u32 = 1;
    /// Scatters into the other hemisphere.
    pub const TRANSMISSION: u32 = 2;
    /// Has a Dirac delta lobe (sampled, never evaluated). A kind with no
    /// [`DIFFUSE`] or [`GLOSSY`] lobe is delta only: emitter sampling is skipped
    /// there, and it has no eval or pdf function.
    pub const DELTA: u32 = 4;
    /// Has a diffuse lobe: the photon mappers store photons and make visible points
    /// on it.
    pub const DIFFUSE: u32 = 8;
    /// Has a glossy (non-delta, non-diffuse) lobe.
    pub const GLOSSY: u32 = 16;
    /// Passes light straight through without bending (thin dielectric): the
    /// volumetric path tracers cross it as Mitsuba's volpath crosses a null lobe.
    pub const NULL: u32 = 32;
}

/// Optional functions of a kind's GLSL file, called by the generated dispatch.
pub mod hooks {
    /// `uint bsdf_<name>_lobes(BsdfRecord b)`: the record's lobes, a subset of the
    /// kind's (`bsdf_lobes`).
    pub const LOBES: u32 = 1;
    /// `BsdfRecord bsdf_<name>_textured(BsdfRecord b)`: fixes up parameters derived
    /// from textured ones once `bsdf_textured` has looked them up.
    pub const TEXTURED: u32 = 2;
}

use lobes::{DELTA, DIFFUSE, GLOSSY, NULL, REFLECTION, TRANSMISSION};

/// Every kind, by id: (id, GLSL name, lobes, hooks), one line each.
#[rustfmt::skip]
pub const KINDS: &[Kind] = &[
    kind(0, "diffuse",         REFLECTION | DIFFUSE,                   0),
    kind(1, "conductor",       REFLECTION | DELTA,                     0),
    kind(2, "roughconductor",  REFLECTION | GLOSSY,                    0),
    kind(3, "dielectric",      REFLECTION | TRANSMISSION | DELTA,      0),
    kind(4, "roughdielectric", REFLECTION | TRANSMISSION | GLOSSY,     0),
    kind(5, "plastic",         REFLECTION | DELTA | DIFFUSE,           0),
    kind(6, "roughplastic",    REFLECTION | GLOSSY | DIFFUSE,          0),
    kind(7, "nori_microfacet", REFLECTION | GLOSSY | DIFFUSE,          hooks::LOBES | hooks::TEXTURED),
    kind(8, "thindielectric",  REFLECTION | TRANSMISSION | DELTA | NULL, 0),
    kind(9, "pplastic",        REFLECTION | GLOSSY | DIFFUSE,          0),
    kind(10, "principled",     REFLECTION | TRANSMISSION | GLOSSY | DIFFUSE, hooks::LOBES),
    kind(11, "principledthin", REFLECTION | TRANSMISSION | GLOSSY | DIFFUSE, hooks::LOBES),
    kind(12, "mask_null",      TRANSMISSION | DELTA | NULL,            0),
    kind(13, "measured",       REFLECTION | GLOSSY,                    0),
    kind(14, "hair",           REFLECTION | TRANSMISSION | GLOSSY,     0),
];

/// `BsdfRecord::kind` of the node records of composite BSDFs (`mask`, `blendbsdf`,
/// `twosided` with two sides, `bumpmap`: `scene::bsdf::composite`), which a hit
/// resolves into one leaf record before any model is evaluated. Its bit in the
/// `BSDF_KINDS` mask says the scene has composites; no kind may take its id.
pub const COMPOSITE: u32 = 31;

const fn kind(id: u32, name: &'static str, lobes: u32, hooks: u32) -> Kind {
    Kind {
        id,
        name,
        lobes,
        hooks,
    }
}

impl Kind {
    /// Every lobe is a delta: no eval or pdf, no emitter sampling.
    pub const fn is_delta(&self) -> bool {
        self.lobes & (DIFFUSE | GLOSSY) == 0
    }
}

/// The kind called `name` ([`Kind::name`]), found at compile time in a `const`: a
/// name missing from [`KINDS`] fails the build.
pub const fn find(name: &str) -> &'static Kind {
    let mut i = 0;
    while i < KINDS.len() {
        if str_eq(KINDS[i].name, name) {
            return &KINDS[i];
        }
        i += 1;
    }
    panic!("a BSDF kind missing from kinds::KINDS")
}

const fn str_eq(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}
