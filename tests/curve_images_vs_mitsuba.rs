//! Curves rendered against Mitsuba 3.9 references of the same files
//! (scenes/curves/; references by tools/mitsuba_ref.py, scenes/refs/README.md): the
//! `linearcurve` of scenes/curves/curves.txt with a uv-debug texture (a shifted or
//! turned parameterization moves its grid) and, moved by a non-uniform `to_world`
//! that keeps the radii, in a rough conductor, casting shadows on a floor; and the same
//! with `bsplinecurve` on scenes/curves/bsplines.txt.

mod common;

use common::{device, repo};
use wavetrace::image::Image;
use wavetrace::render::RenderOptions;

/// Renders scenes/curves/`scene`.xml at `spp` and block-t-tests it against
/// scenes/refs/`reference`.exr (as tests/shape_images_vs_mitsuba.rs does: 8x8 blocks
/// per channel, Bonferroni-corrected, at 1%, and the render scaled by 0.95 rejected).
fn check(scene: &str, reference: &str, spp: u32) {
    let path = repo(&format!("scenes/curves/{scene}.xml"));
    let scene = wavetrace::scene::load(&path, &[])
        .unwrap_or_else(|e| panic!("loading {}: {e}", path.display()));
    let reference =
        Image::read_exr(repo(&format!("scenes/refs/{reference}.exr"))).expect("reference EXR");
    let t = std::time::Instant::now();
    let img = common::render(&device(), &scene, &RenderOptions::default(), spp);
    assert_eq!((img.width, img.height), (reference.width, reference.height));
    let label = format!("{} ({:.1} s)", path.display(), t.elapsed().as_secs_f64());
    common::assert_matches_reference(&img, &reference, &label);
}

#[test]
fn linear_curves_match_mitsuba() {
    check("curves", "curves_linear", 64);
}

/// The same scene with `bsplinecurve` on scenes/curves/bsplines.txt (cubic B-spline
/// tubes, no end caps).
#[test]
fn bspline_curves_match_mitsuba() {
    check("bsplines", "curves_bspline", 64);
}
