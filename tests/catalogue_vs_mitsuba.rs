//! Every material plugin of the material-catalogue issue in one scene, against Mitsuba
//! 3.9.1: tests/data/catalogue/catalogue.xml (made by `python3
//! tools/make_catalogue_scene.py`: a `principled` floor with a BMP base colour, spheres
//! of `mask`, `blendbsdf` (a checkerboard weight, a rough conductor of the named
//! material `a-C`), `bumpmap` (a raw BMP height field over a rough plastic),
//! `principledthin` and `pplastic`, a `twosided` disk with two different BSDFs seen from
//! both sides, a PLY whose diffuse reflectance is its `vertex_color` (`mesh_attribute`)
//! and a `rawconstant` diffuse, `hair` on a sphere, `measured` (tests/data/measured_iso.bsdf),
//! a rough conductor whose `eta` is a BMP texture and whose `k` a spectrum file, and a
//! diffuse whose reflectance is a spectrum file (`<spectrum filename="paint.spd">`); an
//! area light and a constant sky; path tracing to depth 5), against `catalogue_ref.exr`
//! (`python3 tools/mitsuba_ref.py
//! tests/data/catalogue/catalogue.xml -o tests/data/catalogue/catalogue_ref.exr --spp
//! 4096 --variant scalar_rgb`).
//!
//! The check (tests/common `assert_matches_reference_at`): per 8x8 block and channel and
//! over the whole image, a t-test of the pixel differences render - reference, at
//! family-wise level 1%; and the same check must reject the render scaled by 0.95.

mod common;

use common::{assert_matches_reference_at, device, repo};
use wavetrace::image::Image;
use wavetrace::render::RenderOptions;

#[test]
fn every_new_material_plugin_at_once_renders_as_mitsuba() {
    let scene = common::load(&repo("tests/data/catalogue/catalogue.xml"));
    let reference = Image::read_exr(repo("tests/data/catalogue/catalogue_ref.exr"))
        .expect("tests/data/catalogue/catalogue_ref.exr (tools/mitsuba_ref.py)");
    let img = common::render(&device(), &scene, &RenderOptions::default(), 512);
    assert_eq!((img.width, img.height), (reference.width, reference.height));
    assert_matches_reference_at(&img, &reference, "material catalogue, path, 512 spp", 0.01);
}
