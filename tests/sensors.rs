//! Mitsuba's sensors that are no camera (issue 40): the irradiance meter against its
//! closed form and against Mitsuba 3.9.1.

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
