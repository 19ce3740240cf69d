//! Mitsuba's `aov` and `moment` integrators and `render --aov`
//! (scene::integrator::aov, shaders/kernels/aov.comp): channel names and values
//! against Mitsuba 3.9.1's on tests/data/aov/aov_scene.xml (reference by
//! tests/data/aov/make_ref.py), the radiance untouched by AOVs, the second moment
//! against the samples' variance, and errors for bad `aovs` strings.

mod common;

use common::aov_channels::{self, channel};
use common::{device, load_with, repo, temp_dir, temp_file, wavetrace};
use wavetrace::image::exr;
use wavetrace::render::film::FilmSums;
use wavetrace::render::{RenderOptions, Renderer};
use wavetrace::scene::integrator::aov::parse_cli;

fn film(scene: &wavetrace::scene::Scene, options: &RenderOptions, spp: u32) -> FilmSums {
    let device = device();
    let mut r = Renderer::new(&device, scene, options).expect("renderer");
    let count = r.round_sample_count(spp).expect("count");
    r.set_sample_count(count).expect("count");
    r.render_film(0, spp, &mut |_, _| {}).expect("render").0
}

/// At 1 spp of the unjittered stratified sampler every camera ray goes through its
/// pixel's centre in both renderers (wavetrace's within 1/65536 of a pixel: its film
/// positions are kept in 1/32768 cells), so the AOVs agree up to float rounding.
#[test]
fn aov_channels_match_mitsuba_at_pixel_centres() {
    let dir = temp_dir("aov_channels_match_mitsuba");
    let out = dir.join("aov.exr");
    let (code, _, err) = wavetrace(&[
        "render",
        repo("tests/data/aov/aov_scene.xml").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let ours = aov_channels::assert_match_mitsuba(
        &out,
        &repo("tests/data/aov/aov_scene_ref.exr"),
        "my_image",
    );
    // The nested integrator's image is the film's.
    assert_eq!(channel(&ours, "R"), channel(&ours, "my_image.R"));
    // Rays at the corners meet nothing (depth 0); the others meet the three shapes.
    let depth = channel(&ours, "dd.T");
    assert!(depth.contains(&0.0) && depth.iter().filter(|&&d| d > 0.0).count() > 500);
    let shapes: std::collections::BTreeSet<u32> = channel(&ours, "pi.I")
        .iter()
        .zip(depth)
        .filter(|(_, &d)| d > 0.0)
        .map(|(&i, _)| i as u32)
        .collect();
    assert!(shapes.len() >= 2, "primitive indices {shapes:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--aov` adds channels without touching the radiance: the same samples, the same
/// sums, bit for bit (with a box and a Gaussian filter).
#[test]
fn aovs_leave_the_radiance_bit_identical() {
    for filter in ["box", "gaussian"] {
        let scene_path = temp_file(
            "aovs_leave_the_radiance",
            &format!("{filter}.xml"),
            &std::fs::read_to_string(repo("tests/data/aov/aov_scene.xml"))
                .unwrap()
                .replace(
                    "<rfilter type=\"box\"/>",
                    &format!("<rfilter type=\"{filter}\"/>"),
                )
                .replace(
                    "<sampler type=\"stratified\">",
                    "<sampler type=\"independent\">",
                )
                .replace("<boolean name=\"jitter\" value=\"false\"/>", ""),
        );
        let scene = load_with(&scene_path, &[]);
        let plain = wavetrace::scene::Scene {
            integrator: wavetrace::scene::integrator::IntegratorSpec {
                outputs: Default::default(),
                ..scene.integrator.clone()
            },
            ..load_with(&scene_path, &[])
        };
        let options = RenderOptions::default();
        let with = RenderOptions {
            aovs: parse_cli("depth,albedo,sh_normal").unwrap(),
            ..RenderOptions::default()
        };
        let a = film(&plain, &options, 4);
        let b = film(&plain, &with, 4);
        assert_eq!(a.sums, b.sums, "{filter}: radiance sums");
        // Small batches (the filter's samples of a pixel in two batches, from the
        // ring): the same AOV sums, bit for bit.
        let small = RenderOptions {
            max_batch_paths: Some(700),
            ..with.clone()
        };
        let c = film(&plain, &small, 4);
        assert_eq!(c.sums, b.sums, "{filter}: radiance sums in small batches");
        assert_eq!(c.extra, b.extra, "{filter}: AOV sums in small batches");
        assert!(a.extra.aov_names.is_empty());
        assert_eq!(b.extra.aov_names.len(), 7);
        let (names, values) = b.extra_channels();
        assert_eq!(
            names,
            [
                "depth.T",
                "albedo.R",
                "albedo.G",
                "albedo.B",
                "sh_normal.X",
                "sh_normal.Y",
                "sh_normal.Z"
            ]
        );
        assert!(values.iter().all(|v| v.is_finite()));
        // Normals are unit where every sample the pixel weighs meets one plane; the
        // filter mixes them at edges (within 2 pixels for the Gaussian).
        let units = values
            .chunks_exact(7)
            .filter(|p| {
                let n = (p[4] * p[4] + p[5] * p[5] + p[6] * p[6]).sqrt();
                (n - 1.0).abs() < 1e-4
            })
            .count();
        let hits = values.chunks_exact(7).filter(|p| p[0] > 0.0).count();
        assert!(
            hits > 300 && units > hits / if filter == "box" { 2 } else { 5 },
            "{filter}: {units} unit normals of {hits}"
        );
        // The scene's own aov integrator and --aov together.
        let both = film(&scene, &with, 1);
        assert_eq!(both.extra.aov_names.len(), 16 + 7);
    }
}

/// Mitsuba's `moment`: m2_<name> is the mean of each sample's XYZ squared, so
/// m2 - mean² is the samples' (biased) variance; with the box filter each pixel's
/// samples are the single-sample renders of each sample index.
#[test]
fn moment_is_the_mean_of_squares() {
    let scene_path = temp_file(
        "moment_is_the_mean_of_squares",
        "moment.xml",
        &moment_scene(),
    );
    let scene = load_with(&scene_path, &[]);
    let spp = 8;
    let all = film(&scene, &RenderOptions::default(), spp);
    let (names, values) = all.extra_channels();
    assert_eq!(
        names,
        [
            "my_image.X",
            "my_image.Y",
            "my_image.Z",
            "m2_my_image.X",
            "m2_my_image.Y",
            "m2_my_image.Z"
        ]
    );
    // The samples one at a time.
    let device = device();
    let mut r = Renderer::new(&device, &scene, &RenderOptions::default()).expect("renderer");
    let count = r.round_sample_count(spp).expect("count");
    r.set_sample_count(count).expect("count");
    let singles: Vec<FilmSums> = (0..spp)
        .map(|k| r.render_film(k, 1, &mut |_, _| {}).expect("render").0)
        .collect();
    let xyz = |s: &FilmSums, i: usize| {
        let (_, v) = s.extra_channels();
        [v[6 * i], v[6 * i + 1], v[6 * i + 2]]
    };
    for i in 0..all.sums.len() {
        for c in 0..3 {
            let samples: Vec<f64> = singles.iter().map(|s| f64::from(xyz(s, i)[c])).collect();
            let mean = samples.iter().sum::<f64>() / spp as f64;
            let m2 = samples.iter().map(|x| x * x).sum::<f64>() / spp as f64;
            let (our_mean, our_m2) = (
                f64::from(values[6 * i + c]),
                f64::from(values[6 * i + 3 + c]),
            );
            assert!(
                (our_mean - mean).abs() <= 1e-5 * (1.0 + mean.abs()),
                "pixel {i}: mean"
            );
            assert!(
                (our_m2 - m2).abs() <= 1e-5 * (1.0 + m2.abs()),
                "pixel {i}: m2 {our_m2} vs {m2}"
            );
            // The sample variance follows.
            assert!(our_m2 - our_mean * our_mean >= -1e-5 * (1.0 + m2));
        }
    }
}

/// Split renders merge their AOV and moment sums as they merge the film's.
#[test]
fn aov_sums_merge_across_sample_ranges() {
    let scene = load_with(&repo("tests/data/aov/aov_scene.xml"), &[("spp", "4")]);
    let device = device();
    let mut r = Renderer::new(&device, &scene, &RenderOptions::default()).expect("renderer");
    let count = r.round_sample_count(4).expect("count");
    r.set_sample_count(count).expect("count");
    let whole = r.render_film(0, 4, &mut |_, _| {}).expect("render").0;
    let mut a = r.render_film(0, 2, &mut |_, _| {}).expect("render").0;
    let b = r.render_film(2, 2, &mut |_, _| {}).expect("render").0;
    a.merge(&b).expect("merge");
    assert_eq!(a.extra.aov_names, whole.extra.aov_names);
    for (x, y) in a.extra.aovs.iter().zip(&whole.extra.aovs) {
        assert!((x - y).abs() <= 1e-5 * (1.0 + y.abs()), "{x} vs {y}");
    }
}

#[test]
fn bad_aovs_strings_name_the_entry() {
    let cases = [
        ("dd:depth,nn", "'nn'"),
        ("dd:depth,xx:sheen", "'xx:sheen'"),
        ("dd:boundary_test", "unknown AOV type 'boundary_test'"),
    ];
    for (aovs, expected) in cases {
        let path = temp_file(
            "bad_aovs_strings",
            "bad.xml",
            &format!(
                r#"<scene version="3.0.0">
    <integrator type="aov"><string name="aovs" value="{aovs}"/></integrator>
    <shape type="sphere"/>
</scene>"#
            ),
        );
        let err = wavetrace::scene::load(&path, &[])
            .expect_err(aovs)
            .to_string();
        assert!(err.contains(expected), "{aovs}: {err}");
        assert!(err.contains("bad.xml:2"), "{aovs}: file and line: {err}");
    }
    // Names the scene's aov integrator already writes, and too many AOVs.
    let scene = repo("tests/data/aov/aov_scene.xml");
    let (code, _, err) = wavetrace(&["render", scene.to_str().unwrap(), "--aov", "dd:depth"]);
    assert_ne!(code, 0);
    assert!(err.contains("'dd'"), "{err}");
    let many: Vec<String> = (0..10).map(|i| format!("a{i}:uv")).collect();
    let (code, _, err) = wavetrace(&["render", scene.to_str().unwrap(), "--aov", &many.join(",")]);
    assert_ne!(code, 0);
    assert!(err.contains("at most 16"), "{err}");
    let (code, _, err) = wavetrace(&["render", "x.xml", "--aov", "depth,bogus"]);
    assert_ne!(code, 0);
    assert!(
        err.contains("'bogus:bogus'") || err.contains("bogus"),
        "{err}"
    );
}

/// `render --samples` parts with `--aov` merge (`wavetrace merge`) into the AOVs of
/// the unsplit render; the partials record `--aov` for a resume.
#[test]
fn aov_parts_merge_on_the_command_line() {
    let d = temp_dir("aov_parts_merge");
    let scene = repo("tests/data/aov/aov_scene.xml");
    let run = |range: &str, out: &std::path::Path| {
        let (code, _, err) = wavetrace(&[
            "render",
            scene.to_str().unwrap(),
            "--spp",
            "4",
            "--sampler",
            "independent",
            "--aov",
            "depth,n:sh_normal",
            "--samples",
            range,
            "-o",
            out.to_str().unwrap(),
            "-q",
        ]);
        assert_eq!(code, 0, "render --samples {range}: {err}");
    };
    let (whole, a, b) = (d.join("whole.exr"), d.join("a.exr"), d.join("b.exr"));
    run("0..4", &whole);
    run("0..2", &a);
    run("2..4", &b);
    let record = wavetrace::render::partial::Partial::read(&a).expect("partial");
    assert_eq!(
        record.record.aov_option.as_deref(),
        Some("depth:depth,n:sh_normal")
    );
    let merged = d.join("merged.exr");
    let (code, _, err) = wavetrace(&[
        "merge",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "-o",
        merged.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let whole_image = d.join("whole_image.exr");
    let (code, _, err) = wavetrace(&[
        "merge",
        whole.to_str().unwrap(),
        "-o",
        whole_image.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let (_, _, m) = exr::read_channels(&merged).expect("merged");
    let (_, _, w) = exr::read_channels(&whole_image).expect("whole");
    for name in ["depth.T", "n.X", "n.Y", "n.Z", "dd.T", "my_image.A", "R"] {
        let (x, y) = (channel(&m, name), channel(&w, name));
        for (p, q) in x.iter().zip(y) {
            assert!(
                (p - q).abs() <= 2e-3 * (1.0 + q.abs()),
                "{name}: {p} vs {q}"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// Mitsuba's `moment` on the test scene at 256 spp (tests/data/aov/make_ref.py):
/// every channel's image mean within noise (0.2% here; the seeds differ).
#[test]
fn moment_matches_mitsuba() {
    let scene_path = temp_file("moment_matches_mitsuba", "moment.xml", &moment_scene());
    let dir = temp_dir("moment_matches_mitsuba");
    let out = dir.join("moment.exr");
    let (code, _, err) = wavetrace(&[
        "render",
        scene_path.to_str().unwrap(),
        "-D",
        "spp=256",
        "-o",
        out.to_str().unwrap(),
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    let (_, _, ours) = exr::read_channels(&out).expect("ours");
    let (_, _, theirs) = exr::read_channels(repo("tests/data/aov/moment_ref.exr")).expect("ref");
    assert_eq!(ours.len(), theirs.len());
    let mean = |v: &[f32]| v.iter().map(|&x| f64::from(x)).sum::<f64>() / v.len() as f64;
    for c in &theirs {
        let (a, b) = (mean(channel(&ours, &c.name)), mean(&c.values));
        assert!(
            (a - b).abs() <= 2e-3 * b,
            "{}: {a} against Mitsuba's {b}",
            c.name
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The test scene with Mitsuba's `moment` around its nested path integrator and the
/// independent sampler (as make_ref.py makes moment_ref.exr).
fn moment_scene() -> String {
    std::fs::read_to_string(repo("tests/data/aov/aov_scene.xml"))
        .unwrap()
        .replace("<integrator type=\"aov\">", "<integrator type=\"moment\">")
        .replace(
            "<string name=\"aovs\" value=\"dd:depth,nn:sh_normal,gn:geo_normal,pp:position,aa:albedo,uv:uv,pi:prim_index\"/>",
            "",
        )
        .replace("<sampler type=\"stratified\">", "<sampler type=\"independent\">")
        .replace("<boolean name=\"jitter\" value=\"false\"/>", "")
}

/// The albedo AOV is Mitsuba's `eval_diffuse_reflectance`: the reflectance of
/// diffuse and (two-sided) plastic, the base color of principled and principledthin,
/// for the others (roughconductor, pplastic) the BSDF towards the normal times π.
#[test]
fn albedo_matches_mitsuba() {
    let dir = temp_dir("albedo_matches_mitsuba");
    let out = dir.join("albedo.exr");
    let (code, _, err) = wavetrace(&[
        "render",
        repo("tests/data/aov/albedo_scene.xml").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    let (_, _, ours) = exr::read_channels(&out).expect("ours");
    let (_, _, theirs) =
        exr::read_channels(repo("tests/data/aov/albedo_scene_ref.exr")).expect("reference");
    // An aov integrator without a nested one: R, G, B are 0, as in Mitsuba.
    for c in ["R", "G", "B"] {
        assert!(channel(&ours, c).iter().all(|&v| v == 0.0), "{c}");
        assert!(channel(&theirs, c).iter().all(|&v| v == 0.0), "{c}");
    }
    for c in ["aa.R", "aa.G", "aa.B"] {
        let (a, b) = (channel(&ours, c), channel(&theirs, c));
        let lit = b.iter().filter(|&&v| v > 0.0).count();
        assert!(lit > 100, "{c}: {lit} pixels");
        for (i, (x, y)) in a.iter().zip(b).enumerate() {
            assert!(
                (x - y).abs() <= 1e-3 * (1.0 + y.abs()),
                "{c} pixel {i}: {x} against Mitsuba's {y}"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// dp_du, dp_dv, duv_dx and duv_dy of every shape kind (sphere, disk, cylinder, a mesh
/// with uvs and one without, a linear curve and an SDF grid, where Mitsuba's are 0, and
/// a rectangle) through a pinhole, an orthographic and a thin-lens camera (`--sensor`)
/// against Mitsuba 3.9.1 at pixel centres, and at 4 spp, where the differentials are
/// scaled by 1/√spp (references by tests/data/aov/make_ref.py). Mitsuba writes NaN in
/// the uv partials of rays that meet nothing (0/0 on its zeroed interaction); wavetrace
/// writes 0 there, as in its other channels.
#[test]
fn partials_match_mitsuba() {
    let dir = temp_dir("aov_partials_match_mitsuba");
    let cases = [
        ("0", "1", "partials_ref_0.exr"),
        ("1", "1", "partials_ref_1.exr"),
        ("2", "1", "partials_ref_2.exr"),
        ("0", "4", "partials_ref_spp4.exr"),
    ];
    for (sensor, spp, reference) in cases {
        let out = dir.join(format!("partials_{sensor}_{spp}.exr"));
        let (code, _, err) = wavetrace(&[
            "render",
            repo("tests/data/aov/partials_scene.xml").to_str().unwrap(),
            "--sensor",
            sensor,
            "-D",
            &format!("spp={spp}"),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        let (_, _, ours) = exr::read_channels(&out).expect("ours");
        let (_, _, theirs) =
            exr::read_channels(repo("tests/data/aov").join(reference)).expect("reference");
        let depth = channel(&theirs, "dd.T");
        for name in [
            "du.X", "du.Y", "du.Z", "dv.X", "dv.Y", "dv.Z", "dx.U", "dx.V", "dy.U", "dy.V",
        ] {
            let (a, b) = (channel(&ours, name), channel(&theirs, name));
            let (mut loose, mut nonzero) = (0, 0);
            for (i, (&x, &y)) in a.iter().zip(b).enumerate() {
                if depth[i] == 0.0 {
                    assert!(x == 0.0, "{reference} {name} pixel {i}: a miss gives {x}");
                    continue;
                }
                if y.is_nan() {
                    continue; // a pixel at 4 spp some of whose rays miss
                }
                let err = (x - y).abs() / (1.0 + y.abs());
                // Float rounding: the film positions (1/65536 of a pixel) and the
                // offset rays' tangent-plane solve at silhouettes.
                assert!(err <= 5e-2, "{reference} {name} pixel {i}: {x} against {y}");
                loose += usize::from(err > 2e-4);
                nonzero += usize::from(y != 0.0);
                // Curves and SDF grids: 0, as Mitsuba's.
                assert!(
                    y != 0.0 || x.abs() <= 1e-6,
                    "{reference} {name} pixel {i}: {x}"
                );
            }
            assert!(
                loose * 100 <= a.len(),
                "{reference} {name}: {loose} pixels off"
            );
            assert!(nonzero > 300, "{reference} {name}: {nonzero} nonzero");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// AOVs of many samples of one pixel: a 1 x 1 film at 65,536 spp (one thread traces a
/// pixel's samples, and llvmpipe ends a thread's loops after 65,535 iterations: the
/// AOVs of all but ~6,000 samples went missing before batches were bounded per
/// pixel), through a pinhole (the mean depth as at 256 spp, one batch either way) and
/// an irradiancemeter, whose rays the AOVs now follow from its shape (before, they were
/// 0), against Mitsuba 3.9.1's means (tests/data/aov/irradiancemeter_aov.xml).
#[test]
fn aovs_of_one_pixel_at_many_samples() {
    let dir = temp_dir("aovs_of_one_pixel");
    let render = |scene: &std::path::Path, spp: &str, name: &str| {
        let out = dir.join(name);
        let (code, _, err) = common::render_to(scene, &out, spp);
        assert_eq!(code, 0, "{err}");
        exr::read_channels(&out).expect("ours").2
    };
    let meter = repo("tests/data/aov/irradiancemeter_aov.xml");
    let ours = render(&meter, "65536", "meter.exr");
    for (name, mitsuba) in [("dd.T", 1.6953f32), ("nn.Z", 0.34937)] {
        let v = channel(&ours, name)[0];
        // Standard errors ~0.004 (depth) and ~0.002 (normal) for each renderer.
        assert!(
            (v - mitsuba).abs() < 0.02,
            "{name}: {v}, Mitsuba's {mitsuba}"
        );
    }
    let text = std::fs::read_to_string(&meter)
        .unwrap()
        .replace(
            "<sensor type=\"irradiancemeter\">",
            "</shape><sensor type=\"perspective\"><transform name=\"to_world\">\
             <lookat origin=\"0, 0, -1\" target=\"0, 0, 3\" up=\"0, 1, 0\"/></transform>",
        )
        .replace("</sensor>\n    </shape>", "</sensor>");
    let pinhole = temp_file("aovs_of_one_pixel", "pinhole.xml", &text);
    let few = channel(&render(&pinhole, "256", "few.exr"), "dd.T")[0];
    let many = channel(&render(&pinhole, "65536", "many.exr"), "dd.T")[0];
    assert!(
        (many - few).abs() < 0.01 * few,
        "pinhole depth: {many} at 65,536 spp, {few} at 256"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
