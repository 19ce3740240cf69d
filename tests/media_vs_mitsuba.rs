//! Media renders against Mitsuba 3 references of the shipped scenes (scenes/media/,
//! references by tools/mitsuba_ref.py in scenes/refs/): homogeneous media with each
//! phase function, single scattering, the smoke grid and a textured thin dielectric in
//! fog. Mitsuba's own media test scenes are in media_mitsuba_test_scenes.rs.

mod common;

use common::load_with;
use common::media::render_stats;
use wavetrace::gpu::Device;
use wavetrace::image::Image;
use wavetrace::scene::Scene;

/// Renders `scene` (with `defines`) at 64 spp and compares it with a Mitsuba 3
/// `volpath` reference from tools/mitsuba_ref.py (scenes/refs/README.md): one-sample
/// t-tests of the pixel differences per 8x8 block and channel, the worst p-value
/// Bonferroni-corrected over the 192 tests; an unbiased render fails with probability
/// below 1%. Also checks that a 5% bias would be seen.
fn matches_reference(device: &Device, scene: &str, defines: &[(&str, &str)], reference: &str) {
    matches_reference_with(device, scene, defines, reference, None);
}

/// As [`matches_reference`] at `spp` samples.
fn matches_reference_at(
    device: &Device,
    scene: &str,
    defines: &[(&str, &str)],
    reference: &str,
    spp: u32,
) {
    matches_reference_spp(device, scene, defines, reference, None, spp);
}

/// As [`matches_reference`] with another integrator than the scene's.
fn matches_reference_with(
    device: &Device,
    scene: &str,
    defines: &[(&str, &str)],
    reference: &str,
    integrator: Option<&str>,
) {
    matches_reference_spp(device, scene, defines, reference, integrator, 64);
}

fn matches_reference_spp(
    device: &Device,
    scene: &str,
    defines: &[(&str, &str)],
    reference: &str,
    integrator: Option<&str>,
    spp: u32,
) {
    let scene = load_with(&common::repo(scene), defines);
    let reference = Image::read_exr(common::repo(reference)).expect("reference EXR");
    let (img, stats) = render_stats(device, &scene, integrator, spp, 0);
    assert_eq!(stats.discarded, 0, "NaN or infinite samples");
    let label = format!(
        "{} ({:.2} s)",
        reference_name(&scene, defines),
        stats.seconds
    );
    common::assert_matches_reference(&img, &reference, &label);
}

fn reference_name(scene: &Scene, defines: &[(&str, &str)]) -> String {
    format!("{} {defines:?}", scene.path.display())
}

/// The shipped homogeneous scenes against Mitsuba's volpath: a scattering cube
/// (sigma_s = 1, sigma_a = 0; also by vol_path_simple) with isotropic, g = 0.7 and
/// g = -0.7 phase functions, a
/// pure absorber, and two coloured media inside fog that also holds the camera.
#[test]
fn homogeneous_media_match_mitsuba() {
    let device = common::device();
    let cube = "scenes/media/cube.xml";
    matches_reference(&device, cube, &[], "scenes/refs/media_cube.exr");
    // Phase and BSDF sampling alone converge to the same image.
    matches_reference_with(
        &device,
        cube,
        &[],
        "scenes/refs/media_cube.exr",
        Some("vol_path_simple"),
    );
    // The anisotropic cubes at 256 spp: under the small area light their samples are
    // heavy-tailed, and at 64 spp the block means are far enough from normal that an
    // unbiased render fails the t-test for 2 of 5 seeds (t down to -5.6, the sign of
    // rare bright samples missing); 1024-spp renders of seeds 0 and 3 show no block
    // above |t| = 2.8, so nothing is biased.
    matches_reference_at(
        &device,
        cube,
        &[("g", "0.7")],
        "scenes/refs/media_cube_g07.exr",
        256,
    );
    matches_reference_at(
        &device,
        cube,
        &[("g", "-0.7")],
        "scenes/refs/media_cube_gm07.exr",
        256,
    );
    matches_reference(
        &device,
        cube,
        &[("albedo", "0")],
        "scenes/refs/media_cube_absorber.exr",
    );
    matches_reference(
        &device,
        "scenes/media/two_media.xml",
        &[],
        "scenes/refs/media_two.exr",
    );
}

/// Single scattering with distance and with equiangular sampling (a point light in
/// fog) against Mitsuba's volpath with max_depth 2: both have its mean.
#[test]
fn single_scattering_distance_and_equiangular_match_mitsuba() {
    let device = common::device();
    for sampling in ["distance", "equiangular"] {
        matches_reference(
            &device,
            "scenes/media/fog_point.xml",
            &[("sampling", sampling)],
            "scenes/refs/media_fog_point.exr",
        );
    }
}

/// The heterogeneous smoke grid against Mitsuba's volpath.
#[test]
fn grid_medium_matches_mitsuba() {
    let device = common::device();
    matches_reference(
        &device,
        "scenes/media/smoke.xml",
        &[],
        "scenes/refs/media_smoke.exr",
    );
}

/// Albedos that vary in space against Mitsuba's volpath: a homogeneous medium whose
/// albedo is a gridvolume (three channels, its own to_world, tilted against the cube
/// and smaller than it), with and without next-event estimation at its scattering
/// points (`sample_emitters`), and the smoke grid with an albedo grid of another
/// resolution and placement than its density's (scenes/media/albedo_*.xml).
#[test]
fn albedo_grids_match_mitsuba() {
    let device = common::device();
    let homogeneous = "scenes/media/albedo_homogeneous.xml";
    matches_reference(
        &device,
        homogeneous,
        &[],
        "scenes/refs/media_albedo_homogeneous.exr",
    );
    // Without next-event estimation in the medium, light reaches it only where phase
    // sampling finds the small area light: rare bright samples. At 64 spp a block
    // that missed them sat at t = -9.4 (its variance underestimated), where 1024 spp
    // agree with the reference to |t| < 2.8 everywhere, as the block means of the
    // two Mitsuba references (with and without) agree to 1%.
    matches_reference_at(
        &device,
        homogeneous,
        &[("sample_emitters", "false")],
        "scenes/refs/media_albedo_homogeneous_no_nee.exr",
        1024,
    );
    matches_reference(
        &device,
        "scenes/media/albedo_heterogeneous.xml",
        &[],
        "scenes/refs/media_albedo_heterogeneous.exr",
    );
}

/// A thin dielectric pane with a checkerboard specular_transmittance (and fog) against
/// Mitsuba: volpath crosses the pane as a null surface, its textured transmittance
/// weighting camera paths and shadow rays (vol_path.glsl, transmittance.glsl); path
/// samples it as a delta transmission lobe (bsdf_textured).
#[test]
///
/// At 128 spp: the fog and the dim floor corner are noisy in the 4096-spp references
/// too (±5-10% per pixel), and at 64 spp the bottom-left block sat near the test's
/// threshold (t = -4.2 to -4.4 for different triangulations of the same rectangles,
/// where 1024 spp agrees with the reference to within its noise).
fn textured_thin_dielectric_matches_mitsuba() {
    let device = common::device();
    let scene = "scenes/media/thin_textured.xml";
    let at = |defines: &[(&str, &str)], reference: &str| {
        matches_reference_at(&device, scene, defines, reference, 128)
    };
    at(&[], "scenes/refs/media_thin_textured.exr");
    at(
        &[("integrator", "path")],
        "scenes/refs/media_thin_textured_path.exr",
    );
}
