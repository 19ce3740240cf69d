//! Images of the texture and environment-map scenes against Mitsuba 3 references of
//! the same files (scenes/refs/, made by tools/mitsuba_ref.py): textured BSDF
//! parameters and textured area emitters (sampled by their texture), normal maps, and
//! an environment map with a small bright sun.

mod common;

use common::{device, repo};
use wavetrace::image::Image;
use wavetrace::render::RenderOptions;

/// Renders `scene` at `spp` and block-t-tests it against `reference`: one-sample t
/// tests of the pixel differences per 8x8 block and channel, the worst p-value
/// Bonferroni-corrected over the 192 tests of a 64x64 image (image::metrics), so an
/// unbiased render fails with probability below 1%. Also checks that the test sees a
/// 5% bias, so it has the power to catch, e.g., a flipped texture or emitter pattern.
fn check(scene: &str, reference: &str, spp: u32) {
    check_with(scene, &[], reference, spp);
}

/// [`check`] with `-D name=value` scene parameters.
fn check_with(scene: &str, defines: &[(&str, &str)], reference: &str, spp: u32) {
    let path = repo(scene);
    let defines: Vec<(String, String)> = defines
        .iter()
        .map(|(n, v)| (n.to_string(), v.to_string()))
        .collect();
    let scene = wavetrace::scene::load(&path, &defines)
        .unwrap_or_else(|e| panic!("loading {}: {e}", path.display()));
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

/// Emitters sampled by their texture (scene::textured_emitter) on a sphere and a
/// rectangle, bilinear, with clamped and mirrored wraps and to_uv symmetries, as
/// Mitsuba samples them.
#[test]
fn textured_sphere_and_rectangle_lights_match_mitsuba() {
    check(
        "scenes/textures/textured_lights.xml",
        "scenes/refs/textured_lights.exr",
        256,
    );
}

/// Mitsuba 3.9's normalmap with its defaults: flipped invalid normals and the
/// shadowing term (together 0.1% darker on average, up to 0.9% in an 8x8 block).
#[test]
fn normal_maps_match_mitsuba() {
    check(
        "scenes/textures/normalmap.xml",
        "scenes/refs/normalmap.exr",
        256,
    );
}

/// The same with `flip_invalid_normals` and `use_shadowing_function` off.
#[test]
fn normal_maps_without_flip_or_shadowing_match_mitsuba() {
    check_with(
        "scenes/textures/normalmap.xml",
        &[("flip", "false"), ("shadowing", "false")],
        "scenes/refs/normalmap_plain.exr",
        256,
    );
}

#[test]
fn environment_map_lighting_matches_mitsuba() {
    check("scenes/envmap/envmap.xml", "scenes/refs/envmap.exr", 256);
}
