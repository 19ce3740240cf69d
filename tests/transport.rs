//! Light transport with closed-form answers: every direct-lighting and path-tracing
//! estimator must converge to the same known value, so a missing cosine, a pdf off by
//! a factor, a wrong MIS weight or a biased Russian roulette fails here.

mod common;

use common::{device, largest_relative_difference, mean, temp_file};
use wavetrace::gpu::Device;
use wavetrace::image::Image;
use wavetrace::render::{RenderOptions, RenderStats, SetupStats};
use wavetrace::scene::Scene;

/// A shipped scene (`file`, relative to the repository) with `defines`.
fn load_shipped(file: &str, defines: &[(&str, &str)]) -> Scene {
    let defines: Vec<(String, String)> = defines
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    wavetrace::scene::load(&common::repo(file), &defines).unwrap_or_else(|e| panic!("{file}: {e}"))
}

/// `scene` (loaded from `file`) rendered at 8 spp with `options`: the image, what the
/// render did and how its renderer was set up.
fn render_8spp(
    device: &Device,
    scene: &Scene,
    file: &str,
    options: &RenderOptions,
) -> (Image, RenderStats, SetupStats) {
    let mut r = wavetrace::render::Renderer::new(device, scene, options)
        .unwrap_or_else(|e| panic!("{file}: {e}"));
    let (img, stats) = r.render(8, &mut |_, _| {}).expect("render");
    (img, stats, r.setup.clone())
}

/// A Mitsuba scene with a 32x32 camera and a box filter: each pixel is an
/// independent estimate (a Gaussian would share samples among neighbours).
fn scene(camera: &str, fov: f32, body: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
    <sensor type="perspective">
        <float name="fov" value="{fov}"/>
        <transform name="to_world">{camera}</transform>
        <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/>
            <rfilter type="box"/></film>
    </sensor>
    {body}
</scene>"#
    )
}

/// Mean of the image and the standard error of that mean, from the spread of its
/// pixels (independent estimates; the scenes here have a constant true image).
struct Estimate {
    mean: f64,
    se: f64,
}

impl Estimate {
    /// Checks `expected` lies within 5 standard errors (a false failure has
    /// probability 6e-7 per check, for a mean of many independent pixels), and that
    /// the test is sharp: the standard error is below `max_rel_se` of the value, and
    /// the same check rejects `expected` x 0.95 (the power control: a 5% bias is seen).
    fn check(&self, expected: f64, max_rel_se: f64, what: &str) {
        let z = (self.mean - expected) / self.se.max(1e-12);
        println!(
            "{what}: {:.5} ± {:.5} (expected {expected}, z = {z:.2})",
            self.mean, self.se
        );
        assert!(
            z.abs() < 5.0,
            "{what}: {:.5} ± {:.5}, expected {expected} (z = {z:.1})",
            self.mean,
            self.se
        );
        assert!(
            self.se < max_rel_se * expected,
            "{what}: too noisy to test ({:.5})",
            self.se
        );
        let z_biased = (self.mean - 0.95 * expected) / self.se.max(1e-12);
        assert!(
            z_biased.abs() >= 5.0,
            "{what}: the check cannot see a 5% bias (z = {z_biased:.1} against {})",
            0.95 * expected
        );
    }
}

fn render_with(
    xml: &str,
    name: &str,
    integrator: &str,
    spp: u32,
    defines: &[(&str, &str)],
) -> Estimate {
    let path = temp_file("transport", &format!("{name}.xml"), xml);
    let defines: Vec<(String, String)> = defines
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    let s = wavetrace::scene::load(&path, &defines).unwrap_or_else(|e| panic!("{e}"));
    let opts = RenderOptions {
        integrator: Some(integrator.into()),
        ..Default::default()
    };
    let img = common::render(&device(), &s, &opts, spp);
    assert!(img.rgb.iter().all(|v| v.is_finite()));
    let m = mean(&img);
    let var =
        img.rgb.iter().map(|&v| (v as f64 - m).powi(2)).sum::<f64>() / (img.rgb.len() - 1) as f64;
    // Three channels of a grey scene are one estimate: count pixels, not values.
    let se = (var / (img.rgb.len() / 3) as f64).sqrt();
    Estimate { mean: m, se }
}

/// A closed box (2 x 1 x 3) whose walls all emit radiance 1 and reflect diffusely with
/// `albedo`, seen from inside; `max_depth` a scene default (2).
fn emissive_box(albedo: f32) -> String {
    let body = format!(
        r#"
    <default name="max_depth" value="2"/>
    <integrator type="path"><integer name="max_depth" value="$max_depth"/></integrator>
    <shape type="cube"><boolean name="flip_normals" value="true"/>
        <transform name="to_world"><scale value="2, 1, 3"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="{albedo}"/></bsdf>
        <emitter type="area"><rgb name="radiance" value="1"/></emitter>
    </shape>"#
    );
    // Looking at the middle of the far wall, away from edges, where emitter sampling
    // of an adjacent wall would have a heavy tail (1/d² at the corner).
    scene(
        r#"<lookat origin="0.3, 0.1, -1" target="0, 0, 1" up="0, 1, 0"/>"#,
        20.0,
        &body,
    )
}

/// Inside a closed box whose walls all emit radiance 1 and reflect diffusely with
/// albedo 1/2, the radiance of paths of at most D segments is 1 + 1/2 + ... + 1/2^(D-1)
/// everywhere, and 2 for unbounded paths.
#[test]
fn emissive_box_gives_the_geometric_series_for_every_estimator() {
    let xml = emissive_box(0.5);
    for (integrator, depth, spp, expected) in [
        ("direct_ems", "2", 16, 1.5),
        ("direct_mats", "2", 16, 1.5),
        ("direct_mis", "2", 16, 1.5),
        ("path_mats", "4", 16, 1.875),
        ("path_mis", "4", 16, 1.875),
        ("path_mis", "-1", 32, 2.0),
        ("path_mats", "-1", 32, 2.0),
    ] {
        let e = render_with(&xml, "box", integrator, spp, &[("max_depth", depth)]);
        e.check(expected, 0.01, &format!("{integrator} max_depth {depth}"));
    }
}

/// The emissive box again, with walls of albedo 0.97: unbounded paths converge to
/// 1 / (1 - 0.97) = 33.3 radiance. Paths cut at 64 bounces (the budget wavetrace once
/// had) would give (1 - 0.97^64) / 0.03 = 28.8, 13% low; Russian roulette must end the
/// paths instead, without bias.
#[test]
fn unbounded_paths_are_never_truncated() {
    let xml = emissive_box(0.97);
    for (integrator, spp) in [("path_mis", 64), ("path_mats", 64), ("vol_path_mis", 64)] {
        render_with(&xml, "bright_box", integrator, spp, &[("max_depth", "-1")]).check(
            1.0 / 0.03,
            0.01,
            &format!("{integrator}, unbounded"),
        );
    }
}

/// Paths that never end (walls of albedo 1, Russian roulette never starting) are cut
/// at the bounce budget, counted, and what they gathered until then is kept: radiance
/// 1 per segment, so the budget of 40 bounces reads 40 to 41. Without the budget the
/// render would never end.
#[test]
fn endless_paths_are_cut_at_the_budget_and_counted() {
    let body = r#"
    <integrator type="path"><integer name="max_depth" value="-1"/>
        <integer name="rr_depth" value="1000000"/></integrator>
    <shape type="cube"><boolean name="flip_normals" value="true"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf>
        <emitter type="area"><rgb name="radiance" value="1"/></emitter>
    </shape>"#;
    let xml = scene(
        r#"<lookat origin="0, 0, 0" target="0, 0, 1" up="0, 1, 0"/>"#,
        40.0,
        body,
    );
    let path = temp_file("transport", "endless.xml", &xml);
    let s = wavetrace::scene::load(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
    let dev = device();
    for (max_bounces, cut) in [(Some(40), 32 * 32 * 2), (None, 0)] {
        let opts = RenderOptions {
            integrator: Some("path_mis".into()),
            max_bounces,
            ..Default::default()
        };
        let mut r = wavetrace::render::Renderer::new(&dev, &s, &opts).expect("setup");
        if max_bounces.is_none() {
            // The default budget is far beyond what this test can afford to run.
            assert_eq!(
                r.bounce_budget(),
                wavetrace::render::integrator::MAX_BOUNCES
            );
            continue;
        }
        let (img, stats) = r.render(2, &mut |_, _| {}).expect("render");
        // All but the odd path that a grazing sample ends (a zero pdf).
        assert!(
            stats.cut_paths <= cut && stats.cut_paths >= cut - cut / 100,
            "{} of {cut} paths cut at {max_bounces:?} bounces",
            stats.cut_paths
        );
        let m = mean(&img);
        // 40 segments, plus the emitter-sampled (MIS) share of the 41st, whose BSDF-sampled
        // share the cut drops.
        assert!(
            (40.0..41.0).contains(&m),
            "cut paths keep their light: mean {m}"
        );
    }
}

/// A diffuse plane (albedo 1/2) under a sphere light of radiance 10, radius 1/2, whose
/// centre is 2 above the point seen: irradiance π L sin²α with sin α = r/d, so the
/// plane's radiance is ρ L (r/d)² = 0.3125.
#[test]
fn sphere_light_over_a_plane_matches_its_solid_angle() {
    let body = r#"
    <shape type="rectangle"><transform name="to_world"><scale value="100"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
    <shape type="sphere"><point name="center" value="0, 0, 2"/><float name="radius" value="0.5"/>
        <emitter type="area"><rgb name="radiance" value="10"/></emitter></shape>"#;
    // Looking at the origin from the side, over a 0.5° field: the patch seen is 0.03
    // wide, where (r/d)² and the cosine change by under 1e-4.
    let xml = scene(
        r#"<lookat origin="3, 0, 1.5" target="0, 0, 0" up="0, 0, 1"/>"#,
        0.5,
        body,
    );
    let expected = 0.5 * 10.0 * 0.0625;
    // BSDF sampling hits the light with probability sin²α = 1/16 only: more samples.
    for (integrator, spp) in [
        ("direct_mats", 256),
        ("direct_ems", 16),
        ("direct_mis", 16),
        ("path_mis", 16),
    ] {
        render_with(&xml, "sphere", integrator, spp, &[]).check(expected, 0.01, integrator);
    }
}

/// An open plane under a uniform sky of radiance 1 reflects ρ = 1/2.
#[test]
fn constant_environment_over_a_plane_reflects_its_albedo() {
    let body = r#"
    <shape type="rectangle"><transform name="to_world"><scale value="1000"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>"#;
    let xml = scene(
        r#"<lookat origin="0, 0, 2" target="0, 0, 0" up="0, 1, 0"/>"#,
        30.0,
        body,
    );
    for integrator in [
        "direct_ems",
        "direct_mats",
        "direct_mis",
        "path_mis",
        "path_mats",
    ] {
        render_with(&xml, "env", integrator, 64, &[]).check(0.5, 0.01, integrator);
    }
}

/// A point light and a spot light through the general emitter sampling: (ρ/π) I / d²
/// below the point light; the spot is at full intensity inside its beam and dark
/// outside its cutoff.
#[test]
fn point_and_spot_lights_follow_the_inverse_square_law() {
    let plane = r#"<shape type="rectangle"><transform name="to_world"><scale value="100"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>"#;
    let camera = r#"<lookat origin="0, 0, 10" target="0, 0, 0" up="0, 1, 0"/>"#;
    let point = format!(
        r#"{plane}<emitter type="point"><point name="position" value="0, 0, 2"/><rgb name="intensity" value="8"/></emitter>"#
    );
    let expected = 0.5 / std::f64::consts::PI * 8.0 / 4.0;
    // Over the 0.09-wide patch seen, cos θ / d² falls by 5e-4 on average from its
    // value below the light.
    let m = render_with(&scene(camera, 0.5, &point), "point", "direct_ems", 4, &[]).mean;
    assert!(
        (m - expected).abs() < 1e-3 * expected,
        "point: {m} vs {expected}"
    );
    let spot = format!(
        r#"{plane}<emitter type="spot"><transform name="to_world"><lookat origin="0, 0, 2" target="0, 0, 0" up="0, 1, 0"/></transform>
        <rgb name="intensity" value="8"/><float name="cutoff_angle" value="30"/></emitter>"#
    );
    let m = render_with(&scene(camera, 0.5, &spot), "spot", "path_mis", 4, &[]).mean;
    assert!(
        (m - expected).abs() < 1e-3 * expected,
        "spot on axis: {m} vs {expected}"
    );
    // Looking at a point 2 units off axis, 45° from the spot: outside its 30° cutoff.
    let off = r#"<lookat origin="2, 0, 10" target="2, 0, 0" up="0, 1, 0"/>"#;
    let m = render_with(&scene(off, 0.5, &spot), "spot_off", "direct_mis", 4, &[]).mean;
    assert_eq!(m, 0.0, "outside the cutoff");
}

/// Bounces that only end paths meet the emitters alone where a scene has few emitter
/// primitives and no environment (shaders/integrator/path_emitted.glsl): the same image as
/// tracing their rays through the whole BVH, bit for bit, and the shortcut does run
/// (no intersect dispatch for those bounces). Veach's plates under four sphere lights
/// (direct lighting), and textured sphere and rectangle lights (a path tracer of
/// max_depth 3).
#[test]
fn last_bounce_against_the_emitters_alone_matches_the_full_traversal() {
    let device = device();
    for (file, defines) in [
        (
            "scenes/veach/veach.xml",
            vec![("integrator", "direct"), ("res", "48")],
        ),
        ("scenes/textures/textured_lights.xml", vec![("res", "48")]),
    ] {
        let scene = load_shipped(file, &defines);
        let run = |trace_last_bounce: bool| {
            // The wavefront's kernels: on a CPU device first_bounce would run these
            // scenes' bounces in one kernel (first_bounce_in_one_kernel_matches_the_wavefront).
            let options = RenderOptions {
                seed: 3,
                timestamps: true,
                trace_last_bounce,
                wavefront: true,
                ..Default::default()
            };
            let (img, stats, _) = render_8spp(&device, &scene, file, &options);
            (img, stats.kernel_times.by_kernel["intersect"].1)
        };
        let (short, short_intersects) = run(false);
        let (full, full_intersects) = run(true);
        assert!(
            short_intersects < full_intersects,
            "{file}: the last bounce still ran intersect ({short_intersects} dispatches, \
             {full_intersects} tracing it)"
        );
        assert_eq!(short.non_finite_count(), 0, "{file}");
        assert!(mean(&short) > 0.0, "{file}: black image");
        assert_eq!(short.rgb, full.rgb, "{file}: the images differ");
    }
}

/// A case of [`first_bounce_in_one_kernel_matches_the_wavefront`]: (scene, defines,
/// integrator, max_bounces, a render of many paths, fused on a CPU).
type FusedCase = (
    &'static str,
    Vec<(&'static str, &'static str)>,
    Option<&'static str>,
    Option<u32>,
    bool,
    bool,
);

fn fused_cases() -> Vec<FusedCase> {
    let cbox = "scenes/cbox/cbox_path.xml";
    vec![
        (
            "scenes/veach/veach.xml",
            vec![("integrator", "direct"), ("res", "48")],
            None,
            None,
            false,
            true,
        ),
        (
            "scenes/textures/textured_lights.xml",
            vec![("res", "40")],
            Some("direct_mis"),
            None,
            false,
            true,
        ),
        (
            cbox,
            vec![("res", "40")],
            Some("direct_ems"),
            None,
            false,
            true,
        ),
        (
            cbox,
            vec![("res", "40"), ("max_depth", "1")],
            None,
            None,
            false,
            true,
        ),
        (cbox, vec![("res", "40")], None, Some(1), false, true),
        (cbox, vec![("res", "40")], None, None, true, true),
        (cbox, vec![("res", "40")], None, Some(3), true, true),
        (
            "scenes/glass/glass.xml",
            vec![("res", "32")],
            None,
            None,
            true,
            true,
        ),
        (cbox, vec![("res", "40")], None, None, false, false),
        (
            "scenes/textures/normalmap.xml",
            vec![("res", "40")],
            None,
            None,
            true,
            true,
        ),
        (
            "scenes/envmap/envmap_glossy.xml",
            vec![("res", "40")],
            None,
            None,
            true,
            false,
        ),
        (
            "scenes/filters/gaussian.xml",
            vec![("res", "32"), ("pixel_format", "rgba")],
            Some("direct_mats"),
            None,
            false,
            true,
        ),
        (
            "scenes/media/cube.xml",
            vec![("res", "32")],
            None,
            None,
            true,
            true,
        ),
        (
            "scenes/media/smoke.xml",
            vec![("res", "32")],
            None,
            None,
            true,
            true,
        ),
        (
            "scenes/media/thin_textured.xml",
            vec![("res", "32")],
            None,
            None,
            true,
            true,
        ),
        (
            "scenes/media/fog_point.xml",
            vec![("res", "32"), ("sampling", "equiangular")],
            None,
            None,
            true,
            true,
        ),
    ]
}

/// On a CPU device one kernel runs each path's first bounce (shaders/kernels/first_bounce.comp)
/// in place of generate, intersect, shade and shadow: the whole path where that is all
/// (direct lighting; a path tracer of max_depth 1, or cut after one bounce), else the
/// wavefront goes on from bounce 1 (path tracers, in renders of many paths): the same
/// image bit for bit, the same rays and cut paths, and the same alpha. Veach's plates
/// under sphere lights (the last bounce meeting the emitters alone), textured lights
/// (their textures in both bounces), the Cornell box with emitter sampling alone, at
/// max_depth 1, cut at one bounce, and path traced (fused only in a render of many
/// paths; there, as in the glass scene, every camera ray finds a surface and the kernel
/// shades bounce 1 too, its shadow rays left to the shadow kernel; also cut after
/// three bounces); the normal-mapped wall (path traced under an environment, over several
/// batches), and the filter scene's RGBA film (a Gaussian filter; which camera paths
/// cover their pixel). The glossy spheres under a lat-long map keep the wavefront:
/// 44% of their camera rays miss. In scenes with media the kernel runs the medium
/// stage and attenuates shadow rays too: the homogeneous cube (volpath, null boundary),
/// the smoke grid (delta and ratio tracking), a thin dielectric crossed as a null
/// surface in fog, and single scattering with equiangular sampling.
#[test]
fn first_bounce_in_one_kernel_matches_the_wavefront() {
    let device = device();
    let cpu = device.info().kind == wavetrace::gpu::DeviceKind::Cpu;
    let cases = fused_cases();
    for (file, defines, integrator, max_bounces, many, fuses) in cases {
        let scene = load_shipped(file, &defines);
        let run = |wavefront: bool| {
            let options = RenderOptions {
                seed: 7,
                timestamps: true,
                integrator: integrator.map(str::to_string),
                max_bounces,
                wavefront,
                // Sized as for 2048 spp (past FUSED_MIN_PATHS), in small batches.
                expected_spp: many.then_some(2048),
                max_batch_paths: many.then_some(4096),
                ..Default::default()
            };
            let mut r = wavetrace::render::Renderer::new(&device, &scene, &options)
                .unwrap_or_else(|e| panic!("{file}: {e}"));
            let (film, stats) = r.render_film(0, 8, &mut |_, _| {}).expect("render");
            (film.develop(), film.develop_alpha(), stats)
        };
        let (fused, fused_alpha, fused_stats) = run(false);
        let (wave, wave_alpha, wave_stats) = run(true);
        let ran =
            |stats: &RenderStats, kernel: &str| stats.kernel_times.by_kernel.contains_key(kernel);
        let case = format!("{file} {defines:?} {integrator:?}");
        assert!(
            ran(&wave_stats, "generate") && !ran(&wave_stats, "first_bounce"),
            "{case}"
        );
        assert_eq!(
            ran(&fused_stats, "first_bounce"),
            cpu && fuses,
            "{case}: fused"
        );
        assert_eq!(
            ran(&fused_stats, "generate"),
            !(cpu && fuses),
            "{case}: generate"
        );
        assert_eq!(fused.non_finite_count(), 0, "{case}");
        assert!(mean(&fused) > 0.0, "{case}: black image");
        assert_eq!(fused.rgb, wave.rgb, "{case}: the images differ");
        assert_eq!(fused_alpha, wave_alpha, "{case}: the alphas differ");
        assert_eq!(fused_stats.rays, wave_stats.rays, "{case}: rays traced");
        assert_eq!(
            fused_stats.cut_paths, wave_stats.cut_paths,
            "{case}: cut paths"
        );
        if max_bounces.is_some() {
            assert!(fused_stats.cut_paths > 0, "{case}: no path was cut");
        }
        if file.contains("gaussian") {
            assert!(
                fused_alpha.is_some_and(|a| a.contains(&0.0) && a.contains(&1.0)),
                "{case}"
            );
        }
    }
}

/// Scenes of a few primitives are traced without their BVH, each primitive tested in
/// turn (bvh.glsl's bvh_trace_flat): the same image as the traversal, bit for bit, in
/// every kernel that traces (intersect, shadow, and shade's media and emitter-only
/// last bounce). The normal-mapped wall and sphere (path tracer, environment), the
/// glossy spheres under a lat-long map, and a point light in fog (volumetric, the
/// media code of shade and shadow); the glass scene's 19 primitives are traversed.
/// Where the tree is traversed, a scene's few quadrics are tested apart before it
/// (accel::Bvh::apart): the sphere of the normal map, the fog and the glass scene,
/// the two of the env map scene. (On llvmpipe at 16 lanes reading the scene from
/// storage buffers the glass scene is tested in turn too: plan::flat_prims_max.)
#[test]
fn small_scenes_traced_without_the_tree_match_the_traversal() {
    let device = device();
    let flat_max = wavetrace::render::plan::flat_prims_max(device.info());
    for (file, defines, quadrics) in [
        ("scenes/textures/normalmap.xml", vec![("res", "40")], 1),
        ("scenes/envmap/envmap_glossy.xml", vec![("res", "40")], 2),
        ("scenes/media/fog_point.xml", vec![("res", "32")], 1),
        ("scenes/glass/glass.xml", vec![("res", "32")], 1),
    ] {
        let scene = load_shipped(file, &defines);
        let run = |traverse_small_scenes: bool| {
            let options = RenderOptions {
                seed: 5,
                traverse_small_scenes,
                ..Default::default()
            };
            let (img, _, setup) = render_8spp(&device, &scene, file, &options);
            (img, setup.flat.count, setup.flat.flat_only)
        };
        let (flat, flat_prims, flat_only) = run(false);
        let (tree, tree_flat_prims, tree_flat_only) = run(true);
        assert!(!tree_flat_only, "{file}: traversed flat when told not to");
        assert_eq!(tree_flat_prims, quadrics, "{file}: quadrics tested apart");
        assert_eq!(
            flat_only,
            !file.contains("glass") || flat_max >= 19,
            "{file}: {flat_prims} primitives tested in turn"
        );
        if !flat_only {
            assert_eq!(flat_prims, quadrics, "{file}: quadrics tested apart");
        }
        assert_eq!(flat.non_finite_count(), 0, "{file}");
        assert!(mean(&flat) > 0.0, "{file}: black image");
        assert_eq!(flat.rgb, tree.rgb, "{file}: the images differ");
    }
}

/// In scenes with null surfaces, shade and shadow leave the rays that must trace again
/// to full twins of themselves (shaders/queue/deferral.glsl): shade's rays untouched,
/// shadow rays as the rest of the ray from where they stopped, with the random numbers
/// their tracking drew. Deferring in every scene (`deferral: Some(true)`), the same
/// images up to float rounding (within 1e-5 relative; in practice a few values differ
/// in the last bit), and the same rays, as tracing inside the crossing loops: a
/// homogeneous cube (isotropic and g = 0.7), a grid medium (ratio tracking draws its
/// numbers on both sides of the deferral), two media inside a null sphere, a textured
/// thin dielectric (the null lobe's crossings), smoke in a Cornell box and single
/// scattering with equiangular sampling in fog inside a null sphere, in the wavefront
/// and (but for single scattering, whole in first_bounce) after the fused first
/// bounce, which traces in its loops. By default only the homogeneous scenes without
/// null spheres defer, and only on drivers where it pays (not Mesa 26's lavapipe:
/// DeviceInfo::deferral_pays).
#[test]
fn deferred_crossings_match_tracing_in_the_loop() {
    let device = device();
    for (file, defines, by_default) in [
        ("scenes/media/cube.xml", vec![("res", "32")], true),
        (
            "scenes/media/cube.xml",
            vec![("res", "32"), ("g", "0.7")],
            true,
        ),
        ("scenes/media/smoke.xml", vec![("res", "32")], false),
        ("scenes/media/two_media.xml", vec![("res", "32")], false),
        ("scenes/media/thin_textured.xml", vec![("res", "32")], true),
        ("scenes/media/cbox_smoke.xml", vec![("res", "32")], false),
        (
            "scenes/media/fog_point.xml",
            vec![("res", "32"), ("sampling", "equiangular")],
            false,
        ),
    ] {
        let scene = load_shipped(file, &defines);
        for fused in [false, true] {
            // Single scattering's two bounces run whole in first_bounce.
            if fused && file.contains("fog_point") {
                continue;
            }
            let run = |deferral: Option<bool>| {
                let options = RenderOptions {
                    seed: 3,
                    wavefront: !fused,
                    timestamps: true,
                    deferral,
                    // Fused: sized as for 2048 spp (past FUSED_MIN_PATHS), in small
                    // batches.
                    expected_spp: fused.then_some(2048),
                    max_batch_paths: fused.then_some(4096),
                    ..Default::default()
                };
                render_8spp(&device, &scene, file, &options)
            };
            let (deferring, stats, _) = run(Some(true));
            let (tracing, tracing_stats, _) = run(Some(false));
            let (_, default_stats, _) = run(None);
            let case = format!("{file} {defines:?} fused {fused}");
            let ran = |s: &RenderStats, k: &str| s.kernel_times.by_kernel.contains_key(k);
            assert!(ran(&stats, "shadow_deferred"), "{case}");
            assert!(ran(&stats, "shade_deferred"), "{case}");
            assert_eq!(ran(&stats, "first_bounce"), fused, "{case}");
            assert!(!ran(&tracing_stats, "shadow_deferred"), "{case}");
            assert!(stats.deferred > 0, "{case}: nothing was deferred");
            assert_eq!(tracing_stats.deferred, 0, "{case}");
            assert_eq!(
                ran(&default_stats, "shadow_deferred"),
                by_default && device.info().deferral_pays,
                "{case}: deferring by default"
            );
            assert_eq!(deferring.non_finite_count(), 0, "{case}");
            assert!(mean(&deferring) > 0.0, "{case}: black image");
            // A deferred shadow ray's contribution is multiplied by the transmittance
            // up to where it stopped, then by the rest: the product rounds otherwise.
            let largest = largest_relative_difference(&deferring, &tracing);
            assert!(
                largest <= 1e-5,
                "{case}: values differ by up to {largest} (relative)"
            );
            assert_eq!(stats.rays, tracing_stats.rays, "{case}: rays traced");
        }
    }
}
