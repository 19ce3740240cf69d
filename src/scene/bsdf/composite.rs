//! Composite BSDFs on the GPU: Mitsuba 3's `mask`, `blendbsdf`, `twosided` around two
//! BSDFs (or around another composite) and `bumpmap` become node records
//! ([`kinds::COMPOSITE`]) beside the flat records of the models they nest. At a
//! surface hit of the path tracers the tree resolves into its leaves
//! (`shaders/bsdf/composite.glsl`, `bsdf_composite_mix`), without recursion:
//!
//! - a blend (and a mask, which is a blend of a pass-through and its BSDF by the
//!   opacity) keeps both children, each leaf weighted by the product of the weights
//!   on its branch, up to 4 leaves. eval and pdf are the weighted sums,
//!   f = (1 − w) f₀ + w f₁, as Mitsuba's `blendbsdf` and `mask`; sampling picks leaf j
//!   with probability wⱼ by the number that picks the lobe (rescaled to [0, 1) for the
//!   leaf) and weighs a smooth sample by f / pdf of the whole mixture (as Mitsuba
//!   3.9.1's `blendbsdf::sample`), a delta sample by the leaf's own weight (unbiased,
//!   where Mitsuba 3.9.1 mixes a delta's discrete probability with the other child's
//!   density). The vertex evaluates the chosen leaf as a single model and adds the
//!   others' eval and pdf (`bsdf_composite_others`). A blend beyond 4 leaves picks one
//!   side by its weight (unbiased, noisier). The photon mappers resolve the tree into
//!   the one leaf the same number picks (`bsdf_composite_resolve`): E[f] is the blend,
//!   as pbrt-v4's `MixMaterial` chooses one material per intersection.
//! - a twosided node takes its front or back child by the side of the shading normal
//!   wo lies on, and marks the leaf twosided so that the back is seen in the
//!   mirrored frame, as Mitsuba's `twosided`
//!   (`BSDF_TWOSIDED`).
//! - a bump map replaces the shading frame by the one its height field gives, and
//!   goes on with its child.
//!
//! The pass-through of a mask is the leaf kind `mask_null` (`shaders/bsdf/mask_null.glsl`):
//! a delta transmission straight on with weight 1, so the path continues and its depth
//! grows, as the null lobe of Mitsuba's path integrator. Scenes without composites have
//! no node records: the bit [`kinds::COMPOSITE`] of the `BSDF_KINDS` constant is clear
//! and the resolution compiles away.
//!
//! A node record holds: `kind` = [`kinds::COMPOSITE`], `distribution` its
//! `COMPOSITE_*` operation, `tex_specular` and `tex_transmittance` its two children
//! (record indices), `eta` its constant weight (blend, mask) or height scale (bump),
//! `tex_reflectance` the texture of either (id + 1, 0: none), and a bump map's
//! `flags` its `BSDF_NORMALMAP_FLIP` and `BSDF_NORMALMAP_SHADOWING`.

use super::{kinds, Bsdf};
use crate::gpu::layout::{
    BsdfRecord, BSDF_NORMALMAP_FLIP, BSDF_NORMALMAP_SHADOWING, BSDF_TWOSIDED,
};
use crate::scene::properties::Properties;
use crate::scene::Error;

/// `distribution` of a node: (1 − w) child 0 + w child 1 (blend, mask).
pub const COMPOSITE_BLEND: u32 = 0;
/// `distribution` of a node: child 0 in front of the shading normal, child 1 behind.
pub const COMPOSITE_TWOSIDED: u32 = 1;
/// `distribution` of a node: child 0 in the frame of a bump map.
pub const COMPOSITE_BUMP: u32 = 2;

/// A weight of a composite: a float, or a texture's luminance (Mitsuba's `eval_1`),
/// clamped to [0, 1] where it is used.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Weight {
    /// The constant, or the texture's mean luminance.
    pub value: f32,
    /// The texture index, if a texture gives it.
    pub texture: Option<u32>,
}

impl Weight {
    /// Parameter `name` of `props`, a float or a texture; `None` when absent.
    pub fn read(props: &Properties, name: &str) -> Result<Option<Weight>, Error> {
        let texture = props
            .textures()
            .into_iter()
            .find(|(n, _)| n == name)
            .map(|(_, i)| i);
        Ok(props
            .float_opt(name)?
            .map(|value| Weight { value, texture }))
    }

    /// A constant weight.
    pub fn constant(value: f32) -> Weight {
        Weight {
            value,
            texture: None,
        }
    }
}

/// Whether `bsdf` is resolved on the GPU through node records.
pub fn is_composite(bsdf: &Bsdf) -> bool {
    match bsdf {
        Bsdf::Blend { .. } | Bsdf::Mask { .. } | Bsdf::TwoSidedPair(..) | Bsdf::BumpMap { .. } => {
            true
        }
        Bsdf::TwoSided(inner) => is_composite(inner),
        _ => false,
    }
}

/// The records of `bsdfs`: record i is bsdf i's (a model's, or a composite's root
/// node), followed by the records that composites nest. Without composites this is
/// `bsdfs` mapped by `BsdfRecord::from`.
pub fn records(bsdfs: &[Bsdf]) -> Vec<BsdfRecord> {
    let base = bsdfs.len() as u32;
    let mut extra = Vec::new();
    let mut out: Vec<BsdfRecord> = bsdfs.iter().map(|b| node(b, base, 0, &mut extra)).collect();
    out.extend(extra);
    out
}

/// The record of `bsdf`, with `flags` added to its models' records (`BSDF_TWOSIDED`
/// below a twosided node, so that a record alone, as a visible point of the photon
/// mappers keeps it, says so too); the records of what it nests go to `extra` (whose
/// first one has index `base`).
fn node(bsdf: &Bsdf, base: u32, flags: u32, extra: &mut Vec<BsdfRecord>) -> BsdfRecord {
    let flags = flags
        | match bsdf {
            Bsdf::TwoSidedPair(..) | Bsdf::TwoSided(..) => BSDF_TWOSIDED,
            _ => 0,
        };
    let child = |b: &Bsdf, extra: &mut Vec<BsdfRecord>| {
        let r = node(b, base, flags, extra);
        extra.push(r);
        base + extra.len() as u32 - 1
    };
    match bsdf {
        Bsdf::Blend { weight, bsdfs } => {
            let c0 = child(&bsdfs[0], extra);
            let c1 = child(&bsdfs[1], extra);
            node_record(COMPOSITE_BLEND, c0, c1, *weight)
        }
        Bsdf::Mask { opacity, bsdf } => {
            let pass = child_record(mask_null(), base, extra);
            let c1 = child(bsdf, extra);
            node_record(COMPOSITE_BLEND, pass, c1, *opacity)
        }
        Bsdf::TwoSidedPair(pair) => {
            let c0 = child(&pair[0], extra);
            let c1 = child(&pair[1], extra);
            node_record(COMPOSITE_TWOSIDED, c0, c1, Weight::constant(0.0))
        }
        Bsdf::TwoSided(inner) if is_composite(inner) => {
            let c = child(inner, extra);
            node_record(COMPOSITE_TWOSIDED, c, c, Weight::constant(0.0))
        }
        Bsdf::BumpMap { params, bsdf } => {
            let c = child(bsdf, extra);
            let w = Weight {
                value: params.scale,
                texture: Some(params.texture),
            };
            let mut r = node_record(COMPOSITE_BUMP, c, c, w);
            if params.flip_invalid_normals {
                r.flags |= BSDF_NORMALMAP_FLIP;
            }
            if params.use_shadowing_function {
                r.flags |= BSDF_NORMALMAP_SHADOWING;
            }
            r
        }
        model => {
            let mut r = BsdfRecord::from(model);
            r.flags |= flags;
            r
        }
    }
}

fn child_record(r: BsdfRecord, base: u32, extra: &mut Vec<BsdfRecord>) -> u32 {
    extra.push(r);
    base + extra.len() as u32 - 1
}

fn node_record(op: u32, c0: u32, c1: u32, w: Weight) -> BsdfRecord {
    BsdfRecord {
        kind: kinds::COMPOSITE,
        distribution: op,
        tex_specular: c0,
        tex_transmittance: c1,
        eta: w.value,
        tex_reflectance: w.texture.map_or(0, |t| t + 1),
        ..Default::default()
    }
}

/// The record of a mask's pass-through.
fn mask_null() -> BsdfRecord {
    BsdfRecord {
        kind: kinds::find("mask_null").id,
        specular: [1.0; 3],
        transmittance: [1.0; 3],
        eta: 1.0,
        alpha_u: 1.0,
        alpha_v: 1.0,
        ..Default::default()
    }
}

/// The nested BSDFs of a composite, for what the host asks of the whole tree.
pub fn children(bsdf: &Bsdf) -> Vec<&Bsdf> {
    match bsdf {
        Bsdf::Blend { bsdfs, .. } | Bsdf::TwoSidedPair(bsdfs) => vec![&bsdfs[0], &bsdfs[1]],
        Bsdf::Mask { bsdf, .. } | Bsdf::BumpMap { bsdf, .. } => vec![bsdf],
        _ => Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::bsdf::Diffuse;
    use glam::Vec3;

    fn diffuse(r: f32) -> Bsdf {
        Bsdf::Diffuse(Diffuse {
            reflectance: Vec3::splat(r),
        })
    }

    #[test]
    fn composites_append_their_children_after_the_top_level_records() {
        let blend = Bsdf::Blend {
            weight: Weight::constant(0.25),
            bsdfs: Box::new([diffuse(0.1), diffuse(0.9)]),
        };
        let mask = Bsdf::Mask {
            opacity: Weight {
                value: 0.5,
                texture: Some(3),
            },
            bsdf: Box::new(blend.clone()),
        };
        let r = records(&[diffuse(0.5), mask]);
        // 0: diffuse, 1: mask node; 2: null, then the blend's children 3, 4 and the
        // blend node 5.
        assert_eq!(r.len(), 6);
        assert_eq!(r[0], BsdfRecord::from(&diffuse(0.5)));
        assert_eq!(
            (
                r[1].kind,
                r[1].distribution,
                r[1].tex_specular,
                r[1].tex_transmittance
            ),
            (kinds::COMPOSITE, COMPOSITE_BLEND, 2, 5)
        );
        assert_eq!((r[1].eta, r[1].tex_reflectance), (0.5, 4));
        assert_eq!(r[2].kind, kinds::find("mask_null").id);
        assert_eq!(r[3].reflectance, [0.1; 3]);
        assert_eq!(r[4].reflectance, [0.9; 3]);
        assert_eq!(
            (r[5].tex_specular, r[5].tex_transmittance, r[5].eta),
            (3, 4, 0.25)
        );
    }

    #[test]
    fn twosided_nodes_flag_their_models() {
        let pair = Bsdf::TwoSidedPair(Box::new([diffuse(0.1), diffuse(0.9)]));
        let r = records(&[pair, diffuse(0.5)]);
        assert_eq!(
            (r[0].kind, r[0].distribution),
            (kinds::COMPOSITE, COMPOSITE_TWOSIDED)
        );
        assert_eq!(r[1].flags, 0);
        assert_eq!((r[2].flags, r[3].flags), (BSDF_TWOSIDED, BSDF_TWOSIDED));
    }

    #[test]
    fn composite_ops_match_glsl() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders/bsdf/composite.glsl");
        let src = std::fs::read_to_string(path).expect("read composite.glsl");
        for (name, v) in [
            ("COMPOSITE_BLEND", COMPOSITE_BLEND),
            ("COMPOSITE_TWOSIDED", COMPOSITE_TWOSIDED),
            ("COMPOSITE_BUMP", COMPOSITE_BUMP),
        ] {
            assert!(
                src.contains(&format!("#define {name} {v}u\n")),
                "{name} {v}"
            );
        }
    }
}
