//! A `mask` under the volumetric path tracer against Mitsuba 3.9.1's `volpath`
//! (tests/data/mask_volpath.xml: an area light above a masked plane of opacity 0.4 over
//! a diffuse floor; references by `python3 tools/mitsuba_ref.py
//! tests/data/mask_volpath.xml -o tests/data/mask_volpath_depth_N_ref.exr --spp 4096
//! -D max_depth=M`, their JSON beside them).
//!
//! Mitsuba's volpath lets shadow rays through a surface scaled by its BSDF's null
//! transmission (a mask's 1 - opacity) and does not count a null lobe's scattering as
//! a bounce, nor change its MIS state there; wavetrace's volumetric integrators cross a
//! mask the same way (shaders/bsdf/mask_crossing.glsl). Its `path` integrators, as
//! Mitsuba's `path`, see the mask as opaque to shadow rays and its pass-through as a
//! bounce: the same image without a depth limit, but at max_depth 2 (direct light)
//! the floor under the mask would be black.
//!
//! Masks inside other composites (tests/data/mask_nested_volpath.xml: a blend with a
//! mask child, a mask of a textured mask, a blend of two masks; references as above
//! with `mask_nested_volpath`): Mitsuba's volpath passes such a surface whenever the
//! BSDF's sample is a pass-through (the tree's null weight) and weighs shadow rays by
//! eval_null_transmission, which blendbsdf and mask forward with their weights. The
//! floor under each strip shows it: at max_depth 2 it is lit only through the strips'
//! pass-throughs.
//!
//! A bump map over a mask (tests/data/mask_bump_volpath.xml, references as above at
//! 8192 spp; an emitting backdrop seen through the strips at a grazing angle):
//! Mitsuba's bumpmap weighs a pass-through by its shadowing term (bumpmap::sample),
//! and has no null transmission, so its shadow rays are blocked and the light the
//! floor gets through the strip comes by BSDF sampling alone, weighed by volpath's
//! power heuristic: that image depends on the heuristic (with the balance heuristic
//! the test fails by far: block t = 27 at max_depth 2), and the test renders with
//! `mis_heuristic` = `power`. tests/data/mask_bump_mis_volpath.xml (references as
//! above) lights a masked floor through a bumped mask canopy: there the power
//! heuristic weighs the light by the floor's pdf as Mitsuba's mask::pdf gives it, the
//! opacity times the diffuse's (wavetrace's vertex that did not pass samples the
//! diffuse alone).
//!
//! A tree of seven leaves (tests/data/mask_deep_volpath.xml, references as above at
//! 8192 spp): more than a vertex lists at once, so a blend's side is picked
//! stochastically (composite.glsl); the vertex that did not pass is rescaled so that
//! its mean is still the tree's.

mod common;

use common::{assert_matches_reference_at, device, repo};
use wavetrace::image::Image;
use wavetrace::render::RenderOptions;
use wavetrace::scene::integrator::Param;

/// Renders tests/data/`scene`.xml under volpath at `max_depth` with 1024 spp and
/// compares it with tests/data/`scene`_depth_`name`_ref.exr block by block, `name` being
/// the depth or "unbounded" for -1 (the check also rejects the image scaled by 0.95).
/// With `power`, MIS weighs by the power heuristic, as Mitsuba's volpath does
/// (volpath.cpp's mis_weight squares both densities); wavetrace's `volpath` defaults to
/// the balance heuristic, which gives the same mean wherever shadow rays and BSDF
/// sampling see the same surfaces (not through a bump map: see above).
fn render_against(scene: &str, max_depth: i32, power: bool) {
    let depth = if max_depth < 0 {
        "unbounded".to_string()
    } else {
        max_depth.to_string()
    };
    let mut loaded = common::load_with(
        &repo(&format!("tests/data/{scene}.xml")),
        &[("max_depth", &max_depth.to_string())],
    );
    if power {
        loaded
            .integrator
            .params
            .insert("mis_heuristic".into(), Param::String("power".into()));
    }
    let reference = format!("tests/data/{scene}_depth_{depth}_ref.exr");
    let reference = Image::read_exr(repo(&reference)).expect(&reference);
    let img = common::render(&device(), &loaded, &RenderOptions::default(), 1024);
    assert_eq!(img.non_finite_count(), 0);
    let label = format!("{scene}, volpath, max_depth {max_depth}, 1024 spp");
    assert_matches_reference_at(&img, &reference, &label, 0.01);
}

#[test]
fn unbounded_volpath_through_a_mask_matches_mitsuba() {
    render_against("mask_volpath", -1, false);
}

#[test]
fn direct_light_through_a_mask_matches_mitsubas_volpath() {
    render_against("mask_volpath", 2, false);
}

#[test]
fn direct_light_through_nested_masks_matches_mitsubas_volpath() {
    render_against("mask_nested_volpath", 2, false);
}

#[test]
fn unbounded_volpath_through_nested_masks_matches_mitsuba() {
    render_against("mask_nested_volpath", -1, false);
}

#[test]
fn direct_light_through_a_bumped_mask_matches_mitsubas_volpath() {
    render_against("mask_bump_volpath", 2, true);
}

#[test]
fn unbounded_volpath_through_a_bumped_mask_matches_mitsuba() {
    render_against("mask_bump_volpath", -1, true);
}

#[test]
fn direct_light_through_a_deep_tree_of_masks_matches_mitsubas_volpath() {
    render_against("mask_deep_volpath", 2, false);
}

#[test]
fn unbounded_volpath_through_a_deep_tree_of_masks_matches_mitsuba() {
    render_against("mask_deep_volpath", -1, false);
}

#[test]
fn direct_light_through_a_bumped_mask_onto_a_mask_matches_mitsubas_volpath() {
    render_against("mask_bump_mis_volpath", 2, true);
}

#[test]
fn unbounded_volpath_through_a_bumped_mask_onto_a_mask_matches_mitsuba() {
    render_against("mask_bump_mis_volpath", -1, true);
}
