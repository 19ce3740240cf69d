//! Composite BSDFs (`mask`, `blendbsdf`, `twosided` with two sides, `bumpmap`:
//! src/scene/bsdf/composite.rs) against Mitsuba 3 itself, and a white furnace.
//!
//! The scene (tests/data/composite_bsdfs.xml) holds every composite, with textured
//! weights, a `<ref>` nested in a blend and a twosided pair seen from both sides;
//! its reference is Mitsuba 3.9.1's render (`python3 tools/mitsuba_ref.py
//! tests/data/composite_bsdfs.xml -o tests/data/composite_bsdfs_ref.exr --spp 4096
//! --variant scalar_rgb`). Blends and masks mix both children as Mitsuba's do.
//!
//! The furnace: under a constant environment of radiance 1, closed shapes whose BSDFs
//! keep all energy (white diffuse, a dielectric, a mask's pass-through) leave every
//! pixel at 1 with an unbounded path length; a blend, a mask, a twosided pair and a
//! twosided around a blend of such models must too.

mod common;

use common::{assert_matches_reference_at, device, repo, temp_file};
use wavetrace::image::Image;
use wavetrace::render::RenderOptions;

#[test]
fn composites_render_as_mitsuba() {
    let scene = common::load(&repo("tests/data/composite_bsdfs.xml"));
    let reference = Image::read_exr(repo("tests/data/composite_bsdfs_ref.exr"))
        .expect("tests/data/composite_bsdfs_ref.exr");
    let img = common::render(&device(), &scene, &RenderOptions::default(), 256);
    assert_eq!(img.non_finite_count(), 0);
    assert_matches_reference_at(&img, &reference, "composite BSDFs, path, 256 spp", 0.01);
}

/// A furnace scene: a constant environment of radiance 1 and four spheres with
/// `bsdfs` (XML), seen by a 32 x 32 camera, path tracing without a depth limit.
fn furnace_scene(name: &str, bsdfs: [&str; 4]) -> std::path::PathBuf {
    let spheres: String = bsdfs
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let (x, y) = ([-0.55, 0.55][i % 2], [-0.55, 0.55][i / 2]);
            format!(
                r#"<shape type="sphere"><point name="center" value="{x}, {y}, 0"/><float name="radius" value="0.5"/>{b}</shape>"#
            )
        })
        .collect();
    let xml = format!(
        r#"<scene version="3.0.0">
<integrator type="path"><integer name="max_depth" value="-1"/></integrator>
<sensor type="perspective"><float name="fov" value="40"/>
<transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
<film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/><rfilter type="box"/></film>
</sensor>
<emitter type="constant"><rgb name="radiance" value="1"/></emitter>
{spheres}
</scene>"#
    );
    temp_file("composite_furnace", name, &xml)
}

/// Mean and largest deviation from 1 of the 8 x 8 blocks' means.
fn block_deviation(img: &Image) -> (f64, f64) {
    let small = common::downsample(img, 8);
    let worst = small
        .rgb
        .iter()
        .map(|&v| (v as f64 - 1.0).abs())
        .fold(0.0, f64::max);
    (common::mean(img), worst)
}

#[test]
fn blend_mask_and_twosided_keep_a_white_furnace() {
    const WHITE: &str = r#"<bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf></bsdf>"#;
    let blend = format!(
        r#"<bsdf type="blendbsdf"><float name="weight" value="0.4"/>{WHITE}<bsdf type="dielectric"/></bsdf>"#
    );
    let mask = format!(
        r#"<bsdf type="mask"><texture type="checkerboard" name="opacity"><rgb name="color0" value="0.2"/><rgb name="color1" value="0.9"/></texture>{WHITE}</bsdf>"#
    );
    let pair = r#"<bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf><bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf></bsdf>"#;
    let around = r#"<bsdf type="twosided"><bsdf type="blendbsdf"><float name="weight" value="0.7"/><bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf><bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf></bsdf></bsdf>"#;
    let device = device();
    let render = |path: std::path::PathBuf| {
        let scene = common::load(&path);
        common::render(&device, &scene, &RenderOptions::default(), 256)
    };
    let img = render(furnace_scene("white.xml", [&blend, &mask, pair, around]));
    let (mean, worst) = block_deviation(&img);
    println!("furnace: mean {mean:.4}, worst 8x8 block off by {worst:.4}");
    // 256 spp x 64 pixels per block of a furnace whose paths carry a weight of 1
    // until Russian roulette (at most 1/0.99 after it): a block's mean has a standard
    // error well below 0.005, so 0.02 is more than 4 sigma.
    assert!(
        worst < 0.02 && (mean - 1.0).abs() < 0.005,
        "mean {mean}, worst {worst}"
    );
    // The power control: a blend whose diffuse child keeps 90% is seen.
    let grey = blend.replace(
        r#"value="1"/></bsdf></bsdf><bsdf type="dielectric"/>"#,
        r#"value="0.9"/></bsdf></bsdf><bsdf type="dielectric"/>"#,
    );
    assert_ne!(grey, blend);
    let img = render(furnace_scene("grey.xml", [&grey, &grey, &grey, &grey]));
    let (mean, worst) = block_deviation(&img);
    println!("grey blend: mean {mean:.4}, worst 8x8 block off by {worst:.4}");
    assert!(worst > 0.05, "the furnace does not see a 10% loss: {worst}");
}
