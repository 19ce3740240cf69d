//! Images against references: `ao` against a Mitsuba 3 render of the same scene file,
//! and the same scene written in both dialects.

mod common;

use common::{device, load, repo};
use wavetrace::image::metrics::{compare_blocks, rel_mse};
use wavetrace::image::read_exr;
use wavetrace::render::RenderOptions;

/// `scenes/ao/ao.xml` at 64 spp against `scenes/refs/ao.exr`, Mitsuba 3's `direct`
/// integrator under a constant emitter of radiance 1 with white diffuse BSDFs (made by
/// tools/mitsuba_ref.py --ao, see scenes/refs/README.md).
#[test]
fn ao_matches_the_mitsuba_reference() {
    let scene = load(&repo("scenes/ao/ao.xml"));
    let reference = read_exr(&repo("scenes/refs/ao.exr")).expect("reference EXR");
    let img = common::render(&device(), &scene, &RenderOptions::default(), 64);
    assert_eq!((img.width, img.height), (reference.width, reference.height));

    // Per 8x8 block and channel, z = difference of means over the standard error of
    // the render's block mean (the reference has 256x the samples, so its noise is
    // negligible). Noise alone gives mean z² ≈ 1 and, over 768 blocks x channels, a
    // largest |z| around 3.5; a missing cosine or a pdf off by 2 shifts whole regions
    // by tens of standard errors. Flat blocks (all pixels equal) get a floor of 1e-3.
    let c = compare_blocks(&img, &reference, 8, 1e-3);
    println!("{c:?}, relMSE {}", rel_mse(&img, &reference));
    assert!(
        c.mean_z2 < 1.6,
        "mean z² {} (noise gives ~1): {c:?}",
        c.mean_z2
    );
    assert!(
        c.max_abs_z < 6.0,
        "a block is {} standard errors off: {c:?}",
        c.max_abs_z
    );

    // And the same scene with a wrong estimator must fail this check: halving the
    // weight of one sampling strategy is what a pdf off by 2 does.
    let mut biased = img.clone();
    biased.rgb.iter_mut().for_each(|v| *v *= 0.9);
    let b = compare_blocks(&biased, &reference, 8, 1e-3);
    assert!(b.mean_z2 > 4.0, "the check cannot see a 10% bias: {b:?}");
}

/// The Nori-dialect file describes the same scene: the image is identical.
#[test]
fn nori_and_mitsuba_dialects_render_the_same_image() {
    let dev = device();
    let mitsuba = load(&repo("scenes/ao/ao.xml"));
    let nori = load(&repo("scenes/ao/ao_nori.xml"));
    let opts = RenderOptions::default();
    let a = common::render(&dev, &mitsuba, &opts, 4);
    let b = common::render(&dev, &nori, &opts, 4);
    assert_eq!(a.width, b.width);
    let worst = a
        .rgb
        .iter()
        .zip(&b.rgb)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0f32, f32::max);
    assert!(worst <= 1e-6, "images differ by up to {worst}");
}
