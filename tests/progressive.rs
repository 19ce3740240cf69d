//! Progressive rendering (`render::progressive`), what the viewer and `--tev` run on:
//! samples rendered in steps of any size are the render of those samples, a camera
//! move renders the new view and moving back renders the old one again.

mod common;

use wavetrace::render::film::FilmSums;
use wavetrace::render::{RenderOptions, Renderer};

fn cbox(res: u32) -> wavetrace::scene::Scene {
    let defines = [("res".to_string(), res.to_string())];
    wavetrace::scene::load(&common::repo("scenes/cbox/cbox_path.xml"), &defines)
        .expect("load the Cornell box")
}

/// Renders samples 0..spp in steps of at most `max_paths` paths.
fn in_steps(r: &mut Renderer, spp: u32, max_paths: u32) -> FilmSums {
    let mut p = r.start_progressive(Some(spp)).expect("start");
    let mut steps = 0;
    while !p.finished() {
        assert!(r.step(&mut p, max_paths).expect("step") > 0);
        steps += 1;
    }
    assert_eq!(r.step(&mut p, max_paths).expect("step after the end"), 0);
    assert_eq!(p.samples_done(), spp);
    assert!(steps >= 1);
    r.read_film().expect("read film")
}

#[test]
fn steps_of_any_size_render_the_same_samples() {
    let device = common::device();
    let scene = cbox(20);
    let mut r = Renderer::new(&device, &scene, &RenderOptions::default()).expect("renderer");
    let spp = 3;
    let (whole, _) = r.render_film(0, spp, &mut |_, _| {}).expect("render");
    // Runs of pixels smaller than a row, a sample and a half, whole samples.
    for max_paths in [37, 600, 4000] {
        let stepped = in_steps(&mut r, spp, max_paths);
        // film_gather adds every sample to a pixel in the same order whatever the
        // batching: the sums agree bit for bit.
        assert_eq!(stepped, whole, "steps of {max_paths} paths");
    }
}

#[test]
fn a_camera_move_renders_the_new_view_and_moving_back_the_old() {
    let device = common::device();
    let scene = cbox(16);
    let mut r = Renderer::new(&device, &scene, &RenderOptions::default()).expect("renderer");
    let home = in_steps(&mut r, 2, 1 << 20);
    let cam = &scene.camera;
    let turned = cam.to_world * glam::Mat4::from_rotation_y(0.3);
    r.set_camera(turned, cam.fov_x_deg).expect("turn");
    let moved = in_steps(&mut r, 2, 1 << 20);
    let diff: f32 = moved
        .sums
        .iter()
        .zip(&home.sums)
        .map(|(a, b)| (a[0] - b[0]).abs())
        .sum::<f32>()
        / home.sums.len() as f32;
    let mean: f32 = home.sums.iter().map(|s| s[0]).sum::<f32>() / home.sums.len() as f32;
    assert!(
        diff > 0.2 * mean,
        "turning barely changed the image ({diff} vs {mean})"
    );
    r.set_camera(cam.to_world, cam.fov_x_deg).expect("back");
    assert_eq!(
        in_steps(&mut r, 2, 1 << 20),
        home,
        "back home, the same image"
    );
    // A zoom changes the field of view the same way.
    r.set_camera(cam.to_world, cam.fov_x_deg * 0.5)
        .expect("zoom");
    assert_ne!(in_steps(&mut r, 2, 1 << 20), home);
    assert!(
        r.set_camera(cam.to_world, 0.0).is_err(),
        "a zero field of view"
    );
}

#[test]
fn photon_mappers_are_not_progressive() {
    let device = common::device();
    let scene = cbox(8);
    let options = RenderOptions {
        integrator: Some("sppm".into()),
        ..Default::default()
    };
    let mut r = Renderer::new(&device, &scene, &options).expect("renderer");
    assert!(!r.is_progressive());
    let e = r
        .start_progressive(Some(1))
        .err()
        .expect("an error")
        .to_string();
    assert!(e.contains("sppm") && e.contains("render"), "{e}");
}
