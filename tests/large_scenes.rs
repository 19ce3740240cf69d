//! Scenes larger than one binding: arrays split over several bindings render exactly
//! as when whole (`render::scene_parts`).

mod common;

use wavetrace::accel::{prims_from_scene, Bvh};
use wavetrace::render::scene_buffers::SceneRecords;
use wavetrace::render::scene_parts::{array_sizes, scene_arrays, ScenePlan, SCENE_ARRAYS};
use wavetrace::render::{RenderOptions, Renderer};
use wavetrace::scene::Scene;

/// The smallest part size (log2 texels) at which every array of `scene` still fits
/// its bindings: the most splitting the scene allows.
fn smallest_part_shift(scene: &Scene) -> u32 {
    let bvh = Bvh::build(prims_from_scene(scene));
    let records = SceneRecords::new(scene, &bvh);
    let bytes = array_sizes(&scene_arrays(&bvh, &records));
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
    // Sampling distributions (the environment map's).
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
        "sampling distributions",
        "packed density grids",
    ] {
        assert!(
            split.contains(&label),
            "'{label}' was never split: {split:?}"
        );
    }
}

/// A valley of two planes, z = |x| / 2 over [-1, 1]^2, as a grid of `n` x `n` vertices
/// (`n` odd: a column of vertices lies on the fold, so every triangle lies in one
/// plane; every vertex lies exactly on its plane, z being x / 2 in floats too).
fn valley(n: usize) -> (Vec<glam::Vec3>, Vec<[u32; 3]>) {
    assert!(n % 2 == 1);
    let coord = |i: usize| -1.0 + (2 * i) as f32 / (n - 1) as f32;
    let mut positions = Vec::with_capacity(n * n);
    for j in 0..n {
        for i in 0..n {
            let x = coord(i);
            positions.push(glam::Vec3::new(x, coord(j), 0.5 * x.abs()));
        }
    }
    let mut indices = Vec::with_capacity(2 * (n - 1) * (n - 1));
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let v = (j * n + i) as u32;
            let n = n as u32;
            indices.push([v, v + 1, v + n + 1]);
            indices.push([v, v + n + 1, v + n]);
        }
    }
    (positions, indices)
}

/// A scene over 128 MiB — 6 M triangles: 288 MB of primitives, 190 MB of BVH nodes —
/// renders as its three-vertex-wide version does: a valley of two diffuse planes
/// under a constant sky, whose light bounces between the planes. Every vertex of the
/// fine mesh lies exactly on the coarse mesh's planes, so the two images differ only by
/// rounding in the hit points and normals (the same random numbers drive both).
#[test]
fn six_million_triangles_render_as_their_coarse_mesh() {
    // Texture coordinates (x, y): the shading tangent ∂p/∂u orients the BSDF's
    // samples (Mitsuba's sh_frame), and with these uvs it is the same at every point
    // of either mesh (each plane's +x direction). Without uvs it would be each
    // triangle's first edge, which differs between the two triangulations, so the same
    // random numbers would sample other directions.
    let obj = "v -1 -1 0.5\nv 0 -1 0\nv 1 -1 0.5\nv -1 1 0.5\nv 0 1 0\nv 1 1 0.5\n\
               vt -1 -1\nvt 0 -1\nvt 1 -1\nvt -1 1\nvt 0 1\nvt 1 1\n\
               f 1/1 2/2 5/5\nf 1/1 5/5 4/4\nf 2/2 3/3 6/6\nf 2/2 6/6 5/5\n";
    common::temp_file("six-million", "valley.obj", obj);
    let xml = r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="4"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0, -1.2, 3.2" target="0, 0, 0.2" up="0, 0, 1"/></transform>
        <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/></film>
    </sensor>
    <shape type="obj">
        <string name="filename" value="valley.obj"/>
        <boolean name="face_normals" value="true"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.6, 0.4"/></bsdf>
    </shape>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
</scene>"#;
    let path = common::temp_file("six-million", "valley.xml", xml);
    let coarse = common::load(&path);
    // Face normals: the fine mesh's vertices get none either (Mitsuba's smooth
    // normals of the coarse fold would shade it differently).
    assert!(
        coarse.meshes[0].normals.is_empty(),
        "face_normals keeps no normals"
    );
    // The OBJ's v is flipped (Mitsuba's flip_tex_coords): uv = (x, 1 - y).
    let uv = |p: &glam::Vec3| glam::Vec2::new(p.x, 1.0 - p.y);
    let m = &coarse.meshes[0];
    assert!(
        m.uvs.len() == m.positions.len()
            && m.positions.iter().zip(&m.uvs).all(|(p, t)| uv(p) == *t)
    );
    let mut fine = coarse.clone();
    let (positions, indices) = valley(1733);
    assert!(indices.len() > 5_990_000);
    fine.meshes[0].uvs = positions.iter().map(uv).collect();
    fine.meshes[0].positions = positions;
    fine.meshes[0].indices = indices;

    let device = common::device();
    let spp = 4;
    let want = common::render(&device, &coarse, &RenderOptions::default(), spp);
    let mut r = Renderer::new(&device, &fine, &RenderOptions::default()).expect("setup");
    let plan = r.scene_plan().clone();
    let limit = 128 << 20;
    assert!(
        plan.bytes[0] > limit && plan.bytes[1] > limit,
        "BVH nodes and primitives should exceed 128 MiB: {:?}",
        plan.describe()
    );
    let got = r.render(spp, &mut |_, _| {}).expect("render").0;
    drop(r);
    // Rounding moves a hit point by about 1e-7 and can flip a rare discrete choice
    // (which side of a fold a grazing ray lands on); a lost or misplaced triangle
    // shows the sky (1.0) instead of the surface (below 0.8) in a pixel, a change
    // of at least 0.2 / spp in its mean.
    let mut worst = 0.0f32;
    for (a, b) in got.rgb.iter().zip(&want.rgb) {
        worst = worst.max((a - b).abs());
    }
    let mean = |img: &wavetrace::image::Image| common::mean(img);
    println!(
        "6 M triangles: worst pixel difference {worst:.2e}, means {:.5} / {:.5}",
        mean(&got),
        mean(&want)
    );
    assert!(worst < 0.02, "worst pixel difference {worst}");
    assert!((mean(&got) - mean(&want)).abs() < 1e-3 * mean(&want));
}
