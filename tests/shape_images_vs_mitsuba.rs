//! Images of every Mitsuba shape against Mitsuba 3.9 references of the same files
//! (scenes/shapes/, made by tools/make_shape_scenes.py; references by
//! tools/mitsuba_ref.py, scenes/refs/README.md). Each scene shows its shape twice:
//! with a uv-debug texture (a shifted, turned or mirrored parameterization moves its
//! grid and corner marks) and, mirrored by `to_world`, with a normal map over an
//! anisotropic rough conductor (whose highlight follows the tangent frame). The
//! checkerboard cube is the scene of issue 17.

mod common;

use common::{device, repo};
use wavetrace::image::Image;
use wavetrace::render::RenderOptions;

/// Renders scenes/shapes/`name`.xml at `spp` and block-t-tests it against
/// scenes/refs/shapes_`name`.exr (8x8 blocks per channel, Bonferroni-corrected, at
/// 1%; and the test must reject the render scaled by 0.95, so it sees a 5% error such
/// as a texture shifted by a cell).
fn check(name: &str, spp: u32) {
    let path = repo(&format!("scenes/shapes/{name}.xml"));
    let scene = wavetrace::scene::load(&path, &[])
        .unwrap_or_else(|e| panic!("loading {}: {e}", path.display()));
    let reference =
        Image::read_exr(repo(&format!("scenes/refs/shapes_{name}.exr"))).expect("reference EXR");
    let t = std::time::Instant::now();
    let img = common::render(&device(), &scene, &RenderOptions::default(), spp);
    assert_eq!((img.width, img.height), (reference.width, reference.height));
    let label = format!("{name} ({:.1} s)", t.elapsed().as_secs_f64());
    common::assert_matches_reference(&img, &reference, &label);
}

#[test]
fn cube_matches_mitsuba() {
    check("cube", 64);
}

#[test]
fn rectangle_matches_mitsuba() {
    check("rectangle", 64);
}

#[test]
fn disk_matches_mitsuba() {
    check("disk", 64);
}

#[test]
fn sphere_matches_mitsuba() {
    check("sphere", 64);
}

#[test]
fn cylinder_matches_mitsuba() {
    check("cylinder", 64);
}

#[test]
fn obj_matches_mitsuba() {
    check("obj", 64);
}

#[test]
fn ply_matches_mitsuba() {
    check("ply", 64);
}

#[test]
fn serialized_matches_mitsuba() {
    check("serialized", 64);
}

/// Issue 17: the checker pattern on each face of a Mitsuba cube, with a
/// bitmap-textured floor and a bitmap-textured light.
#[test]
fn checkerboard_cube_matches_mitsuba() {
    check("checker_cube", 64);
}
