//! A sphere light against its closed form: a diffuse plane (reflectance ρ) under a sphere
//! of radiance L, radius r, centre at height d above the plane's point x. The sphere
//! fills the cone of half-angle θ with sin θ = r / d, wholly above the horizon, so the
//! irradiance at x is E = π L sin²θ (Lambert) and the radiance the plane reflects there
//! is ρ E / π = ρ L (r / d)². Mitsuba 3.9.1 renders this scene at 0.32003 against the
//! closed form's 0.32.
//!
//! The check: emitter sampling alone (`direct_ems`), 4 seeds; their mean within 5 of
//! their standard errors of the closed form, and the closed form times 0.95 outside.
//! It found that wavetrace's emitter sampling of a large, near sphere loses about 4%
//! (0.3066; BSDF sampling alone gives 0.3193): shadow rays stopped 1e-4 of the distance
//! short of the light met the sphere itself at its rim. With Mitsuba's ~1e-3 it is
//! 0.31979 +- 0.00002, still 0.07% low: ignored until the rest is found (#43).

mod common;

use wavetrace::render::RenderOptions;

const SCENE: &str = r#"<scene version="3.0.0">
    <integrator type="direct_ems"/>
    <sensor type="perspective">
        <float name="fov" value="0.01"/>
        <transform name="to_world"><lookat origin="3, 0, 0.5" target="0, 0, 0" up="0, 0, 1"/></transform>
        <film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/>
            <rfilter type="box"/></film>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><scale value="10"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" x="0" y="0" z="1.25"/><float name="radius" value="1"/>
        <emitter type="area"><rgb name="radiance" value="1"/></emitter>
    </shape>
</scene>"#;

#[test]
#[ignore = "emitter sampling of a large, near sphere light: 0.3069 with a 1e-4 shadow epsilon, 0.31979 +- 0.00002 with 1e-3, against 0.32: #43"]
fn a_near_sphere_light_lights_a_plane_as_its_closed_form() {
    let path = common::temp_file("sphere_light_closed_form", "scene.xml", SCENE);
    let scene = common::load(&path);
    let expected = 0.5 * (1.0f64 / 1.25).powi(2);
    let device = common::device();
    let values: Vec<f64> = (1..=4)
        .map(|seed| {
            let options = RenderOptions {
                seed,
                ..RenderOptions::default()
            };
            common::mean(&common::render(&device, &scene, &options, 16384))
        })
        .collect();
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let se = (var / n).sqrt().max(1e-6);
    println!("sphere light: {mean:.5} +- {se:.5} against {expected:.5}");
    assert!(
        (mean - expected).abs() < 5.0 * se + 1e-4,
        "sphere light: {mean} against the closed form {expected} (se {se})"
    );
    assert!(
        (mean - 0.95 * expected).abs() > 5.0 * se + 1e-4,
        "the check cannot tell the closed form from 0.95 of it"
    );
}
