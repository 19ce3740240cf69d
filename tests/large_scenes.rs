//! Scenes larger than one binding: arrays split over several bindings render exactly
//! as when whole (`render::scene_parts`).

mod common;

use wavetrace::accel::{prims_from_scene, Bvh};
use wavetrace::render::scene_buffers::SceneRecords;
use wavetrace::render::scene_parts::{scene_arrays, ScenePlan, SCENE_ARRAYS};
use wavetrace::render::{RenderOptions, Renderer};
use wavetrace::scene::Scene;

/// The smallest part size (log2 texels) at which every array of `scene` still fits
/// its bindings: the most splitting the scene allows.
fn smallest_part_shift(scene: &Scene) -> u32 {
    let bvh = Bvh::build(prims_from_scene(scene));
    let records = SceneRecords::new(scene, &bvh);
    let arrays = scene_arrays(&bvh, &records);
    let bytes = std::array::from_fn(|a| arrays[a].len() as u64);
    (0..32)
        .find(|&s| ScenePlan::new(bytes, s).is_ok())
        .expect("some part size fits")
}

/// Renders the scene file `path` whole and split at the smallest part size; the images
/// must be bit-identical (a split changes where a texel is read from, never its value
/// or the order of any arithmetic). Returns the arrays that were split.
fn split_equals_whole(
    path: &std::path::Path,
    defines: &[(&str, &str)],
    spp: u32,
) -> Vec<&'static str> {
    let defines: Vec<(String, String)> = defines
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    let name = path.display();
    let scene =
        wavetrace::scene::load(path, &defines).unwrap_or_else(|e| panic!("loading {name}: {e}"));
    let device = common::device();
    let whole = common::render(&device, &scene, &RenderOptions::default(), spp);
    let shift = smallest_part_shift(&scene);
    let options = RenderOptions {
        scene_part_shift: Some(shift),
        ..RenderOptions::default()
    };
    let mut r = Renderer::new(&device, &scene, &options).expect("split setup");
    let plan = r.scene_plan().clone();
    assert!(plan.is_split(), "{name}: nothing split at 2^{shift} texels");
    let split = r.render(spp, &mut |_, _| {}).expect("split render").0;
    let differ = whole
        .rgb
        .iter()
        .zip(&split.rgb)
        .filter(|(a, b)| a.to_bits() != b.to_bits());
    assert_eq!(
        differ.count(),
        0,
        "{name}: values of the split render differ"
    );
    (0..SCENE_ARRAYS.len())
        .filter(|&a| plan.parts[a] > 1)
        .map(|a| SCENE_ARRAYS[a].label)
        .collect()
}

/// A wavy 36 x 36 grid with vertex normals and uvs under a checkerboard, lit by a
/// sphere and the sky: geometry dominates its arrays, so all four geometry arrays
/// split at the smallest part size.
fn wavy_grid_scene() -> std::path::PathBuf {
    // 2450 triangles: the primitives (3 texels each) need parts of 2^11 texels, which
    // the triangles (2450 texels) and vertices (2592) overflow too.
    let n = 36;
    let mut obj = String::new();
    let h = |x: f32, y: f32| 0.1 * (5.0 * x).sin() * (4.0 * y).cos();
    for j in 0..n {
        for i in 0..n {
            let (x, y) = (
                2.0 * i as f32 / (n - 1) as f32 - 1.0,
                2.0 * j as f32 / (n - 1) as f32 - 1.0,
            );
            let (dx, dy) = (
                0.5 * (5.0 * x).cos() * (4.0 * y).cos(),
                -0.4 * (5.0 * x).sin() * (4.0 * y).sin(),
            );
            obj += &format!(
                "v {x} {y} {}\nvn {} {} 1\nvt {} {}\n",
                h(x, y),
                -dx,
                -dy,
                (x + 1.0) / 2.0,
                (y + 1.0) / 2.0
            );
        }
    }
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let v = j * n + i + 1;
            let f = |a: usize| format!("{a}/{a}/{a}");
            obj += &format!(
                "f {} {} {}\nf {} {} {}\n",
                f(v),
                f(v + 1),
                f(v + n + 1),
                f(v),
                f(v + n + 1),
                f(v + n)
            );
        }
    }
    common::temp_file("split", "grid.obj", &obj);
    let xml = r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="3"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="50"/>
        <transform name="to_world"><lookat origin="0, -2, 2" target="0, 0, 0" up="0, 0, 1"/></transform>
        <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/></film>
    </sensor>
    <shape type="obj">
        <string name="filename" value="grid.obj"/>
        <bsdf type="diffuse">
            <texture type="checkerboard" name="reflectance">
                <transform name="to_uv"><scale x="6" y="6"/></transform>
            </texture>
        </bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" value="1, -1, 2"/>
        <float name="radius" value="0.3"/>
        <emitter type="area"><rgb name="radiance" value="30"/></emitter>
    </shape>
    <emitter type="constant"><rgb name="radiance" value="0.3"/></emitter>
</scene>"#;
    common::temp_file("split", "grid.xml", xml)
}

#[test]
fn scenes_split_over_bindings_render_exactly_as_whole() {
    let mut split = Vec::new();
    // BVH nodes, primitives, triangles and vertices (normals and uvs).
    split.extend(split_equals_whole(&wavy_grid_scene(), &[], 2));
    // Bitmaps (texel words).
    split.extend(split_equals_whole(
        &common::repo("scenes/textures/textures.xml"),
        &[("res", "24"), ("max_depth", "3")],
        2,
    ));
    // Environment-map distributions.
    split.extend(split_equals_whole(
        &common::repo("scenes/envmap/envmap.xml"),
        &[("res", "24")],
        2,
    ));
    // A packed density grid.
    split.extend(split_equals_whole(
        &common::repo("scenes/media/smoke.xml"),
        &[("res", "24")],
        2,
    ));
    for label in [
        "bvh nodes",
        "primitives",
        "triangles",
        "vertices",
        "texels",
        "envmap distributions",
        "packed density grids",
    ] {
        assert!(
            split.contains(&label),
            "'{label}' was never split: {split:?}"
        );
    }
}
