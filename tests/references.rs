//! Objects a Mitsuba scene declares once at the top level with an `id` and uses by
//! `<ref>` (src/scene/inline_refs.rs): the scene renders exactly as the one that writes
//! them where they are used.

mod common;

use common::{device, load, temp_file};
use wavetrace::render::{RenderOptions, Renderer};

/// A textured sphere on a plane under a constant sky, with the sensor's film, sampler
/// and reconstruction filter and the sphere's texture given by `parts`.
fn scene(declared: &str, sensor: &str, texture: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
  {declared}
  <integrator type="path"><integer name="max_depth" value="4"/></integrator>
  <sensor type="perspective">
    <float name="fov" value="40"/>
    <transform name="to_world"><lookat origin="0, 1, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
    {sensor}
  </sensor>
  <emitter type="constant"><rgb name="radiance" value="0.8, 0.9, 1.0"/></emitter>
  <shape type="sphere"><bsdf type="diffuse">{texture}</bsdf></shape>
  <shape type="rectangle">
    <transform name="to_world"><rotate x="1" angle="-90"/><scale value="4"/><translate y="-1"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.4, 0.3, 0.2"/></bsdf>
  </shape>
</scene>"#
    )
}

const SAMPLER: &str = r#"<sampler type="stratified"><integer name="sample_count" value="9"/><integer name="seed" value="7"/></sampler>"#;
const FILM: &str = r#"<film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="16"/>RFILTER</film>"#;
const RFILTER: &str = r#"<rfilter type="tent"><float name="radius" value="1.5"/></rfilter>"#;
const TEXTURE: &str = r#"<texture type="checkerboard"><rgb name="color0" value="0.8, 0.1, 0.1"/><transform name="to_uv"><scale value="6"/></transform></texture>"#;

/// `el` with an `id` (or a `name`) added to its first tag.
fn with(el: &str, attr: &str) -> String {
    let end = el.find(['>', '/']).expect("a tag");
    format!("{} {attr}{}", &el[..end], &el[end..])
}

#[test]
fn a_referenced_film_sampler_rfilter_and_texture_render_as_written_inline() {
    let inline = scene(
        "",
        &format!("{SAMPLER}{}", FILM.replace("RFILTER", RFILTER)),
        &with(TEXTURE, r#"name="reflectance""#),
    );
    let declared = scene(
        &format!(
            "{}{}{}{}",
            with(RFILTER, r#"id="rf""#),
            with(&FILM.replace("RFILTER", r#"<ref id="rf"/>"#), r#"id="flm""#),
            with(SAMPLER, r#"id="smp""#),
            with(TEXTURE, r#"id="tex""#)
        ),
        r#"<ref id="flm"/><ref id="smp"/>"#,
        r#"<ref name="reflectance" id="tex"/>"#,
    );
    let dev = device();
    let render = |name: &str, text: &str| {
        let scene = load(&temp_file("references", name, text));
        assert_eq!(
            (scene.camera.width, scene.camera.height, scene.spp),
            (24, 16, 9)
        );
        let mut r = Renderer::new(&dev, &scene, &RenderOptions::default())
            .unwrap_or_else(|e| panic!("setup: {e}"));
        r.render(scene.spp, &mut |_, _| {}).expect("render").0
    };
    let a = render("inline.xml", &inline);
    let b = render("declared.xml", &declared);
    assert!(a.rgb.iter().any(|&v| v > 0.05), "a lit image");
    let bits =
        |img: &wavetrace::image::Image| img.rgb.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert!(bits(&a) == bits(&b), "the images differ");
}
