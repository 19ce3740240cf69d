//! Mitsuba 3's own render regression suite (mitsuba-data `tests/scenes`, beside the
//! project in `../shared/scenes/mitsuba/regression/`; its SOURCES.txt gives the commit),
//! judged as Mitsuba's `src/render/tests/test_renders.py` judges its own variants.
//!
//! Per scene `<folder>/<name>_<integrator>.xml` with `refs/<name>_ref_rgb.exr` and
//! `refs/<name>_ref_rgb_var.exr` (the per-sample variance): render with the integrator
//! of the file name (passed as the `integrator` define, with `spp`), at
//! spp = 2,000,000 / pixel count, seed 0; convert image, reference and variance to XYZ
//! (linear sRGB primaries, as `Bitmap::convert`); per pixel-channel
//! z = |img - ref| * sqrt(spp / max(var, 1e-4)), p = 2 (1 - Phi(z)); with the Sidak
//! level alpha = 1 - (1 - 0.01)^(1 / pixel count), accept when the pixel-channels with
//! p > alpha, divided by 3, are at least 99.75% of the pixel count.
//!
//! Each scene also checks the criterion's power: the render scaled by 1.05 must be
//! rejected ([`Power::Rejects`]), except where a scene says why it cannot be
//! ([`Power::Blind`]: various_emitters).
//!
//! Scenes wavetrace does not render right yet are `#[ignore]`d with the reason; run
//! them all with `cargo test --test mitsuba_regression_suite -- --include-ignored
//! --nocapture`, which prints a table row per scene (`| scene | pass | fraction |
//! energy | 1.05x |`). `WAVETRACE_REGRESSION_SPP_SCALE` (default 1) scales the sample
//! count; the statistic uses the spp rendered, so the criterion stays the same.
//!
//! The participating-media folder of the suite (`../shared/scenes/mitsuba/media/`) has
//! no variance images: `media_mitsuba_test_scenes.rs` tests it with a block t-test.

mod common;

use std::path::PathBuf;
use std::time::Instant;

use common::device;
use wavetrace::image::Image;
use wavetrace::render::RenderOptions;

/// Mitsuba's `test_renders.py` constants.
const SAMPLES_PER_IMAGE: u64 = 2_000_000;
const ALPHA: f64 = 0.01;
const ACCEPT_FRACTION: f64 = 0.9975;
const MIN_VARIANCE: f64 = 1e-4;

/// Whether the criterion can see a 5% error in a scene.
#[derive(Clone, Copy)]
enum Power {
    /// The render scaled by 1.05 must be rejected.
    Rejects,
    /// It cannot be; the scene's comment says why (its row still prints the outcome).
    Blind,
}

/// What the criterion says about one image.
struct Verdict {
    /// Fraction of pixel-channels whose p-value exceeds the Sidak level.
    fraction: f64,
    passes: bool,
}

fn suite(rel: &str) -> PathBuf {
    common::repo("../shared/scenes/mitsuba/regression/tests/scenes").join(rel)
}

/// Linear sRGB (Rec. 709, D65) to CIE XYZ, as Mitsuba's `srgb_to_xyz`.
fn to_xyz(rgb: &[f32]) -> [f64; 3] {
    let (r, g, b) = (rgb[0] as f64, rgb[1] as f64, rgb[2] as f64);
    [
        0.412453 * r + 0.357580 * g + 0.180423 * b,
        0.212671 * r + 0.715160 * g + 0.072169 * b,
        0.019334 * r + 0.119193 * g + 0.950227 * b,
    ]
}

/// The standard normal's upper tail, 1 - Phi(z).
fn normal_sf(z: f64) -> f64 {
    0.5 * erfc(z / std::f64::consts::SQRT_2)
}

/// Complementary error function, Numerical Recipes' `erfcc` (Chebyshev fit, relative
/// error below 1.2e-7 everywhere), ample for p-values against alpha ~ 4e-6.
fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let ans = t
        * (-z * z - 1.26551223
            + t * (1.00002368
                + t * (0.37409196
                    + t * (0.09678418
                        + t * (-0.18628806
                            + t * (0.27886807
                                + t * (-1.13520398
                                    + t * (1.48851587 + t * (-0.82215223 + t * 0.17087277)))))))))
            .exp();
    if x >= 0.0 {
        ans
    } else {
        2.0 - ans
    }
}

/// Mitsuba's Z-test of `img` (scaled by `scale`) against `reference` and its per-sample
/// `variance` at `spp`.
fn z_test(img: &Image, reference: &Image, variance: &Image, spp: u32, scale: f32) -> Verdict {
    let pixels = (img.width * img.height) as usize;
    let alpha = 1.0 - (1.0 - ALPHA).powf(1.0 / pixels as f64);
    let mut accepted = 0usize;
    for i in 0..pixels {
        let px: Vec<f32> = img.rgb[3 * i..3 * i + 3]
            .iter()
            .map(|v| v * scale)
            .collect();
        let x = to_xyz(&px);
        let r = to_xyz(&reference.rgb[3 * i..3 * i + 3]);
        let v = to_xyz(&variance.rgb[3 * i..3 * i + 3]);
        for c in 0..3 {
            let z = (x[c] - r[c]).abs() * (spp as f64 / v[c].max(MIN_VARIANCE)).sqrt();
            let p = 2.0 * normal_sf(z);
            // A NaN pixel fails, as in Mitsuba (NaN > alpha is false).
            if p > alpha {
                accepted += 1;
            }
        }
    }
    let fraction = accepted as f64 / (3 * pixels) as f64;
    Verdict {
        fraction,
        passes: fraction >= ACCEPT_FRACTION,
    }
}

/// Renders `<folder>/<file>` as Mitsuba's test does and applies its criterion; prints
/// the scene's table row; panics unless it passes and (with [`Power::Rejects`]) the
/// render scaled by 1.05 fails.
fn check(folder: &str, file: &str, power: Power) {
    let stem = file.strip_suffix(".xml").expect("an .xml scene");
    let (name, integrator) = stem.rsplit_once('_').expect("<name>_<integrator>.xml");
    let scene_path = suite(&format!("{folder}/{file}"));
    assert!(
        scene_path.is_file(),
        "{} is missing: Mitsuba's regression suite lives in ../shared/scenes/mitsuba/regression",
        scene_path.display()
    );
    let read = |suffix: &str| {
        let path = suite(&format!("{folder}/refs/{name}_{suffix}.exr"));
        Image::read_exr(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    };
    let (reference, variance) = (read("ref_rgb"), read("ref_rgb_var"));
    let pixels = reference.width as u64 * reference.height as u64;
    let scale: f64 = std::env::var("WAVETRACE_REGRESSION_SPP_SCALE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0);
    let spp = (((SAMPLES_PER_IMAGE / pixels) as f64 * scale) as u32).max(1);
    let t = Instant::now();
    let spp_text = spp.to_string();
    let scene = common::load_with(
        &scene_path,
        &[("spp", &spp_text), ("integrator", integrator)],
    );
    let options = RenderOptions {
        expected_spp: Some(spp),
        ..RenderOptions::default()
    };
    let img = common::render(&device(), &scene, &options, spp);
    assert_eq!(
        (img.width, img.height),
        (reference.width, reference.height),
        "{name}: image size"
    );
    let verdict = z_test(&img, &reference, &variance, spp, 1.0);
    let scaled = z_test(&img, &reference, &variance, spp, 1.05);
    let energy = common::mean(&img) / common::mean(&reference);
    println!(
        "| {folder}/{name} | {} | {:.4} | {energy:.4} | {} | {spp} spp, {:.1} s |",
        if verdict.passes { "pass" } else { "FAIL" },
        verdict.fraction,
        if scaled.passes {
            "not rejected"
        } else {
            "rejected"
        },
        t.elapsed().as_secs_f64()
    );
    assert!(
        verdict.passes,
        "{folder}/{name}: {:.4} of the pixel-channels pass Mitsuba's Z-test, below {ACCEPT_FRACTION} \
         (energy ratio {energy:.4})",
        verdict.fraction
    );
    if let Power::Rejects = power {
        assert!(
            !scaled.passes,
            "{folder}/{name}: the render scaled by 1.05 still passes ({:.4}): the criterion \
             cannot see a 5% error here",
            scaled.fraction
        );
    }
}

/// One test per scene: `scene!(test_name, folder, file, power)`, with
/// `#[ignore = "..."]` before it where wavetrace does not pass it yet.
macro_rules! scene {
    ($(#[$attr:meta])* $test:ident, $folder:literal, $file:literal, $power:ident) => {
        $(#[$attr])*
        #[test]
        fn $test() {
            check($folder, $file, Power::$power);
        }
    };
}

// bsdf_spheres: a grid of spheres (or one) under an area light, an environment map and a
// point light, path tracing at max_depth 2, 48x48 pixels.
scene!(
    arealight,
    "bsdf_spheres",
    "test_arealight_path.xml",
    Rejects
);
scene!(bumpmap, "bsdf_spheres", "test_bumpmap_path.xml", Rejects);
scene!(constant, "bsdf_spheres", "test_constant_path.xml", Rejects);
scene!(envmap, "bsdf_spheres", "test_envmap_path.xml", Rejects);
scene!(
    normalmap_identity_roughconductor,
    "bsdf_spheres",
    "test_normalmap_identity_roughconductor_path.xml",
    Rejects
);
scene!(
    normalmap,
    "bsdf_spheres",
    "test_normalmap_path.xml",
    Rejects
);
scene!(
    normalmap_roughconductor,
    "bsdf_spheres",
    "test_normalmap_roughconductor_path.xml",
    Rejects
);
scene!(
    pointlight,
    "bsdf_spheres",
    "test_pointlight_path.xml",
    Rejects
);
scene!(
    roughdielectric,
    "bsdf_spheres",
    "test_roughdielectric_path.xml",
    Rejects
);
scene!(
    roughplastic_linear,
    "bsdf_spheres",
    "test_roughplastic_linear_path.xml",
    Rejects
);
scene!(
    roughplastic_nonlinear,
    "bsdf_spheres",
    "test_roughplastic_nonlinear_path.xml",
    Rejects
);
scene!(
    textured_diffuse,
    "bsdf_spheres",
    "test_textured_diffuse_path.xml",
    Rejects
);
scene!(
    // a-C loads (Mitsuba's RGB values) and matches Mitsuba with a constant alpha; the
    // checkerboard-textured alpha does not (fraction 0.747, energy 1.0013; also
    // isotropic): where the checker cells fall or how they are read.
    textured_roughconductor,
    "bsdf_spheres",
    "test_textured_roughconductor_path.xml",
    Rejects
);
scene!(
    texturedprincipled1,
    "bsdf_spheres",
    "test_texturedprincipled1_path.xml",
    Rejects
);
scene!(
    texturedprincipled2,
    "bsdf_spheres",
    "test_texturedprincipled2_path.xml",
    Rejects
);
scene!(
    texturedprincipledthin,
    "bsdf_spheres",
    "test_texturedprincipledthin_path.xml",
    Rejects
);

// The other folders.
scene!(
    floating_sphere,
    "floating_sphere",
    "test_directional_direct.xml",
    Rejects
);
scene!(
    infinite_mirrors,
    "infinite_mirrors",
    "scene_path.xml",
    Rejects
);
scene!(
    instancing,
    "instancing",
    "test_instancing_path.xml",
    Rejects
);
scene!(
    mesh_attributes_1_face,
    "mesh_attributes",
    "test_mesh_attributes_1_face_direct.xml",
    Rejects
);
scene!(
    mesh_attributes_3_face,
    "mesh_attributes",
    "test_mesh_attributes_3_face_direct.xml",
    Rejects
);
scene!(
    mesh_attributes_3_vertex,
    "mesh_attributes",
    "test_mesh_attributes_3_vertex_direct.xml",
    Rejects
);
scene!(
    orthographic,
    "orthographic_sensor",
    "test_orthographic_path.xml",
    Rejects
);
scene!(
    projector_constant,
    "projector",
    "test_projector_constant_direct.xml",
    Rejects
);
scene!(
    projector_textured,
    "projector",
    "test_projector_textured_direct.xml",
    Rejects
);
scene!(spot, "spot_light", "test_spot_direct.xml", Rejects);
scene!(
    texture_interp,
    "texture_interp",
    "test_texture_interp_direct.xml",
    Rejects
);
// The particle tracer at 61 spp (2,000,000 / 512 x 64 pixels): a light path reaches a
// pixel rarely, so the reference's per-sample variance is large against its mean and a
// 5% shift moves z by far less than the Sidak threshold (1.05x passes at 0.9992, as the
// render does): at the criterion's sample count this scene cannot see a 5% error.
scene!(
    various_emitters,
    "various_emitters",
    "test_various_emitters_ptracer.xml",
    Blind
);
scene!(
    various_shapes,
    "various_shapes",
    "test_various_shapes_path.xml",
    Rejects
);
