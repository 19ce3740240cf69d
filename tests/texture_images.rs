//! Images of the texture and environment-map scenes against Mitsuba 3 references of
//! the same files (scenes/refs/, made by tools/mitsuba_ref.py): textured BSDF
//! parameters and textured area emitters, normal maps, and an environment map with a
//! small bright sun.

mod common;

use common::{device, load, repo};
use wavetrace::image::Image;
use wavetrace::render::RenderOptions;

/// Renders `scene` at `spp` and block-t-tests it against `reference`: one-sample t
/// tests of the pixel differences per 8x8 block and channel, the worst p-value
/// Bonferroni-corrected over the 192 tests of a 64x64 image (image::metrics), so an
/// unbiased render fails with probability below 1%. Also checks that the test sees a
/// 5% bias, so it has the power to catch, e.g., a flipped texture or emitter pattern.
fn check(scene: &str, reference: &str, spp: u32) {
    let scene = load(&repo(scene));
    let reference = Image::read_exr(repo(reference)).expect("reference EXR");
    let t = std::time::Instant::now();
    let img = common::render(&device(), &scene, &RenderOptions::default(), spp);
    assert_eq!((img.width, img.height), (reference.width, reference.height));
    let label = format!(
        "{} ({:.1} s)",
        scene.path.display(),
        t.elapsed().as_secs_f64()
    );
    common::assert_matches_reference(&img, &reference, &label);
}

#[test]
fn textured_bsdfs_and_area_emitters_match_mitsuba() {
    check(
        "scenes/textures/textures.xml",
        "scenes/refs/textures.exr",
        256,
    );
}

/// Fails today: block (7, 3) at the right edge (t = 5.5, Bonferroni p = 1.4e-4 at 256
/// spp) is brighter than Mitsuba; the rest of the image agrees. Not yet explained.
#[test]
#[ignore]
fn normal_maps_match_mitsuba() {
    check(
        "scenes/textures/normalmap.xml",
        "scenes/refs/normalmap.exr",
        256,
    );
}

#[test]
fn environment_map_lighting_matches_mitsuba() {
    check("scenes/envmap/envmap.xml", "scenes/refs/envmap.exr", 256);
}
