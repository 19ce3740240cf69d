//! Renders with analytic answers: each test would fail on a missing cosine, a wrong
//! pdf, a camera flipped left-right, or a sample that depends on batching.

mod common;

use common::{device, load, mean, pixel, render, temp_file};
use wavetrace::render::{RenderOptions, Renderer};

/// A Mitsuba scene: camera at `origin` looking at `target`, 32x32, and `shapes`.
fn scene(origin: &str, target: &str, up: &str, fov: f32, integrator: &str, shapes: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
    {integrator}
    <sensor type="perspective">
        <float name="fov" value="{fov}"/>
        <transform name="to_world"><lookat origin="{origin}" target="{target}" up="{up}"/></transform>
        <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/></film>
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
    </sensor>
    {shapes}
</scene>"#
    )
}

/// Renders samples 0..spp of a scene written to a temporary file, default options.
fn render_xml(test: &str, name: &str, xml: &str, spp: u32) -> wavetrace::image::Image {
    render(
        &device(),
        &load(&temp_file(test, name, xml)),
        &RenderOptions::default(),
        spp,
    )
}

const GROUND: &str = r#"<shape type="rectangle"><transform name="to_world"><scale value="100"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>"#;

#[test]
fn ao_of_an_open_plane_is_exactly_one_with_cosine_sampling() {
    let xml = scene(
        "0, 0, 5",
        "0, 0, 0",
        "0, 1, 0",
        40.0,
        r#"<integrator type="ao"/>"#,
        GROUND,
    );
    let img = render_xml("ao_plane", "scene.xml", &xml, 4);
    // cos θ / π over the cosine pdf cos θ / π is exactly 1 for every unoccluded sample.
    for (i, v) in img.rgb.iter().enumerate() {
        assert!((v - 1.0).abs() < 1e-6, "value {v} at {i}");
    }
}

#[test]
fn ao_of_an_open_plane_averages_one_with_uniform_sampling() {
    let integrator =
        r#"<integrator type="ao"><string name="sampling" value="uniform"/></integrator>"#;
    let xml = scene("0, 0, 5", "0, 0, 0", "0, 1, 0", 40.0, integrator, GROUND);
    let img = render_xml("ao_uniform", "scene.xml", &xml, 64);
    // Estimator 2 cos θ under uniform sampling: mean 1, variance 4/3 - 1 = 1/3. Over
    // 32*32*64 samples the mean's standard deviation is 0.0023; allow 5 of them.
    let m = mean(&img);
    assert!((m - 1.0).abs() < 0.0115, "mean {m}");
    // The samples really are noisy (not a constant weight).
    let var = img.rgb.iter().map(|&v| (v as f64 - m).powi(2)).sum::<f64>() / img.rgb.len() as f64;
    assert!(var > 1e-4, "variance {var}");
}

#[test]
fn ao_next_to_a_large_wall_is_one_half() {
    // A point on the floor beside an (effectively) infinite wall sees half of the
    // cosine-weighted hemisphere: AO = 1/2 wherever the wall is far larger than the
    // distance to it.
    let wall = r#"<shape type="rectangle"><transform name="to_world"><scale value="1000"/>
            <rotate y="1" angle="90"/></transform></shape>"#;
    let floor = r#"<shape type="rectangle"><transform name="to_world"><scale value="1000"/>
            <rotate x="1" angle="-90"/></transform></shape>"#;
    let xml = scene(
        "0.5, 2, 0",
        "0.5, 0, 0",
        "0, 0, 1",
        10.0,
        r#"<integrator type="ao"/>"#,
        &format!("{wall}{floor}"),
    );
    let img = render_xml("ao_wall", "scene.xml", &xml, 64);
    // 32*32*64 binary-ish samples of mean 1/2: sd of the mean < 0.002; the finite wall
    // (1000 units at distance < 1) lets through less than 0.1%.
    let m = mean(&img);
    assert!((m - 0.5).abs() < 0.01, "mean {m}");
}

#[test]
fn ao_inside_a_closed_box_is_black_unless_max_t_limits_occluders() {
    let cube =
        r#"<shape type="cube"><transform name="to_world"><scale value="10"/></transform></shape>"#;
    let dark = scene(
        "0, 0, 0",
        "0, 0, 1",
        "0, 1, 0",
        60.0,
        r#"<integrator type="ao"/>"#,
        cube,
    );
    let img = render_xml("ao_box", "dark.xml", &dark, 4);
    assert_eq!(
        mean(&img),
        0.0,
        "every occlusion ray inside a closed box hits a wall"
    );
    let limited = r#"<integrator type="ao"><float name="max_t" value="0.5"/></integrator>"#;
    let lit = scene("0, 0, 0", "0, 0, 1", "0, 1, 0", 60.0, limited, cube);
    let img = render_xml("ao_box", "lit.xml", &lit, 16);
    // Far from edges nothing lies within 0.5 of the wall: the centre pixel is 1.
    assert!((pixel(&img, 16, 16)[0] - 1.0).abs() < 1e-6);
    assert!(mean(&img) > 0.9, "mean {}", mean(&img));
}

#[test]
fn simple_point_light_follows_the_inverse_square_cosine_law() {
    // Light 2 units above the plane, intensity 8 W/sr, reflectance 0.5: straight below
    // it L = (ρ/π) I cos θ / d² = (0.5/π) * 8 / 4.
    let light = r#"<emitter type="point"><point name="position" value="0, 0, 2"/>
        <rgb name="intensity" value="8"/></emitter>"#;
    let xml = scene(
        "0, 0, 10",
        "0, 0, 0",
        "0, 1, 0",
        0.5,
        r#"<integrator type="simple"/>"#,
        &format!("{GROUND}{light}"),
    );
    let img = render_xml("simple", "scene.xml", &xml, 4);
    let expected = 0.5 / std::f32::consts::PI * 8.0 / 4.0;
    let c = pixel(&img, 16, 16)[0];
    // The pixel covers a 0.0027-wide patch: cos θ / d² varies by < 1e-5 over it.
    assert!((c - expected).abs() < 1e-4 * expected, "{c} vs {expected}");
}

#[test]
fn camera_keeps_world_left_on_the_image_left() {
    // Looking down -z with +y up, world +x is on the image's right. A point light near
    // the plane at x = +3 lights the right half more.
    let light = r#"<emitter type="point"><point name="position" value="3, 0, 0.5"/>
        <rgb name="intensity" value="1"/></emitter>"#;
    let xml = scene(
        "0, 0, 10",
        "0, 0, 0",
        "0, 1, 0",
        60.0,
        r#"<integrator type="simple"/>"#,
        &format!("{GROUND}{light}"),
    );
    let img = render_xml("orient", "scene.xml", &xml, 1);
    let (l, r) = (pixel(&img, 2, 16)[0], pixel(&img, 29, 16)[0]);
    assert!(
        r > 10.0 * l,
        "right {r} should be far brighter than left {l}"
    );
    // And +y is up: a light at y = +3 lights the top rows.
    let light = light.replace("3, 0, 0.5", "0, 3, 0.5");
    let xml = scene(
        "0, 0, 10",
        "0, 0, 0",
        "0, 1, 0",
        60.0,
        r#"<integrator type="simple"/>"#,
        &format!("{GROUND}{light}"),
    );
    let img = render_xml("orient", "scene_y.xml", &xml, 1);
    let (t, b) = (pixel(&img, 16, 2)[0], pixel(&img, 16, 29)[0]);
    assert!(
        t > 10.0 * b,
        "top {t} should be far brighter than bottom {b}"
    );
}

#[test]
fn normals_of_a_plane_facing_the_camera_are_plus_z() {
    let xml = scene(
        "0, 0, 5",
        "0, 0, 0",
        "0, 1, 0",
        30.0,
        r#"<integrator type="normals"/>"#,
        GROUND,
    );
    let img = render_xml("normals", "scene.xml", &xml, 1);
    for p in img.rgb.chunks(3) {
        assert!(
            p[0].abs() < 1e-5 && p[1].abs() < 1e-5 && (p[2] - 1.0).abs() < 1e-5,
            "{p:?}"
        );
    }
}

/// A render is a function of (scene, seed, sample range) alone: batch size and
/// splitting the range change nothing, and the seed changes the noise.
#[test]
fn samples_do_not_depend_on_batching_or_range_splits() {
    let bunny = load(&common::repo("../shared/scenes/nori/bunny/bunny.xml"));
    let mut bunny = bunny;
    bunny.camera.width = 48;
    bunny.camera.height = 40;
    let dev = device();
    let opts = RenderOptions {
        integrator: Some("ao".into()),
        ..Default::default()
    };
    let whole = render(&dev, &bunny, &opts, 4);
    // Batches of 500 paths: a batch is part of one sample of the pixels.
    let small = RenderOptions {
        max_batch_paths: Some(500),
        ..opts.clone()
    };
    let batched = render(&dev, &bunny, &small, 4);
    assert_eq!(whole.rgb, batched.rgb, "batch size changed the image");

    // Ranges rendered apart merge into the whole (the film's weighted sums add up;
    // bunny.xml names no filter: Nori's Gaussian).
    let mut r = Renderer::new(&dev, &bunny, &opts).unwrap();
    let mut a = r.render_film(0, 1, &mut |_, _| {}).unwrap().0;
    let b = r.render_film(1, 3, &mut |_, _| {}).unwrap().0;
    a.merge(&b).unwrap();
    let combined = a.develop();
    for i in 0..whole.rgb.len() {
        assert!(
            (combined.rgb[i] - whole.rgb[i]).abs() < 1e-5,
            "pixel value {i}: {} vs {}",
            combined.rgb[i],
            whole.rgb[i]
        );
    }

    let other = render(&dev, &bunny, &RenderOptions { seed: 1, ..opts }, 4);
    assert_ne!(whole.rgb, other.rgb, "the seed must change the noise");
}

/// A convex shape alone never occludes itself: its AO is exactly 1 wherever it is
/// seen (cosine sampling weighs every unoccluded sample 1). The camera is close enough
/// that the shape fills the view (seeing the cube's edges too), so any
/// self-intersection of an occlusion ray shows as a pixel below 1. Checked from a
/// millimetre to ten kilometres, at the origin and far from it.
#[test]
fn convex_shapes_never_occlude_themselves_at_any_scale() {
    let dev = device();
    for (scale, offset) in [
        (1e-3f32, 0.0f32),
        (1.0, 0.0),
        (1e4, 0.0),
        (1.0, 1e4),
        (1e-2, 1e3),
    ] {
        for shape in ["sphere", "cube"] {
            let shape_xml = format!(
                r#"<shape type="{shape}"><transform name="to_world"><rotate x="0.70710678" y="0.70710678" z="0" angle="30"/>
                    <scale value="{scale}"/><translate value="{offset}, {offset}, 0"/></transform></shape>"#
            );
            let (o, t) = (
                format!("{offset}, {offset}, {}", 2.5 * scale),
                format!("{offset}, {offset}, 0"),
            );
            let xml = scene(&o, &t, "0, 1, 0", 20.0, r#"<integrator type="ao"/>"#, &shape_xml).replace(
                r#"<float name="fov""#,
                &format!(
                    r#"<float name="near_clip" value="{}"/><float name="far_clip" value="{}"/><float name="fov""#,
                    0.01 * scale,
                    100.0 * scale
                ),
            );
            let s = load(&temp_file(
                "convex",
                &format!("{shape}{scale}{offset}.xml"),
                &xml,
            ));
            let img = render(&dev, &s, &RenderOptions::default(), 16);
            let worst = img.rgb.iter().fold(1.0f32, |m, &v| m.min(v));
            assert!(
                worst > 1.0 - 1e-6,
                "{shape} at scale {scale} offset {offset}: self-occlusion, AO {worst}"
            );
        }
    }
}
