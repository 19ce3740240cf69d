//! Instancing on the GPU (`shapegroup` / `instance`, src/accel/instance.rs,
//! shaders/accel/instance.glsl): a scene of instances renders as the same shapes
//! written out one by one (flattened), with the same samples. The group holds a mesh
//! with vertex normals and uvs under a checkerboard (so the shading normal and the uvs
//! must follow each instance), a sphere and a rectangle; the instances turn, scale and
//! move it, and a floor outside the group shares the top-level tree with them.

mod common;

use common::{device, temp_dir};
use glam::{Mat3, Mat4, Quat, Vec3};
use wavetrace::image::Image;
use wavetrace::render::RenderOptions;

/// A tent of four triangles with vertex normals that are not the faces' (so the
/// shading normal shows whether it was mapped by the inverse transpose) and uvs.
const TENT_OBJ: &str = "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nv 0 0.8 0\n\
vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n\
vn -0.6 0.5 -0.6\nvn 0.6 0.5 -0.6\nvn 0.6 0.5 0.6\nvn -0.6 0.5 0.6\nvn 0 1 0\n\
f 1/1/1 5/5/5 2/2/2\nf 2/2/2 5/5/5 3/3/3\nf 3/3/3 5/5/5 4/4/4\nf 4/4/4 5/5/5 1/1/1\n";

/// The group's shapes, each with its own to_world (`{M}` is replaced by the matrix
/// that places it).
const SHAPES: [&str; 3] = [
    r#"<shape type="obj"><string name="filename" value="tent.obj"/>{M}
    <bsdf type="diffuse"><texture type="checkerboard" name="reflectance">
        <rgb name="color0" value="0.8 0.2 0.1"/><rgb name="color1" value="0.1 0.5 0.8"/>
        <transform name="to_uv"><scale x="4" y="4"/></transform></texture></bsdf></shape>"#,
    r#"<shape type="sphere">{M}<bsdf type="roughconductor"><float name="alpha" value="0.3"/></bsdf></shape>"#,
    r#"<shape type="rectangle">{M}<bsdf type="diffuse"><rgb name="reflectance" value="0.3 0.7 0.3"/></bsdf></shape>"#,
];

/// Each shape's own to_world in the group.
fn shape_maps() -> [Mat4; 3] {
    [
        Mat4::from_scale(Vec3::new(1.0, 1.4, 0.8)),
        Mat4::from_scale_rotation_translation(
            Vec3::splat(0.35),
            Quat::IDENTITY,
            Vec3::new(1.2, 0.4, 0.0),
        ),
        Mat4::from_rotation_translation(Quat::from_rotation_x(-1.2), Vec3::new(-1.0, 0.5, 0.8))
            * Mat4::from_scale(Vec3::splat(0.5)),
    ]
}

/// The instances' maps: turned, scaled (uniformly: a sphere stays one when written
/// out), moved.
fn instance_maps() -> Vec<Mat4> {
    (0..6)
        .map(|k| {
            let k = k as f32;
            Mat4::from_scale_rotation_translation(
                Vec3::splat(0.6 + 0.15 * k),
                Quat::from_rotation_y(0.9 * k) * Quat::from_rotation_x(0.2 * (k - 2.0)),
                Vec3::new(-4.0 + 1.8 * k, 0.3 * k - 0.5, 1.5 * (k % 2.0)),
            )
        })
        .collect()
}

fn matrix(m: &Mat4) -> String {
    let r = m.transpose().to_cols_array(); // row-major
    let v: Vec<String> = r.iter().map(|x| format!("{x:e}")).collect();
    format!(
        r#"<transform name="to_world"><matrix value="{}"/></transform>"#,
        v.join(" ")
    )
}

/// The scene around `body`: a camera, an environment and a floor.
fn scene(body: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
<integrator type="path"><integer name="max_depth" value="4"/></integrator>
<sensor type="perspective"><float name="fov" value="50"/>
  <transform name="to_world"><lookat origin="0, 6, 12" target="0, 0, 0" up="0, 1, 0"/></transform>
  <film type="hdrfilm"><integer name="width" value="96"/><integer name="height" value="64"/></film>
  <sampler type="independent"><integer name="sample_count" value="16"/></sampler></sensor>
<emitter type="constant"><rgb name="radiance" value="1"/></emitter>
<emitter type="point"><point name="position" x="3" y="8" z="4"/><rgb name="intensity" value="60"/></emitter>
<shape type="rectangle"><transform name="to_world"><scale value="10"/><rotate x="1" angle="-90"/><translate y="-1.5"/></transform>
  <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
{body}
</scene>"#
    )
}

fn instanced() -> String {
    let maps = shape_maps();
    let mut body = String::from(r#"<shape type="shapegroup" id="group">"#);
    for (s, m) in SHAPES.iter().zip(&maps) {
        body += &s.replace("{M}", &matrix(m));
    }
    body += "</shape>\n";
    for m in instance_maps() {
        body += &format!(
            r#"<shape type="instance"><ref id="group"/>{}</shape>"#,
            matrix(&m)
        );
    }
    scene(&body)
}

fn flattened() -> String {
    let maps = shape_maps();
    let mut body = String::new();
    for inst in instance_maps() {
        for (s, m) in SHAPES.iter().zip(&maps) {
            body += &s.replace("{M}", &matrix(&(inst * *m)));
        }
    }
    scene(&body)
}

fn render(name: &str, xml: &str) -> Image {
    render_with(name, xml, None, 16, 0)
}

/// Renders `xml` with `integrator` in place of the scene's (None: the scene's) and
/// `seed`.
fn render_with(name: &str, xml: &str, integrator: Option<&str>, spp: u32, seed: u32) -> Image {
    let dir = temp_dir("instancing");
    std::fs::write(dir.join("tent.obj"), TENT_OBJ).expect("write obj");
    let path = dir.join(name);
    std::fs::write(&path, xml).expect("write scene");
    let scene = wavetrace::scene::load(&path, &[]).unwrap_or_else(|e| panic!("{name}: {e}"));
    let options = RenderOptions {
        integrator: integrator.map(str::to_string),
        seed,
        ..RenderOptions::default()
    };
    common::render(&device(), &scene, &options, spp)
}

/// How many of the two images' values agree to 1e-3 (relative, or absolute below
/// 1e-2), and how many there are.
/// The instance maps, each stretching its object by `scale(1, 0.6 + 0.2 k, 1.3)`
/// first.
fn stretched_maps() -> Vec<Mat4> {
    instance_maps()
        .iter()
        .enumerate()
        .map(|(k, m)| *m * Mat4::from_scale(Vec3::new(1.0, 0.6 + 0.2 * k as f32, 1.3)))
        .collect()
}

fn agreeing_values(a: &Image, b: &Image) -> (usize, usize) {
    let close = a
        .rgb
        .iter()
        .zip(&b.rgb)
        .filter(|(x, y)| (*x - *y).abs() <= 1e-3 * x.abs().max(y.abs()).max(1e-2))
        .count();
    (close, a.rgb.len())
}

/// One tent (`SHAPES[0]` with `extra` after its transform) in a group placed by each
/// of `maps`, and the same tents written out: the two scene bodies.
fn tents_grouped_and_written(extra: &str, maps: &[Mat4]) -> (String, String) {
    let tent = SHAPES[0].replace("{M}", &format!("{{M}}{extra}"));
    let own = shape_maps()[0];
    let mut grouped = format!(
        r#"<shape type="shapegroup" id="group">{}</shape>"#,
        tent.replace("{M}", &matrix(&own))
    );
    let mut written = String::new();
    for m in maps {
        grouped += &format!(
            r#"<shape type="instance"><ref id="group"/>{}</shape>"#,
            matrix(m)
        );
        written += &tent.replace("{M}", &matrix(&(*m * own)));
    }
    (grouped, written)
}

/// The photon mappers and the particle tracer trace instances too (their light paths
/// meet, and their emitters' points and the camera's visible points lie on, mapped
/// primitives): each renders the instanced scene as the flattened one. Their light
/// paths diverge where a photon lands a rounding apart, so the two renders differ by
/// noise, not rounding: the worst 16 x 16 block difference between them must stay
/// within twice the one between two seeds of the flattened scene, and the means within
/// 1% (the particle tracer's 2%, or three times the two seeds' difference). Without the instance constants the kernels rendered the instances black (means
/// 30% apart); a wrong transform moves whole blocks.
#[test]
fn photon_mappers_and_the_particle_tracer_render_instances_as_their_shapes() {
    // The largest difference of 16 x 16 block means, relative to the mean of `b`.
    let worst_block = |a: &Image, b: &Image| {
        let block = |img: &Image, bx: u32, by: u32| {
            let mut sum = 0.0;
            for y in 16 * by..16 * by + 16 {
                for x in 16 * bx..16 * bx + 16 {
                    sum += img.pixel(x, y).iter().map(|&v| v as f64).sum::<f64>();
                }
            }
            sum / (3.0 * 256.0)
        };
        let mb = common::mean(b);
        (0..a.height / 16)
            .flat_map(|by| (0..a.width / 16).map(move |bx| (bx, by)))
            .map(|(bx, by)| (block(a, bx, by) - block(b, bx, by)).abs() / mb)
            .fold(0.0, f64::max)
    };
    for (integrator, spp) in [("photonmapper", 4), ("sppm", 16), ("ptracer", 64)] {
        let a = render_with("instanced.xml", &instanced(), Some(integrator), spp, 0);
        let b = render_with("flattened.xml", &flattened(), Some(integrator), spp, 0);
        let c = render_with("flattened.xml", &flattened(), Some(integrator), spp, 1);
        let (ma, mb, mc) = (common::mean(&a), common::mean(&b), common::mean(&c));
        let (worst, noise) = (worst_block(&a, &b), worst_block(&c, &b));
        println!(
            "{integrator}: instanced mean {ma:.5}, flattened {mb:.5} (seed 1: {mc:.5}); blocks differ by at most {worst:.4} of the mean (two seeds: {noise:.4})"
        );
        assert!(ma > 0.05, "{integrator}: the scene is lit");
        // The particle tracer's mean at 64 spp moves by about 0.5% between seeds.
        let floor = if integrator == "ptracer" { 2e-2 } else { 1e-2 };
        let mean_bound = (floor * mb).max(3.0 * (mc - mb).abs());
        assert!(
            (ma - mb).abs() <= mean_bound,
            "{integrator}: means {ma} vs {mb} (two seeds {mc} vs {mb})"
        );
        assert!(
            worst <= 2.0 * noise,
            "{integrator}: a block differs by {worst} of the mean, two seeds by {noise}"
        );
    }
}

/// The same image within float noise: the instances' vertices are mapped on the GPU
/// (the flattened ones at load), so a few paths may take another turn where a ray
/// grazes an edge; everywhere else the pixels agree to rounding.
#[test]
fn instances_render_as_their_shapes_written_out() {
    let a = render("instanced.xml", &instanced());
    let b = render("flattened.xml", &flattened());
    assert_eq!((a.width, a.height), (b.width, b.height));
    let (close, n) = agreeing_values(&a, &b);
    let (ma, mb) = (common::mean(&a), common::mean(&b));
    println!("instanced mean {ma:.5}, flattened {mb:.5}; {close} of {n} values agree to 1e-3");
    assert!(ma > 0.05, "the scene is lit");
    assert!((ma - mb).abs() <= 2e-3 * mb, "means {ma} vs {mb}");
    // Measured on lavapipe: all 18432 agree; a path grazing an edge may differ.
    assert!(close as f64 >= 0.999 * n as f64, "{close} of {n} agree");
}

/// One instance that stretches unevenly (out of sight, below the floor) makes every
/// record general (the 3×4 rows, not a quaternion: accel::instance): the tents placed
/// by them render as the tents written out, to rounding.
#[test]
fn general_instance_records_render_as_their_shapes_written_out() {
    let mut maps = instance_maps();
    maps.push(
        Mat4::from_translation(Vec3::new(0.0, -50.0, 0.0))
            * Mat4::from_scale(Vec3::new(1.0, 0.6, 1.3)),
    );
    let (grouped, written) = tents_grouped_and_written("", &maps);
    let dir = temp_dir("instancing");
    std::fs::write(dir.join("tent.obj"), TENT_OBJ).expect("write obj");
    std::fs::write(dir.join("general_records.xml"), scene(&grouped)).expect("write scene");
    let loaded = wavetrace::scene::load(&dir.join("general_records.xml"), &[]).expect("load");
    let bvh = wavetrace::accel::instance::scene_bvh(&loaded).expect("bvh");
    let texels = bvh.two_level.expect("two levels").texels;
    assert_eq!(texels, wavetrace::accel::instance::GENERAL_TEXELS);
    let a = render("general.xml", &scene(&grouped));
    let b = render("general_flat.xml", &scene(&written));
    let (close, n) = agreeing_values(&a, &b);
    println!("{close} of {n} values agree to 1e-3");
    assert!(close as f64 >= 0.999 * n as f64, "{close} of {n} agree");
}

/// Without groups nothing changes: a scene is traced by its one tree, and one with
/// an unused group renders as the scene without it (its shapes are not seen).
#[test]
fn an_unused_group_is_not_seen() {
    let maps = shape_maps();
    let mut body = String::from(r#"<shape type="shapegroup" id="group">"#);
    for (s, m) in SHAPES.iter().zip(&maps) {
        body += &s.replace("{M}", &matrix(m));
    }
    body += "</shape>\n";
    let a = render("unused.xml", &scene(&body));
    let b = render("empty.xml", &scene(""));
    assert_eq!(a.rgb, b.rgb);
}

/// Unevenly stretched instances in sight (each tent by its own `scale(1, 0.6 + 0.2 k,
/// 1.3)` inside the instance's map) render as the tents written out, to rounding: the
/// faces' normals, uvs and tangents follow the instance. The tent is shaded by its
/// faces (`face_normals`): with vertex normals, given or computed, the two scenes
/// differ where the stretch is uneven (3234 of 18432 values here), in Mitsuba 3.9.1 as
/// in wavetrace (3942 of 18432 there; the instanced-minus-flattened shading normals of
/// the two renderers agree to 4e-4 at 64 spp, the normals differing by 0.05), since
/// written out each vertex normal is mapped and normalized before it is interpolated,
/// in an instance after; the geometric normals agree in both.
#[test]
fn unevenly_stretched_instances_render_as_their_shapes_written_out() {
    let (grouped, written) = tents_grouped_and_written(
        r#"<boolean name="face_normals" value="true"/>"#,
        &stretched_maps(),
    );
    let a = render("stretched.xml", &scene(&grouped));
    let b = render("stretched_flat.xml", &scene(&written));
    let (close, n) = agreeing_values(&a, &b);
    println!("{close} of {n} values agree to 1e-3");
    assert!(close as f64 >= 0.999 * n as f64, "{close} of {n} agree");
}

/// A sphere and a cylinder in a group under unevenly stretching instances become an
/// ellipsoid and an elliptic cylinder (in Mitsuba the instance maps its object's
/// interaction: the point and tangents by to_world, the normal by the inverse
/// transpose). At one sample a pixel (box filter) each pixel's position, geometric
/// normal and ∂p/∂u are one hit's: the position must lie on the mapped quadric, the
/// normal be the inverse transpose of the group's radial direction there, and ∂p/∂u
/// lie in the tangent plane. Computed from the mapped record as a sphere's, the normal
/// and the re-projected point were the round shape's (off by up to 0.2).
#[test]
fn unevenly_stretched_quadrics_have_the_inverse_transposed_normal() {
    let (centre, radius) = (Vec3::new(1.2, 0.4, 0.0), 0.35);
    let (base, axis, tube) = (Vec3::new(-1.0, 0.0, -0.5), Vec3::new(0.0, 0.9, 0.0), 0.3);
    let mut body = format!(
        r#"<shape type="shapegroup" id="group">
        <shape type="sphere"><point name="center" x="{}" y="{}" z="{}"/><float name="radius" value="{radius}"/></shape>
        <shape type="cylinder"><point name="p0" x="{}" y="{}" z="{}"/><point name="p1" x="{}" y="{}" z="{}"/><float name="radius" value="{tube}"/></shape></shape>"#,
        centre.x,
        centre.y,
        centre.z,
        base.x,
        base.y,
        base.z,
        base.x + axis.x,
        base.y + axis.y,
        base.z + axis.z
    );
    let maps = stretched_maps();
    for m in &maps {
        body += &format!(
            r#"<shape type="instance"><ref id="group"/>{}</shape>"#,
            matrix(m)
        );
    }
    let xml = scene(&body)
        .replace(
            r#"<integrator type="path"><integer name="max_depth" value="4"/></integrator>"#,
            r#"<integrator type="aov"><string name="aovs" value="pp:position,gn:geo_normal,du:dp_du"/></integrator>"#,
        )
        .replace(r#"<film type="hdrfilm">"#, r#"<film type="hdrfilm"><rfilter type="box"/>"#);
    let path = common::temp_file("instancing", "quadrics.xml", &xml);
    let scene = wavetrace::scene::load(&path, &[]).expect("load");
    let device = device();
    let mut r = wavetrace::render::Renderer::new(&device, &scene, &RenderOptions::default())
        .expect("renderer");
    let film = r.render_film(0, 1, &mut |_, _| {}).expect("render").0;
    let (names, values) = film.extra_channels();
    let at = |name: &str| {
        names
            .iter()
            .position(|n| n == name)
            .unwrap_or_else(|| panic!("no {name} in {names:?}"))
    };
    let (p_at, n_at, du_at) = (at("pp.X"), at("gn.X"), at("du.X"));
    let c = names.len();
    let (mut spheres, mut cylinders, mut worst_n, mut worst_du) = (0, 0, 0.0f32, 0.0f32);
    for px in values.chunks(c) {
        let v = |i: usize| Vec3::new(px[i], px[i + 1], px[i + 2]);
        let (p, ng, du) = (v(p_at), v(n_at), v(du_at));
        for m in &maps {
            let q = m.inverse().transform_point3(p);
            let to_world_normal =
                |n: Vec3| (Mat3::from_mat4(m.inverse()).transpose() * n).normalize();
            let mut radial_to = |n: Vec3| {
                worst_n = worst_n.max(1.0 - ng.dot(to_world_normal(n)).abs());
                worst_du = worst_du.max(du.normalize().dot(ng).abs());
            };
            let s = q - centre;
            let h = (q - base).dot(axis) / axis.length_squared();
            let radial = q - base - h * axis;
            if (s.length() - radius).abs() < 1e-3 * radius {
                spheres += 1;
                radial_to(s);
            } else if (radial.length() - tube).abs() < 1e-3 * tube && (0.0..=1.0).contains(&h) {
                cylinders += 1;
                radial_to(radial);
            }
        }
    }
    println!("{spheres} sphere and {cylinders} cylinder pixels; normals within {worst_n:e} (1 - |cos|), dp/du off the tangent plane by {worst_du:e}");
    assert!(
        spheres > 100 && cylinders > 100,
        "{spheres} sphere, {cylinders} cylinder pixels"
    );
    assert!(worst_n < 1e-4, "a normal is off by {worst_n} (1 - |cos|)");
    assert!(
        worst_du < 1e-3,
        "dp/du leaves the tangent plane by {worst_du}"
    );
}
