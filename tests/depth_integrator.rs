//! Mitsuba 3's `depth` integrator (the first hit's distance along the camera ray, 0
//! where it meets nothing; shaders/integrator/first_hit.glsl) against Mitsuba 3.9.1's
//! on `scenes/ptracer/ptracer_room.xml`, block by block.

mod common;

use common::{assert_matches_reference, device, load_with, repo};
use wavetrace::image::exr;
use wavetrace::render::RenderOptions;

#[test]
fn depth_matches_mitsuba() {
    let device = device();
    let reference = exr::read(repo("scenes/refs/ptracer_room_depth.exr")).expect("reference");
    let scene = load_with(&repo("scenes/ptracer/ptracer_room.xml"), &[]);
    let options = RenderOptions {
        integrator: Some("depth".into()),
        ..RenderOptions::default()
    };
    let img = common::render(&device, &scene, &options, 256);
    assert_matches_reference(&img, &reference, "ptracer_room depth");
    // Rays that meet nothing: none in this room, whose walls fill the view.
    assert!(img.rgb.iter().all(|&v| v > 0.0));
}
