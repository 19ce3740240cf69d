//! Mitsuba 3's `batch` sensor (issue 40): several cameras side by side in one film.
//! tests/data/batch_sensor/batch.xml holds a batch of two perspective cameras (sensor
//! 0, a 64 x 32 film) and the same two cameras alone (sensors 1 and 2, 32 x 32 each;
//! the second child's `fov_axis` y resolves against its own nested 32 x 32 film, as
//! Mitsuba's does before the batch sets its film to the slice). Its reference batch_ref.exr is Mitsuba 3.9.1's render
//! of sensor 0 (scalar_rgb, 8192 spp, seed 7:
//! `scene = mi.load_file("batch.xml"); mi.render(scene, sensor=0, spp=8192, seed=7)`,
//! written with `mi.Bitmap(img).write`).

mod common;

use common::{device, repo, temp_file};
use wavetrace::image::Image;
use wavetrace::render::RenderOptions;

const SCENE: &str = "tests/data/batch_sensor/batch.xml";

/// Columns [x0, x0 + w) of `img`.
fn columns(img: &Image, x0: u32, w: u32) -> Image {
    let mut rgb = Vec::with_capacity((3 * w * img.height) as usize);
    for y in 0..img.height {
        let row = (3 * (y * img.width + x0)) as usize;
        rgb.extend_from_slice(&img.rgb[row..row + 3 * w as usize]);
    }
    Image {
        width: w,
        height: img.height,
        rgb,
    }
}

/// Each half of the batch renders as its camera alone (`--sensor 1`, `--sensor 2`),
/// within noise block by block (the sampler's pixel keys differ between a 64-wide
/// and a 32-wide film, so the samples do), and the whole batch as Mitsuba's.
#[test]
fn batch_of_two_cameras_matches_each_camera_and_mitsuba() {
    let device = device();
    let spp = 1024;
    let render = |sensor: usize| {
        let mut sc = common::load(&repo(SCENE));
        sc.select_sensor(sensor).expect("sensor");
        common::render(&device, &sc, &RenderOptions::default(), spp)
    };
    let batch = render(0);
    assert_eq!((batch.width, batch.height), (64, 32));
    for child in 0..2u32 {
        let alone = render(child as usize + 1);
        assert_eq!((alone.width, alone.height), (32, 32));
        common::assert_matches_reference(
            &columns(&batch, 32 * child, 32),
            &alone,
            &format!("batch child {child} against the camera alone"),
        );
    }
    let reference =
        Image::read_exr(repo("tests/data/batch_sensor/batch_ref.exr")).expect("reference EXR");
    common::assert_matches_reference(&batch, &reference, "batch against Mitsuba 3.9.1");
}

/// A batch of an orthographic, a thin-lens and a perspective camera (batch3.xml, 96 x
/// 32) against Mitsuba 3.9.1's render (batch3_ref.exr, made as batch_ref.exr is).
#[test]
fn batch_of_three_kinds_matches_mitsuba() {
    let sc = common::load(&repo("tests/data/batch_sensor/batch3.xml"));
    let img = common::render(&device(), &sc, &RenderOptions::default(), 1024);
    assert_eq!((img.width, img.height), (96, 32));
    let reference =
        Image::read_exr(repo("tests/data/batch_sensor/batch3_ref.exr")).expect("reference EXR");
    common::assert_matches_reference(&img, &reference, "3-kind batch against Mitsuba 3.9.1");
}

/// batch3.xml with Mitsuba's default Gaussian filter and `sample_border`, whose
/// samples reach a pixel past the film: left of it they stay in child 0, right of it
/// Mitsuba's sample_ray wraps them to the last child's left edge (x n - floor(x n) of
/// a position past 1), which we do too. Against Mitsuba 3.9.1's llvm_ad_rgb (exact
/// filter weights, as ours; batch3_gaussian_ref.exr: 4096 spp, seed 3, the
/// `<rfilter type="box"/>` replaced as below).
#[test]
fn batch_with_a_gaussian_filter_matches_mitsuba() {
    let text = std::fs::read_to_string(repo("tests/data/batch_sensor/batch3.xml")).expect("scene");
    let path = temp_file(
        "batch_sensor",
        "batch3_gaussian.xml",
        &text.replace(
            r#"<rfilter type="box"/>"#,
            r#"<boolean name="sample_border" value="true"/>"#,
        ),
    );
    let sc = common::load(&path);
    let img = common::render(&device(), &sc, &RenderOptions::default(), 4096);
    let reference = Image::read_exr(repo("tests/data/batch_sensor/batch3_gaussian_ref.exr"))
        .expect("reference EXR");
    // The wrap shows in the last column alone, too little for an 8 x 8 block: a t-test
    // of its 32 pixels per channel (the variance widened by the filter's factor, as
    // the block test's), which sees the samples past the edge kept in place at t = 7.8.
    let factor = sc.film.filter.block_variance_factor(8);
    for c in 0..3 {
        let d: Vec<f64> = (0..img.height)
            .map(|y| (common::pixel(&img, 95, y)[c] - common::pixel(&reference, 95, y)[c]) as f64)
            .collect();
        let n = d.len() as f64;
        let mean = d.iter().sum::<f64>() / n;
        let var = d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
        let t = mean / (factor * var / n).sqrt();
        println!("last column, channel {c}: t = {t:.2}");
        assert!(
            t.abs() < 5.0,
            "last column, channel {c}: t = {t:.2} against Mitsuba"
        );
    }
    common::assert_matches_filtered_reference(
        &img,
        &reference,
        "3-kind batch, Gaussian filter, against Mitsuba 3.9.1",
        &sc.film.filter,
    );
}

/// A film width not divisible by the number of children is an error at the batch
/// sensor's line, as in Mitsuba; so is a child of a kind a batch does not hold.
#[test]
fn batch_refuses_indivisible_width_and_other_children() {
    let text = std::fs::read_to_string(repo(SCENE)).expect("scene");
    let path = temp_file(
        "batch_sensor",
        "width63.xml",
        &text.replace(r#"name="width" value="64""#, r#"name="width" value="63""#),
    );
    let err = wavetrace::scene::load(&path, &[]).unwrap_err().to_string();
    assert!(
        err.contains("width63.xml:24")
            && err.contains("width (63) must be divisible by the number of child sensors (2)"),
        "{err}"
    );
    // A radiancemeter child needs its own film of 1 x 1 (Mitsuba's check, before the
    // batch sets its film to the slice).
    let path = temp_file(
        "batch_sensor",
        "radiancemeter.xml",
        &text.replacen(
            r#"<sensor type="perspective">
            <float name="fov" value="40"/>"#,
            r#"<sensor type="radiancemeter">"#,
            1,
        ),
    );
    let err = wavetrace::scene::load(&path, &[]).unwrap_err().to_string();
    assert!(
        err.contains("radiancemeter.xml:25") && err.contains("a film of 1 x 1 pixels"),
        "{err}"
    );
    let path = temp_file(
        "batch_sensor",
        "distant.xml",
        &text.replacen(
            r#"<sensor type="perspective">
            <float name="fov" value="40"/>"#,
            r#"<sensor type="distant">"#,
            1,
        ),
    );
    let err = wavetrace::scene::load(&path, &[]).unwrap_err().to_string();
    assert!(
        err.contains("distant.xml:25")
            && err.contains(
                "perspective, orthographic, thinlens or radiancemeter sensors, not 'distant'"
            ),
        "{err}"
    );
    // Mitsuba's batch also holds an irradiancemeter in a <shape>: not yet here.
    let path = temp_file(
        "batch_sensor",
        "irradiancemeter.xml",
        &text.replacen(
            r#"<sensor type="perspective">
            <float name="fov" value="40"/>"#,
            r#"<shape type="rectangle"><sensor type="irradiancemeter"/></shape>
        <sensor type="perspective">
            <float name="fov" value="40"/>"#,
            1,
        ),
    );
    let err = wavetrace::scene::load(&path, &[]).unwrap_err().to_string();
    assert!(
        err.contains("irradiancemeter.xml:25") && err.contains("not supported yet"),
        "{err}"
    );
}

/// A batch of a perspective camera and two radiance meters (batch_meter.xml, 48 x 16:
/// each meter, given its own 1 x 1 film as Mitsuba requires, fills its 16 x 16 slice
/// with estimates of its one ray's radiance) against Mitsuba 3.9.1's render
/// (batch_meter_ref.exr, made as batch_ref.exr is).
#[test]
fn batch_with_radiancemeters_matches_mitsuba() {
    let sc = common::load(&repo("tests/data/batch_sensor/batch_meter.xml"));
    let img = common::render(&device(), &sc, &RenderOptions::default(), 1024);
    assert_eq!((img.width, img.height), (48, 16));
    let reference = Image::read_exr(repo("tests/data/batch_sensor/batch_meter_ref.exr"))
        .expect("reference EXR");
    common::assert_matches_reference(&img, &reference, "meter batch against Mitsuba 3.9.1");
}

/// What cannot render a batch yet says so: the particle tracer (its camera
/// connections know one camera) and the uv partials' AOVs (they need each child's ray
/// differentials).
#[test]
fn batch_refuses_ptracer_and_uv_partials() {
    let mut sc = common::load(&repo(SCENE));
    sc.select_sensor(0).expect("sensor");
    let options = RenderOptions {
        integrator: Some("ptracer".into()),
        ..Default::default()
    };
    let err = wavetrace::render::Renderer::new(&device(), &sc, &options)
        .err()
        .expect("ptracer refuses a batch")
        .to_string();
    assert!(err.contains("not to a batch sensor"), "{err}");
    let options = RenderOptions {
        aovs: wavetrace::scene::integrator::aov::parse_cli("depth,duv_dx").expect("aov"),
        ..Default::default()
    };
    let err = wavetrace::render::Renderer::new(&device(), &sc, &options)
        .err()
        .expect("uv partials refuse a batch")
        .to_string();
    assert!(
        err.contains("the AOV 'duv_dx' of a batch sensor is not supported yet"),
        "{err}"
    );
}

/// AOVs of a batch (batch3_aov.xml: batch3.xml's orthographic, thin-lens and
/// perspective cameras under Mitsuba's aov integrator, 1 spp at pixel centres) equal
/// Mitsuba 3.9.1's up to float rounding, every child's rays traced as the radiance's
/// (`python3 -c "import mitsuba as mi; mi.set_variant('scalar_rgb'); s =
/// mi.load_file('tests/data/batch_sensor/batch3_aov.xml'); mi.render(s);
/// s.sensors()[0].film().write('tests/data/batch_sensor/batch3_aov_ref.exr')"`).
#[test]
fn batch_aovs_match_mitsuba_at_pixel_centres() {
    let dir = common::temp_dir("batch_aovs");
    let out = dir.join("aov.exr");
    let (code, _, err) = common::wavetrace(&[
        "render",
        repo("tests/data/batch_sensor/batch3_aov.xml")
            .to_str()
            .unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let ours = common::aov_channels::assert_match_mitsuba(
        &out,
        &repo("tests/data/batch_sensor/batch3_aov_ref.exr"),
        "_arg_0",
    );
    // Each child sees the spheres and the floor: depths vary in every third.
    let depth = common::aov_channels::channel(&ours, "dd.T");
    for child in 0..3 {
        let third: Vec<f32> = (0..32)
            .flat_map(|y| (32 * child..32 * child + 32).map(move |x| (x, y)))
            .map(|(x, y)| depth[y * 96 + x])
            .collect();
        let lo = third.iter().cloned().fold(f32::MAX, f32::min);
        let hi = third.iter().cloned().fold(0.0f32, f32::max);
        assert!(hi > lo + 0.5, "child {child}: depths {lo} to {hi}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A batch's `--samples` parts merge to its whole render bit for bit, as any sensor's
/// do where every part after the first holds one sample (tests/split.rs: a pixel's
/// sum is a float32 fold over its samples in order).
#[test]
fn batch_parts_merge_to_the_whole() {
    let dir = common::temp_dir("batch_sensor_parts");
    let out = |n: &str| dir.join(n).to_string_lossy().into_owned();
    let scene = repo("tests/data/batch_sensor/batch3.xml");
    let scene = scene.to_string_lossy();
    let run = |args: &[&str]| {
        let (code, _, err) = common::wavetrace(args);
        assert_eq!(code, 0, "{args:?}: {err}");
    };
    run(&[
        "render",
        &scene,
        "-q",
        "--spp",
        "16",
        "-o",
        &out("whole.exr"),
    ]);
    for (range, name) in [("0..15", "p0.exr"), ("15..16", "p1.exr")] {
        run(&[
            "render",
            &scene,
            "-q",
            "--spp",
            "16",
            "--samples",
            range,
            "-o",
            &out(name),
        ]);
    }
    run(&[
        "merge",
        &out("p0.exr"),
        &out("p1.exr"),
        "-o",
        &out("merged.exr"),
    ]);
    let whole = Image::read_exr(out("whole.exr")).expect("whole");
    let merged = Image::read_exr(out("merged.exr")).expect("merged");
    assert_eq!((whole.width, whole.height), (merged.width, merged.height));
    let differing = whole
        .rgb
        .iter()
        .zip(&merged.rgb)
        .enumerate()
        .filter(|(_, (a, b))| a != b)
        .map(|(i, (a, b))| (i / 3 % 96, i / 3 / 96, *a, *b))
        .collect::<Vec<_>>();
    assert!(
        differing.is_empty(),
        "{} values of the merged parts differ from the whole render, the first (x, y, whole, merged): {:?}",
        differing.len(),
        &differing[..differing.len().min(5)]
    );
}
