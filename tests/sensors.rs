//! Mitsuba's sensors that are no camera (issue 40): the irradiance meter against its
//! closed form and against Mitsuba 3.9.1; `render --sensor`; and the directional area
//! light, which only light paths leave, against Mitsuba's particle tracer.

mod common;

use common::{device, temp_file};
use wavetrace::render::RenderOptions;

/// An irradiance meter on a shape facing a sky of radiance L alone: every ray leaves
/// to the sky, so every sample is π L (Mitsuba's weight π times the cosine-sampled
/// radiance), on a quadric (a disk) and on a mesh (a rectangle).
#[test]
fn irradiancemeter_under_a_sky_measures_pi_l() {
    for shape in [r#"<shape type="disk">"#, r#"<shape type="rectangle">"#] {
        let text = format!(
            r#"<scene version="3.0.0">
            <emitter type="constant"><rgb name="radiance" value="0.7, 0.5, 0.3"/></emitter>
            {shape}
                <transform name="to_world"><rotate x="1" angle="30"/><translate value="1, 2, 3"/></transform>
                <sensor type="irradiancemeter">
                    <film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/><rfilter type="box"/></film>
                </sensor>
            </shape>
        </scene>"#
        );
        let sc = common::load(&temp_file("sensors", "irradiancemeter_sky.xml", &text));
        let img = common::render(&device(), &sc, &RenderOptions::default(), 64);
        assert_eq!((img.width, img.height), (1, 1));
        for (c, l) in [0.7f32, 0.5, 0.3].into_iter().enumerate() {
            let want = std::f32::consts::PI * l;
            assert!(
                (img.rgb[c] - want).abs() < 1e-4 * want,
                "{shape}: channel {c}: {} against π L = {want}",
                img.rgb[c]
            );
        }
    }
}

/// An irradiance meter on a rectangle (a mesh) and on a sphere (a quadric), lit by a
/// sphere light and a sky and shaded by a diffuse sphere (tests/scenes below), against
/// Mitsuba 3.9.1 (scalar_rgb, 32 renders of 262,144 samples: the mean and its standard
/// error): within 5 standard deviations of our mean of 262,144 samples (a sample's
/// deviation is below 1.6, measured from Mitsuba's renders).
#[test]
fn irradiancemeter_matches_mitsuba() {
    let scene = |sensor_shape: &str| {
        format!(
            r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="3"/></integrator>
    <emitter type="constant"><rgb name="radiance" value="0.25"/></emitter>
    <shape type="sphere">
        <point name="center" value="0.5, 0.3, 2"/><float name="radius" value="0.4"/>
        <emitter type="area"><rgb name="radiance" value="4, 3, 2"/></emitter>
    </shape>
    <shape type="sphere">
        <point name="center" value="-0.2, 0, 0.8"/><float name="radius" value="0.3"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.7, 0.5, 0.3"/></bsdf>
    </shape>
    {sensor_shape}
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
        <sensor type="irradiancemeter">
            <film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/><rfilter type="box"/></film>
            <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        </sensor>
    </shape>
</scene>"#
        )
    };
    let cases = [
        (
            r#"<shape type="rectangle"><transform name="to_world"><scale value="1.5"/></transform>"#,
            [1.0368867f64, 0.9614737, 0.88648635],
        ),
        (
            r#"<shape type="sphere"><point name="center" value="0,0,0"/><float name="radius" value="0.35"/>"#,
            [0.8633589, 0.83437365, 0.8055195],
        ),
    ];
    let spp = 262144;
    let sigma = 1.6 / (spp as f64).sqrt();
    for (shape, want) in cases {
        let sc = common::load(&temp_file("sensors", "irradiancemeter.xml", &scene(shape)));
        let img = common::render(&device(), &sc, &RenderOptions::default(), spp);
        for (c, want) in want.into_iter().enumerate() {
            let got = img.rgb[c] as f64;
            println!("irradiancemeter {shape}: channel {c}: {got} against Mitsuba's {want}");
            assert!(
                (got - want).abs() < 5.0 * sigma,
                "{shape}: channel {c}: {got} against Mitsuba's {want} (5σ = {})",
                5.0 * sigma
            );
        }
    }
}

/// `render --sensor I` of a scene with two cameras renders camera I exactly as the
/// scene holding only that camera renders (the same seed, the same samples); parts of
/// it merge, parts of different sensors refuse to; an index out of range says how many
/// sensors there are.
#[test]
fn render_picks_a_sensor() {
    let camera = |x: f32| {
        format!(
            r#"<sensor type="perspective"><float name="fov" value="40"/>
                <transform name="to_world"><lookat origin="{x}, 1, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
                <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="6"/></film>
                <sampler type="independent"><integer name="sample_count" value="4"/></sampler></sensor>"#
        )
    };
    let scene = |cameras: &[String]| {
        format!(
            r#"<scene version="3.0.0">
            {}
            <emitter type="constant"><rgb name="radiance" value="0.5"/></emitter>
            <shape type="sphere"><bsdf type="diffuse"/></shape>
            <shape type="rectangle"><transform name="to_world"><translate value="0, 0, -1"/><scale value="3"/></transform><bsdf type="diffuse"/></shape>
        </scene>"#,
            cameras.join("\n")
        )
    };
    let dir = common::temp_dir("sensors_pick");
    let both = dir.join("both.xml");
    let second = dir.join("second.xml");
    std::fs::write(&both, scene(&[camera(-1.0), camera(1.5)])).unwrap();
    std::fs::write(&second, scene(&[camera(1.5)])).unwrap();
    let out = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let run = |args: &[&str]| {
        let (code, _, err) = common::wavetrace(args);
        (code, err)
    };
    let (b, s) = (both.to_string_lossy(), second.to_string_lossy());
    assert_eq!(
        run(&["render", &b, "-q", "--sensor", "1", "-o", &out("b1.exr")]).0,
        0
    );
    assert_eq!(run(&["render", &s, "-q", "-o", &out("s.exr")]).0, 0);
    assert_eq!(run(&["render", &b, "-q", "-o", &out("b0.exr")]).0, 0);
    let read = |name: &str| wavetrace::image::Image::read_exr(dir.join(name)).expect(name);
    assert_eq!(
        read("b1.exr").rgb,
        read("s.exr").rgb,
        "--sensor 1 renders the second camera"
    );
    assert_ne!(
        read("b0.exr").rgb,
        read("s.exr").rgb,
        "by default the first camera"
    );
    // Parts of sensor 1 merge to its whole render; a part of sensor 0 does not join them.
    for (range, name) in [("0..2", "p0.exr"), ("2..4", "p1.exr")] {
        let args = [
            "render",
            &b,
            "-q",
            "--sensor",
            "1",
            "--samples",
            range,
            "-o",
            &out(name),
        ];
        assert_eq!(run(&args).0, 0);
    }
    let args = [
        "render",
        &b,
        "-q",
        "--samples",
        "2..4",
        "-o",
        &out("q1.exr"),
    ];
    assert_eq!(run(&args).0, 0);
    assert_eq!(
        run(&["merge", &out("p0.exr"), &out("p1.exr"), "-o", &out("m.exr")]).0,
        0
    );
    let (m, whole) = (read("m.exr").rgb, read("b1.exr").rgb);
    let worst = m
        .iter()
        .zip(&whole)
        .map(|(a, b)| (a - b).abs() / b.abs().max(1e-3))
        .fold(0.0f32, f32::max);
    assert!(
        worst < 1e-3,
        "merged parts against the whole render: {worst}"
    );
    let (code, err) = run(&[
        "merge",
        &out("p0.exr"),
        &out("q1.exr"),
        "-o",
        &out("bad.exr"),
    ]);
    assert_ne!(code, 0);
    assert!(err.contains("sensors 1 and 0"), "{err}");
    let (code, err) = run(&["render", &b, "-q", "--sensor", "2", "-o", &out("x.exr")]);
    assert_ne!(code, 0);
    assert!(err.contains("the scene has 2 sensors (0 to 1)"), "{err}");
}

/// A directional area light (a tilted rectangle sending its light along its normal
/// onto a floor and a sphere): the particle tracer's image has Mitsuba 3.9.1's mean
/// (scalar_rgb ptracer, max_depth 4: 8 renders of 1,024 samples, the mean of their
/// means; one render's mean deviates by 3.1e-5 in red), within 7 of those deviations
/// at 1,024 samples; and the path tracer, as Mitsuba's, sees no light at all (the
/// light's sample_direction and eval are zero).
#[test]
fn directionalarea_lights_only_light_paths() {
    let text = r#"<scene version="3.0.0">
    <default name="integrator" value="ptracer"/>
    <integrator type="$integrator"><integer name="max_depth" value="4"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <transform name="to_world"><lookat origin="0, 2, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="24"/><rfilter type="box"/></film>
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><scale value="0.8"/><rotate x="1" angle="60"/><translate value="0.3, 2.5, 0"/></transform>
        <emitter type="directionalarea"><rgb name="radiance" value="3, 2, 1"/></emitter>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf>
    </shape>
    <shape type="sphere"><point name="center" value="-0.5, 0.5, 0.5"/><float name="radius" value="0.5"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.3, 0.6, 0.3"/></bsdf></shape>
</scene>"#;
    let path = temp_file("sensors", "directionalarea.xml", text);
    let sc = common::load(&path);
    let img = common::render(&device(), &sc, &RenderOptions::default(), 1024);
    let n = (img.width * img.height) as usize;
    let want = [0.08975843f64, 0.06165967, 0.02991948];
    let sigma = [3.1e-5f64, 2.6e-5, 1.1e-5];
    for c in 0..3 {
        let got = (0..n).map(|i| img.rgb[3 * i + c] as f64).sum::<f64>() / n as f64;
        println!(
            "directionalarea ptracer: channel {c}: mean {got} against Mitsuba's {}",
            want[c]
        );
        assert!(
            (got - want[c]).abs() < 7.0 * sigma[c],
            "channel {c}: mean {got} against Mitsuba's {}",
            want[c]
        );
    }
    let sc = common::load_with(&path, &[("integrator", "path")]);
    let img = common::render(&device(), &sc, &RenderOptions::default(), 16);
    assert!(
        img.rgb.iter().all(|&v| v == 0.0),
        "path sees no directional area light"
    );
    // The photon mapper (photons for direct light too) agrees within its bias; SPPM,
    // which lights visible points by emitter sampling, refuses.
    let text = text.replace(
        r#"<integrator type="$integrator"><integer name="max_depth" value="4"/></integrator>"#,
        r#"<integrator type="$integrator"/>"#,
    );
    let path = temp_file("sensors", "directionalarea_photons.xml", &text);
    let sc = common::load_with(&path, &[("integrator", "photonmapper")]);
    let img = common::render(&device(), &sc, &RenderOptions::default(), 64);
    let got = (0..n).map(|i| img.rgb[3 * i] as f64).sum::<f64>() / n as f64;
    assert!(
        (got / want[0] - 1.0).abs() < 0.02,
        "photonmapper: mean {got} against {}",
        want[0]
    );
    let out = common::temp_dir("sensors_sppm").join("x.exr");
    let (code, _, err) = common::wavetrace(&[
        "render",
        &path.to_string_lossy(),
        "-D",
        "integrator=sppm",
        "-q",
        "-o",
        &out.to_string_lossy(),
    ]);
    assert_ne!(code, 0);
    assert!(
        err.contains("directionalarea emitter never answers"),
        "{err}"
    );
}
