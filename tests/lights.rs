//! Mitsuba's lights and cameras (issue 40): the thin-lens camera against a Mitsuba 3.9
//! reference of scenes/lights/thinlens.xml, and the photon mappers under a directional
//! light and a projector against closed forms. (The directional light, the projector,
//! the textured spot light and the orthographic camera in the path integrators are
//! judged by Mitsuba's regression suite: tests/mitsuba_regression_suite.rs.)

mod common;

use common::{device, repo, temp_file};
use wavetrace::image::Image;
use wavetrace::render::RenderOptions;

/// Depth of field: scenes/lights/thinlens.xml (a thin lens focused on the middle of
/// three spheres, a directional light and a sky) against Mitsuba 3.9.1's rendering of
/// the same file (scenes/refs/lights_thinlens.exr, 4096 spp), block by block.
#[test]
fn thinlens_matches_mitsuba() {
    let scene = common::load(&repo("scenes/lights/thinlens.xml"));
    let reference = Image::read_exr(repo("scenes/refs/lights_thinlens.exr")).expect("reference");
    let img = common::render(&device(), &scene, &RenderOptions::default(), 256);
    assert_eq!((img.width, img.height), (reference.width, reference.height));
    common::assert_matches_reference(&img, &reference, "thinlens");
}

/// The mean of the image's pixels in green.
fn mean_green(img: &Image) -> f64 {
    let n = (img.width * img.height) as usize;
    (0..n).map(|i| img.rgb[3 * i + 1] as f64).sum::<f64>() / n as f64
}

/// A diffuse plane (albedo 0.5) at z = 0 seen from above by a camera that sees only
/// its part lit evenly, under `emitter`, rendered by `integrator`: the image is
/// (ρ/π) E everywhere, E the (uniform) irradiance there, and the gather's kernel adds
/// no bias where the irradiance is uniform over the gather disk.
fn plane_under(test: &str, emitter: &str, integrator: &str) -> Image {
    let text = format!(
        r#"<scene version="3.0.0">
            {integrator}
            <sensor type="perspective">
                <float name="fov" value="30"/>
                <transform name="to_world"><lookat origin="0, 0, 2" target="0, 0, 0" up="0, 1, 0"/></transform>
                <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/>
                    <rfilter type="box"/></film>
            </sensor>
            <shape type="rectangle">
                <transform name="to_world"><scale value="2"/></transform>
                <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
            </shape>
            {emitter}
        </scene>"#
    );
    let sc = common::load(&temp_file("lights", &format!("{test}.xml"), &text));
    common::render(&device(), &sc, &RenderOptions::default(), 4)
}

const PHOTONMAPPER: &str = r#"<integrator type="photonmapper"><integer name="photonCount" value="400000"/><float name="photonRadius" value="0.1"/></integrator>"#;
const SPPM: &str = r#"<integrator type="sppm"><integer name="photonsperiteration" value="100000"/><float name="radius" value="0.1"/></integrator>"#;

/// Photons from a directional light (irradiance 2 straight down: ρ/π E = 1/π): they
/// leave a disk as wide as the scene's bounding sphere, and the plane's image must be
/// 1/π within the estimate's noise (about 1% over the image).
#[test]
fn photon_mappers_see_a_directional_light() {
    let light = r#"<emitter type="directional"><vector name="direction" value="0, 0, -1"/><rgb name="irradiance" value="2"/></emitter>"#;
    for integrator in [PHOTONMAPPER, SPPM] {
        let img = plane_under("directional", light, integrator);
        let got = mean_green(&img);
        let want = 1.0 / std::f64::consts::PI;
        println!("directional: {got} against {want}");
        assert!(
            (got / want - 1.0).abs() < 0.03,
            "{integrator}: {got} against {want}"
        );
    }
    // The path tracer too (exact up to the camera's noise, which is none here).
    let img = plane_under("directional_path", light, r#"<integrator type="path"/>"#);
    let got = mean_green(&img);
    assert!(
        (got * std::f64::consts::PI - 1.0).abs() < 1e-4,
        "path: {got}"
    );
}

/// Photons from a projector 1 above the plane looking down (fov 90: it lights
/// |x|, |y| <= 1; irradiance 1): the plane receives π irradiance there (Mitsuba's
/// projector), so the image is ρ = 0.5.
#[test]
fn photon_mappers_see_a_projector() {
    let light = r#"<emitter type="projector"><float name="fov" value="90"/><rgb name="irradiance" value="1"/>
        <transform name="to_world"><lookat origin="0, 0, 1" target="0, 0, 0" up="0, 1, 0"/></transform></emitter>"#;
    for integrator in [PHOTONMAPPER, SPPM] {
        let img = plane_under("projector", light, integrator);
        let got = mean_green(&img);
        println!("projector: {got} against 0.5");
        assert!(
            (got / 0.5 - 1.0).abs() < 0.03,
            "{integrator}: {got} against 0.5"
        );
    }
    let img = plane_under("projector_path", light, r#"<integrator type="path"/>"#);
    let got = mean_green(&img);
    assert!((got / 0.5 - 1.0).abs() < 1e-4, "path: {got}");
}

/// A radiance meter looking down at a diffuse plane (albedo ρ) under a directional
/// light (irradiance E at cos θ = 3/√14) and a sky of radiance L: its one pixel is
/// (ρ/π) E cos θ + ρ L, within 5 standard deviations of its 65,536 samples (each
/// sample's deviation is below 0.35: half of them pick the directional light, doubled).
#[test]
fn radiancemeter_sees_the_radiance_along_its_ray() {
    let text = r#"<scene version="3.0.0">
        <integrator type="path"><integer name="max_depth" value="2"/></integrator>
        <sensor type="radiancemeter">
            <point name="origin" value="0.3, 0.2, 2"/>
            <vector name="direction" value="-0.1, 0, -1"/>
            <film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/><rfilter type="box"/></film>
        </sensor>
        <emitter type="constant"><rgb name="radiance" value="0.2"/></emitter>
        <emitter type="directional"><vector name="direction" value="-1, -2, -3"/><rgb name="irradiance" value="2"/></emitter>
        <shape type="rectangle"><bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf></shape>
    </scene>"#;
    let sc = common::load(&temp_file("lights", "radiancemeter.xml", text));
    let spp = 65536;
    let img = common::render(&device(), &sc, &RenderOptions::default(), spp);
    assert_eq!((img.width, img.height), (1, 1));
    let (rho, e, l) = (0.6f64, 2.0f64, 0.2f64);
    let want = rho / std::f64::consts::PI * e * 3.0 / 14f64.sqrt() + rho * l;
    let got = img.rgb[1] as f64;
    let sigma = 0.35 / (spp as f64).sqrt();
    println!("radiancemeter: {got} against {want} (σ < {sigma})");
    assert!((got - want).abs() < 5.0 * sigma, "{got} against {want}");
}

/// A distant sensor looking straight down at a 2 x 2 diffuse square (albedo ρ) under
/// a directional light (irradiance E at cos θ = 3/√14) and a sky (radiance L): its rays
/// start uniformly over the bounding sphere's cross-section (radius √2), a fraction
/// 4 / 2π of them meets the square, whose radiance is (ρ/π) E cos θ + ρ L, and the rest
/// see the sky: the pixel is their mix, within 5 standard deviations of 65,536 samples.
#[test]
fn distant_sensor_averages_over_the_scene() {
    let text = r#"<scene version="3.0.0">
        <integrator type="path"><integer name="max_depth" value="2"/></integrator>
        <sensor type="distant">
            <vector name="direction" value="0, 0, -1"/>
            <film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/><rfilter type="box"/></film>
        </sensor>
        <emitter type="constant"><rgb name="radiance" value="0.2"/></emitter>
        <emitter type="directional"><vector name="direction" value="-1, -2, -3"/><rgb name="irradiance" value="2"/></emitter>
        <shape type="rectangle"><bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf></shape>
    </scene>"#;
    let sc = common::load(&temp_file("lights", "distant.xml", text));
    let spp = 65536;
    let img = common::render(&device(), &sc, &RenderOptions::default(), spp);
    let (rho, e, l) = (0.6f64, 2.0f64, 0.2f64);
    let plane = rho / std::f64::consts::PI * e * 3.0 / 14f64.sqrt() + rho * l;
    let f = 4.0 / (2.0 * std::f64::consts::PI);
    let want = f * plane + (1.0 - f) * l;
    let got = img.rgb[1] as f64;
    let sigma = 0.4 / (spp as f64).sqrt();
    println!("distant: {got} against {want} (σ < {sigma})");
    assert!((got - want).abs() < 5.0 * sigma, "{got} against {want}");
}
