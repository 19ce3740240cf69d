//! Textures and environment-map lookups in their GLSL form (shaders/texture/texture.glsl
//! and envmap.glsl, through shaders/tests/texture_eval.comp) against the CPU
//! reference in src/scene/texture.rs and src/scene/envmap.rs, at random points.

mod common;

use glam::{Mat3, Vec2, Vec3};
use wavetrace::accel::{prims_from_scene, Bvh};
use wavetrace::gpu::layout::EMITTER_ENVMAP;
use wavetrace::gpu::{shaders, Kernel};
use wavetrace::image::Image;
use wavetrace::render::scene_buffers::SceneRecords;
use wavetrace::scene::texture::mesh_attribute;
use wavetrace::scene::{envmap, Emitter, Scene, Texture};

const N: u32 = 20_000;

/// Small xorshift generator: the test's random points, fixed by the seed.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// Runs the lookup kernel for `queries` on texture or envmap emitter `id`.
fn lookup(scene: &Scene, queries: &[[f32; 4]], id: u32, mode: u32) -> Vec<Vec3> {
    let device = common::device();
    let bvh = Bvh::build(prims_from_scene(scene));
    let records = SceneRecords::new(scene, &bvh);
    let (layout, buffers) = common::upload_scene(&device, &bvh, &records, 2, 12);
    let kernel = Kernel::new(
        &device,
        "texture_eval",
        shaders::TESTS_TEXTURE_EVAL,
        &layout,
        &[],
    )
    .unwrap();
    let raw = common::run_query_kernel(
        &device,
        &layout,
        &kernel,
        &buffers.set,
        queries,
        &[queries.len() as u32, id, mode],
    );
    raw.iter().map(|v| Vec3::new(v[0], v[1], v[2])).collect()
}

/// Writes a `w` x `h` test image whose texels all differ (a smooth ramp plus a hash),
/// as PNG (8-bit sRGB) and EXR (linear, values up to 8).
fn write_images(dir: &std::path::Path, w: u32, h: u32) {
    let mut png = image::RgbImage::new(w, h);
    let mut exr = Image::new(w, h);
    for y in 0..h {
        for x in 0..w {
            let k = (x * 7 + y * 13) % 17;
            let c = [(x * 255 / w) as u8, (y * 255 / h) as u8, (k * 15) as u8];
            png.put_pixel(x, y, image::Rgb(c));
            exr.set_pixel(
                x,
                y,
                [x as f32 / w as f32 * 8.0, y as f32 + 0.25, k as f32 / 17.0],
            );
        }
    }
    png.save(dir.join("t.png")).unwrap();
    exr.write_exr(dir.join("t.exr")).unwrap();
}

#[test]
fn gpu_texture_lookups_equal_the_cpu_reference() {
    let dir = common::temp_file("textures", "x", "")
        .parent()
        .unwrap()
        .to_path_buf();
    write_images(&dir, 7, 5);
    let xml = r#"<scene version="3.0.0">
    <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film></sensor>
    <texture type="bitmap" id="t0"><string name="filename" value="t.png"/></texture>
    <texture type="bitmap" id="t1"><string name="filename" value="t.png"/><string name="filter_type" value="nearest"/><string name="wrap_mode" value="mirror"/></texture>
    <texture type="bitmap" id="t2"><string name="filename" value="t.exr"/><string name="wrap_mode" value="clamp"/>
        <transform name="to_uv"><scale x="3" y="2"/><rotate z="1" angle="30"/><translate x="0.1" y="-0.3"/></transform></texture>
    <texture type="bitmap" id="t3"><string name="filename" value="t.png"/><boolean name="raw" value="true"/><string name="wrap_mode" value="mirror"/></texture>
    <texture type="bitmap" id="t4"><string name="filename" value="t.exr"/><string name="filter_type" value="nearest"/><string name="wrap_mode" value="clamp"/></texture>
    <texture type="checkerboard" id="t5"><rgb name="color0" value="0.9, 0.1, 0.2"/><rgb name="color1" value="0.05, 0.5, 0.7"/>
        <transform name="to_uv"><scale x="4" y="6"/></transform></texture>
    <texture type="noise" id="t6"><float name="frequency" value="5"/><integer name="octaves" value="6"/><integer name="seed" value="9"/>
        <rgb name="color0" value="0.1, 0.2, 0.3"/><rgb name="color1" value="0.9, 0.8, 0.1"/></texture>
    <texture type="marble" id="t7"><float name="frequency" value="3"/><float name="variation" value="2.5"/><integer name="octaves" value="3"/></texture>
    <texture type="rawconstant" id="t8"><vector name="value" value="-0.5, 2.0, 0.25"/></texture>
    <texture type="rawconstant" id="t9"><float name="value" value="1.75"/></texture>
    <shape type="rectangle"><bsdf type="diffuse"><ref name="reflectance" id="t0"/></bsdf></shape>
</scene>"#;
    let path = dir.join("scene.xml");
    std::fs::write(&path, xml).unwrap();
    let scene = common::load(&path);
    assert_eq!(scene.textures.len(), 10);

    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    // Uvs over [-2, 3]²: every wrap mode sees several periods; one in 16 over
    // [-200, 300]², where texel indices reach ±2000 (texture_wrap's remainder through
    // a float quotient).
    let uvs: Vec<[f32; 4]> = (0..N)
        .map(|i| {
            let s = if i % 16 == 0 { 100.0 } else { 1.0 };
            [
                s * (5.0 * rng.next() - 2.0),
                s * (5.0 * rng.next() - 2.0),
                0.0,
                0.0,
            ]
        })
        .collect();
    for (k, tex) in scene.textures.iter().enumerate() {
        let gpu = lookup(&scene, &uvs, k as u32 + 1, 0);
        let mut worst = 0f32;
        let mut differ = 0;
        for (q, g) in uvs.iter().zip(&gpu) {
            let c = tex.eval(Vec2::new(q[0], q[1]));
            let err = (c - *g).abs().max_element() / (1.0 + c.abs().max_element());
            worst = worst.max(err);
            // float rounding: 1e-4 relative; more is a different texel or formula.
            if err > 1e-4 {
                differ += 1;
            }
        }
        let kind = match tex {
            Texture::Bitmap { .. } => "bitmap",
            Texture::Checkerboard { .. } => "checkerboard",
            Texture::Noise { .. } => "noise",
            Texture::Marble { .. } => "marble",
            Texture::Constant { .. } => "rawconstant",
            Texture::MeshAttribute { .. } => "mesh_attribute",
        };
        println!(
            "texture {k} ({kind}): worst relative difference {worst:.2e}, {differ} of {N} differ"
        );
        // A lookup can land within an ulp of a texel or checker edge, where the GPU's
        // rounding may pick the other side: allow a handful in 20,000.
        assert!(
            differ <= 5,
            "texture {k} ({kind}): {differ} of {N} GPU lookups differ from the CPU reference (worst {worst:.2e})"
        );
    }
}

#[test]
fn gpu_envmap_lookups_equal_the_cpu_reference() {
    let dir = common::temp_file("textures-env", "x", "")
        .parent()
        .unwrap()
        .to_path_buf();
    write_images(&dir, 16, 8);
    let xml = r#"<scene version="3.0.0">
    <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film></sensor>
    <emitter type="envmap"><string name="filename" value="t.exr"/><float name="scale" value="1.5"/>
        <transform name="to_world"><rotate x="0.4364358" y="0.8728716" z="0.2182179" angle="70"/></transform></emitter>
    <shape type="rectangle"/>
</scene>"#;
    let path = dir.join("scene.xml");
    std::fs::write(&path, xml).unwrap();
    let scene = common::load(&path);
    let Emitter::EnvMap {
        texture,
        scale,
        to_world,
        ..
    } = scene.emitters[0].clone()
    else {
        panic!("not an envmap: {:?}", scene.emitters[0])
    };
    let Texture::Bitmap {
        width,
        height,
        texels,
        ..
    } = &scene.textures[texture as usize]
    else {
        panic!()
    };
    let bvh = Bvh::build(prims_from_scene(&scene));
    let records = SceneRecords::new(&scene, &bvh);
    let id = records
        .emitters
        .iter()
        .position(|e| e.kind == EMITTER_ENVMAP)
        .unwrap() as u32;
    let mut rng = Rng(0x1234_5678_9abc_def1);
    let dirs: Vec<[f32; 4]> = (0..N)
        .map(|_| {
            let d = Vec3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5).normalize();
            [d.x, d.y, d.z, 0.0]
        })
        .collect();
    let gpu = lookup(&scene, &dirs, id, 1);
    let to_local: Mat3 = to_world.transpose();
    let mut differ = 0;
    for (q, g) in dirs.iter().zip(&gpu) {
        let d = to_local * Vec3::new(q[0], q[1], q[2]);
        let c = envmap::eval(*width, *height, texels, envmap::direction_to_uv(d)) * scale;
        let err = (c - *g).abs().max_element() / (1.0 + c.abs().max_element());
        if err > 1e-3 {
            differ += 1;
        }
    }
    println!("envmap: {differ} of {N} lookups differ");
    assert!(
        differ <= 5,
        "{differ} of {N} envmap lookups differ from the CPU reference"
    );
}

/// A binary PLY of a fan of `n` triangles around vertex 0 in the z = 0 plane, as one
/// polygon face (so the fan's triangles share its face attributes) plus a lone
/// triangle; vertex attributes `r g b` (uchar: values as written, as Mitsuba's) and
/// `w_x` (float), face attributes `color_0..2` and `weight_0`.
fn write_attribute_ply(path: &std::path::Path) {
    let n = 5u32;
    let mut head = String::from("ply\nformat binary_little_endian 1.0\n");
    head += &format!("element vertex {}\n", n + 2 + 3);
    for p in ["x", "y", "z"] {
        head += &format!("property float {p}\n");
    }
    head += "property uchar r\nproperty uchar g\nproperty uchar b\nproperty float w_x\n";
    head += "element face 2\nproperty list uchar int vertex_indices\n";
    head += "property float color_0\nproperty float color_1\nproperty float color_2\nproperty float weight_0\nend_header\n";
    let mut b = head.into_bytes();
    let vertex = |b: &mut Vec<u8>, p: [f32; 3], c: [u8; 3], w: f32| {
        for v in p {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b.extend_from_slice(&c);
        b.extend_from_slice(&w.to_le_bytes());
    };
    vertex(&mut b, [0.0, 0.0, 0.0], [10, 20, 30], 0.5);
    for k in 0..=n {
        let a = k as f32 * 0.5;
        vertex(
            &mut b,
            [a.cos(), a.sin(), 0.0],
            [k as u8 * 40, 255 - k as u8 * 30, 7],
            k as f32 * 1.5 - 2.0,
        );
    }
    for (k, p) in [[3.0, 0.0, 0.0], [4.0, 0.0, 0.0], [3.0, 1.0, 0.0]]
        .iter()
        .enumerate()
    {
        vertex(&mut b, *p, [200, k as u8, 100], -1.0);
    }
    b.push(n as u8 + 2);
    for i in 0..n + 2 {
        b.extend_from_slice(&(i as i32).to_le_bytes());
    }
    for v in [0.25f32, 0.5, 0.75, 3.0] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.push(3);
    for i in [n + 2, n + 3, n + 4] {
        b.extend_from_slice(&(i as i32).to_le_bytes());
    }
    for v in [0.9f32, 0.1, 0.2, -4.0] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    std::fs::write(path, b).unwrap();
}

/// Mesh attributes (vertex ones interpolated, face ones per face, 1 and 3 channels,
/// scaled) looked up on the GPU at the surface point of a primitive equal
/// mesh_attribute::eval, on a mesh that follows another (its vertex and triangle
/// numbers do not start at 0) and whose polygon is fan-triangulated.
#[test]
fn gpu_mesh_attribute_lookups_equal_the_cpu_reference() {
    let dir = common::temp_file("textures-attr", "x", "")
        .parent()
        .unwrap()
        .to_path_buf();
    write_attribute_ply(&dir.join("fan.ply"));
    let names = ["vertex_color", "vertex_w", "face_color", "face_weight"];
    let textures: String = names
        .iter()
        .enumerate()
        .map(|(i, n)| {
            format!(
                r#"<texture type="mesh_attribute" id="t{i}"><string name="name" value="{n}"/><float name="scale" value="{}"/></texture>"#,
                1.0 + i as f32 * 0.5
            )
        })
        .collect();
    let xml = format!(
        r#"<scene version="3.0.0">
    <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film></sensor>
    {textures}
    <shape type="rectangle"><transform name="to_world"><translate z="5"/></transform></shape>
    <shape type="ply"><string name="filename" value="fan.ply"/><bsdf type="diffuse"><ref name="reflectance" id="t0"/></bsdf></shape>
    <shape type="sphere"><point name="center" x="0" y="0" z="-5"/></shape>
</scene>"#
    );
    let path = dir.join("attr.xml");
    std::fs::write(&path, xml).unwrap();
    let scene = common::load(&path);
    let bvh = Bvh::build(prims_from_scene(&scene));
    let mesh = &scene.meshes[1];
    assert_eq!(mesh.indices.len(), 6);
    let mut rng = Rng(0x5eed_1234_abcd_ef01);
    let mut queries = Vec::new();
    let mut want: Vec<Vec<Vec3>> = vec![Vec::new(); names.len()];
    for (slot, prim) in bvh.prims.iter().enumerate() {
        if prim.shape != 1 {
            continue;
        }
        let k = prim.index as usize - scene.meshes[0].indices.len();
        for _ in 0..8 {
            let (mut u, mut v) = (rng.next(), rng.next());
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            queries.push([f32::from_bits(slot as u32), u, v, 0.0]);
            for (i, n) in names.iter().enumerate() {
                let scale = 1.0 + i as f32 * 0.5;
                want[i].push(mesh_attribute::eval(mesh, n, scale, k, u, v).unwrap());
            }
        }
    }
    assert_eq!(queries.len(), 48);
    for (i, n) in names.iter().enumerate() {
        let gpu = lookup(&scene, &queries, i as u32 + 1, 2);
        for (g, c) in gpu.iter().zip(&want[i]) {
            let err = (*g - *c).abs().max_element() / (1.0 + c.abs().max_element());
            assert!(err < 1e-5, "{n}: GPU {g} vs CPU {c}");
        }
        println!("{n}: {} lookups agree", gpu.len());
    }
    // The PLY's values as written (uchar 255 stays 255) and the fan sharing its face.
    assert!(want[0][0].max_element() > 1.0);
    let face = mesh
        .attributes
        .iter()
        .find(|a| a.name == "face_weight")
        .unwrap();
    assert_eq!(face.values, vec![3.0, 3.0, 3.0, 3.0, 3.0, -4.0]);
}
