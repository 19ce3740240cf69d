//! Photon mapping (`render::photon`): the hash grid against a brute-force neighbour
//! search, the photon mapper against closed forms, determinism, and bad input.

mod common;

use std::collections::BTreeSet;
use std::mem::size_of;

use common::stats::SplitMix64;
use common::{device, temp_file};
use wavetrace::gpu::layout::{Photon, PhotonParams, Push};
use wavetrace::gpu::{
    shaders, BindingKind, BindingLayout, Buffer, CommandList, DescriptorSet, Kernel, Location,
};
use wavetrace::render::photon::{grid, photon_binding_kinds, GridShape, PhotonMap};
use wavetrace::render::scene_buffers::scene_binding_kinds;
use wavetrace::render::wavefront::wavefront_binding_kinds;

/// Entries per query of `shaders/tests/photon_neighbours.comp`: a count and up to 255
/// photon ids.
const RESULT_STRIDE: usize = 256;

/// The photons within each query's radius (xyz, w = radius) as the grid of `photons`
/// built on the GPU finds them, by their `path` ids.
fn gpu_neighbours(photons: &[Photon], queries: &[[f32; 4]], max_radius: f32) -> Vec<Vec<u32>> {
    let device = device();
    let layout = BindingLayout::with_kinds(
        &device,
        &[
            scene_binding_kinds(),
            wavefront_binding_kinds(),
            photon_binding_kinds(),
            vec![BindingKind::Storage, BindingKind::Storage],
        ],
        size_of::<Push>() as u32,
    )
    .expect("layout");
    let n = photons.len() as u32;
    let map = PhotonMap::new(&device, &layout, n, 1, 1).expect("photon map");
    map.store
        .photons
        .write(&device, 0, bytemuck::cast_slice(photons))
        .expect("upload photons");
    let max_abs = photons
        .iter()
        .flat_map(|p| p.position)
        .chain(queries.iter().flat_map(|q| [q[0], q[1], q[2]]))
        .fold(0f32, |m, v| m.max(v.abs()));
    let shape = GridShape::new(n, max_radius, max_abs, map.store.max_buckets);
    let params = PhotonParams {
        cell_size: shape.cell,
        inv_cell_size: 1.0 / shape.cell,
        table_mask: shape.buckets - 1,
        path_limit: u32::MAX,
        ..Default::default()
    };
    map.params
        .write(&device, 0, bytemuck::bytes_of(&params))
        .expect("parameters");
    let kernels = grid::GridKernels::new(&device, &layout).expect("grid kernels");
    let mut cmd = CommandList::new(&device).expect("commands");
    kernels.record(&mut cmd, &map, &map.set, n, shape.buckets);
    cmd.submit_and_wait().expect("grid build");

    let input = Buffer::from_slice(&device, "queries", queries).expect("queries");
    let out = Buffer::new(
        &device,
        "neighbours",
        (queries.len() * RESULT_STRIDE * 4) as u64,
        Location::Gpu,
    )
    .expect("results");
    let set = DescriptorSet::new(&layout, 3, &[&input, &out]).expect("query set");
    let kernel = Kernel::new(
        &device,
        "photon_neighbours",
        shaders::TESTS_PHOTON_NEIGHBOURS,
        &layout,
        &[],
    )
    .expect("kernel");
    let push = Push {
        path_count: queries.len() as u32,
        ..Default::default()
    };
    cmd.dispatch(
        &kernel,
        &[&map.set, &set],
        bytemuck::bytes_of(&push),
        [(queries.len() as u32).div_ceil(128), 1, 1],
    );
    cmd.submit_and_wait().expect("queries");
    let raw: Vec<u32> = out.read(&device).expect("read back");
    (0..queries.len())
        .map(|q| {
            let r = &raw[q * RESULT_STRIDE..(q + 1) * RESULT_STRIDE];
            let count = r[0] as usize;
            assert!(count < RESULT_STRIDE, "query {q} found {count} photons");
            r[1..=count].to_vec()
        })
        .collect()
}

/// The photons within each query's radius, by brute force, with the distance computed
/// as `photon_in_radius` does (grid.glsl); the test's coordinates keep it exact.
fn brute_force(photons: &[Photon], queries: &[[f32; 4]]) -> Vec<BTreeSet<u32>> {
    queries
        .iter()
        .map(|q| {
            photons
                .iter()
                .filter(|p| {
                    let d = [
                        p.position[0] - q[0],
                        p.position[1] - q[1],
                        p.position[2] - q[2],
                    ];
                    d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= q[3] * q[3]
                })
                .map(|p| p.path)
                .collect()
        })
        .collect()
}

fn photon(position: [f32; 3]) -> Photon {
    Photon {
        position,
        ..Default::default()
    }
}

/// A photon set and queries that probe the grid's corner cases: photons spread over
/// [-4, 4]³ and in a dense cluster, at multiples of 1/64 (so that every squared
/// distance is exact in f32, whatever the order and fusing of its sums); photons exactly
/// at the query radius along each axis and at the query point itself; photons exactly
/// on cell borders (multiples of the cell side, where `floor(p / side)` may round either
/// way), with queries on the same axis line (one non-zero coordinate of the difference,
/// so its square rounds alike on both sides) whose radius reaches just to them.
fn probe_set(seed: u64, max_radius: f32) -> (Vec<Photon>, Vec<[f32; 4]>) {
    let mut rng = SplitMix64(seed);
    let mut grid_coord = |range: i64| (rng.next_u64() % (2 * range as u64 + 1)) as i64 - range;
    let mut photons = Vec::new();
    let mut queries = Vec::new();
    for _ in 0..20_000 {
        let c = [0, 0, 0].map(|_: i32| grid_coord(256) as f32 / 64.0);
        photons.push(photon(c));
    }
    // A dense cluster: about 120 photons in a sphere of the largest radius.
    for _ in 0..2_000 {
        let c = [0, 0, 0].map(|_: i32| (64 + grid_coord(32)) as f32 / 64.0);
        photons.push(photon(c));
    }
    let radii = [max_radius, max_radius / 2.0, max_radius / 4.0];
    for k in 0..1500 {
        let x = [0, 0, 0].map(|_: i32| grid_coord(240) as f32 / 64.0);
        let r = radii[k % 3];
        queries.push([x[0], x[1], x[2], r]);
        // Exactly at the radius, on each axis, both ways; and at the point itself.
        for axis in 0..3 {
            for s in [-1.0, 1.0] {
                let mut p = x;
                p[axis] += s * r;
                photons.push(photon(p));
            }
        }
        photons.push(photon(x));
    }
    // Cell borders: the grid's cell side as GridShape picks it.
    let side = GridShape::new(
        photons.len() as u32 + 4000,
        max_radius,
        4.5,
        grid::MAX_BUCKETS,
    )
    .cell;
    for _ in 0..1000 {
        let k = grid_coord(7) as f32;
        let (y, z) = (grid_coord(200) as f32 / 64.0, grid_coord(200) as f32 / 64.0);
        let border = k * side;
        photons.push(photon([border, y, z]));
        photons.push(photon([y, border, z]));
        let r = radii[(grid_coord(1) + 1) as usize % 3];
        // Queries inside and outside the border cell, reaching just to it, and past it.
        for dx in [-r, r, -0.5 * r, 0.5 * r] {
            queries.push([border + dx, y, z, r]);
            queries.push([y, border + dx, z, r]);
        }
    }
    for (i, p) in photons.iter_mut().enumerate() {
        p.path = i as u32;
    }
    (photons, queries)
}

#[test]
fn grid_finds_the_same_neighbours_as_brute_force() {
    let max_radius = 0.25;
    for seed in [1u64, 2, 3] {
        let (photons, queries) = probe_set(seed, max_radius);
        let expected = brute_force(&photons, &queries);
        let found = gpu_neighbours(&photons, &queries, max_radius);
        let mut at_radius = 0;
        let mut total = 0;
        for (q, (want, got)) in expected.iter().zip(&found).enumerate() {
            let got_set: BTreeSet<u32> = got.iter().copied().collect();
            assert_eq!(
                got.len(),
                got_set.len(),
                "seed {seed}, query {q}: a photon was found twice"
            );
            assert_eq!(
                &got_set, want,
                "seed {seed}, query {q} {:?}: grid and brute force disagree",
                queries[q]
            );
            total += want.len();
            at_radius += want
                .iter()
                .filter(|&&i| {
                    let p = photons[i as usize].position;
                    let d: f32 = (0..3).map(|c| (p[c] - queries[q][c]).powi(2)).sum();
                    d == queries[q][3] * queries[q][3]
                })
                .count();
        }
        // The probe set must exercise what it claims: many neighbours, thousands of
        // them exactly at the radius.
        assert!(
            total > 30_000 && at_radius > 8_000,
            "{total} neighbours, {at_radius} at the radius"
        );
        println!(
            "seed {seed}: {} photons, {} queries, {total} neighbours ({at_radius} exactly at the radius): all found",
            photons.len(),
            queries.len()
        );
    }
}

/// Writes `text` as a scene file for `test` and loads it.
fn scene(test: &str, text: &str) -> wavetrace::scene::Scene {
    let path = temp_file("photon", &format!("{test}.xml"), text);
    common::load(&path)
}

#[test]
fn photon_mappers_refuse_media_and_scenes_without_emitters() {
    let device = device();
    let media = scene(
        "media",
        r#"<scene version="3.0.0">
            <integrator type="sppm"/>
            <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>
            <medium type="homogeneous" id="fog"><rgb name="sigma_t" value="1"/><rgb name="albedo" value="0.5"/></medium>
            <shape type="sphere"><ref name="interior" id="fog"/><bsdf type="null"/></shape>
            <emitter type="point"><point name="position" x="0" y="3" z="0"/><rgb name="intensity" value="1"/></emitter>
        </scene>"#,
    );
    let e = wavetrace::render::Renderer::new(&device, &media, &Default::default())
        .err()
        .expect("a photon mapper refuses media");
    assert!(e.to_string().contains("participating media"), "{e}");
    let dark = scene(
        "dark",
        r#"<scene version="3.0.0">
            <integrator type="photonmapper"/>
            <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>
            <shape type="sphere"/>
        </scene>"#,
    );
    let e = wavetrace::render::Renderer::new(&device, &dark, &Default::default())
        .err()
        .expect("a photon mapper needs an emitter");
    assert!(e.to_string().contains("needs an emitter"), "{e}");
}

/// Irradiance on the plane z = 0 at (x, y) from a point light of intensity `i` at
/// height `h` above the origin: E = I cos θ / d² = I h / (h² + ρ²)^{3/2}.
fn point_light_irradiance(i: f64, h: f64, x: f64, y: f64) -> f64 {
    i * h / (h * h + x * x + y * y).powf(1.5)
}

/// The mean of `f` over the disk of radius `r` around (cx, cy) (midpoint rule in polar
/// coordinates, 96 x 96 cells: far below the test's noise for these smooth functions).
fn disk_mean(f: impl Fn(f64, f64) -> f64, cx: f64, cy: f64, r: f64) -> f64 {
    let n = 96;
    let (mut sum, mut area) = (0.0, 0.0);
    for a in 0..n {
        let rho = r * (a as f64 + 0.5) / n as f64;
        for b in 0..n {
            let phi = std::f64::consts::TAU * (b as f64 + 0.5) / n as f64;
            sum += f(cx + rho * phi.cos(), cy + rho * phi.sin()) * rho;
            area += rho;
        }
    }
    sum / area
}

/// The photon mapper's density estimate on a diffuse plane (albedo ρ = 0.5) under a
/// point light of intensity 1 at height 1 (no other surface: photons stored at the
/// plane, the first hit, then lost), seen from above: each pixel must equal
/// (ρ/π) Ē, Ē the irradiance averaged over the gather disk (radius 0.4) and over the
/// pixel's footprint, within the estimate's noise: the photon count in a disk is
/// binomial, K ~ B(N, p) with p = Ē π r² / (4π I), so the estimate's standard deviation
/// is (ρ/π) 4π I / (π r² N) √(N p (1 - p)); and the pixel's camera samples, uniform over
/// its footprint, add the variance of Ē over the footprint / spp (measured: without it
/// the z-scores over several seeds had a variance of 5). The pixels tested lie more
/// than the disk's diameter apart, so their photons (and errors) are independent; each
/// must be within 4 standard deviations (a false alarm over 9 pixels: 6e-4; over seeds
/// 0-3 the 36 z-scores had a mean square of 0.9). The kernel bias is what
/// the disk mean accounts for: at the centre it is 10% (Ē = 0.894 against E = 1), and
/// the centre pixel must be more than 4 deviations from the unblurred value.
#[test]
fn photon_mapper_estimates_irradiance_under_a_point_light() {
    const SPP: u32 = 4;
    let (w, radius, fov) = (16u32, 0.4f64, 60.0f64);
    let text = format!(
        r#"<scene version="3.0.0">
            <integrator type="photonmapper">
                <integer name="photonCount" value="200000"/>
                <float name="photonRadius" value="{radius}"/>
            </integrator>
            <sensor type="perspective">
                <float name="fov" value="{fov}"/>
                <transform name="to_world"><lookat origin="0, 0, 2" target="0, 0, 0" up="0, 1, 0"/></transform>
                <film type="hdrfilm"><integer name="width" value="{w}"/><integer name="height" value="{w}"/></film>
            </sensor>
            <shape type="rectangle">
                <transform name="to_world"><scale value="50"/></transform>
                <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
            </shape>
            <emitter type="point"><point name="position" x="0" y="0" z="1"/><rgb name="intensity" value="1"/></emitter>
        </scene>"#
    );
    let sc = scene("point_plane", &text);
    let device = device();
    let mut r =
        wavetrace::render::Renderer::new(&device, &sc, &Default::default()).expect("renderer");
    let (img, stats) = r.render(SPP, &mut |_, _| {}).expect("render");
    let photons = stats.photons.expect("photon statistics");
    let n = photons.emitted as f64;
    // About half the photons head down to the plane.
    assert!(
        (photons.stored as f64 / n - 0.5).abs() < 0.01,
        "{photons:?}"
    );
    let (albedo, intensity, h) = (0.5f64, 1.0f64, 1.0f64);
    // Film position (pixels) to the plane point the camera ray meets (camera.glsl:
    // camera x is world -x, camera y world +y, looking down -z from z = 2).
    let t = (fov.to_radians() * 0.5).tan();
    let plane = |fx: f64, fy: f64| {
        let (nx, ny) = (fx / w as f64, fy / w as f64);
        ((2.0 * nx - 1.0) * 2.0 * t, (1.0 - 2.0 * ny) * 2.0 * t)
    };
    let blurred = |x: f64, y: f64| {
        disk_mean(
            |a, b| point_light_irradiance(intensity, h, a, b),
            x,
            y,
            radius,
        )
    };
    let scale = albedo / std::f64::consts::PI * 4.0 * std::f64::consts::PI * intensity
        / (std::f64::consts::PI * radius * radius * n);
    for py in [2u32, 8, 13] {
        for px in [2u32, 8, 13] {
            // The pixel's footprint, 8 x 8 sub-positions: the mean of the blurred
            // irradiance over it, and its variance, which the pixel's 4 camera samples
            // (uniform in the pixel) see as noise of their own.
            let sub: Vec<f64> = (0..64)
                .map(|s| {
                    let (x, y) = plane(
                        px as f64 + (s % 8) as f64 / 8.0 + 1.0 / 16.0,
                        py as f64 + (s / 8) as f64 / 8.0 + 1.0 / 16.0,
                    );
                    blurred(x, y)
                })
                .collect();
            let e = sub.iter().sum::<f64>() / 64.0;
            let var_e = sub.iter().map(|v| (v - e).powi(2)).sum::<f64>() / 64.0;
            let p = e * std::f64::consts::PI * radius * radius
                / (4.0 * std::f64::consts::PI * intensity);
            let sigma_photons = scale * (n * p * (1.0 - p)).sqrt();
            let sigma_camera = albedo / std::f64::consts::PI * (var_e / SPP as f64).sqrt();
            let sigma = (sigma_photons.powi(2) + sigma_camera.powi(2)).sqrt();
            let want = albedo / std::f64::consts::PI * e;
            let got = img.pixel(px, py)[1] as f64;
            let z = (got - want) / sigma;
            println!("pixel ({px}, {py}): {got:.5} against (ρ/π) Ē = {want:.5}, σ = {sigma:.5}, z = {z:.2}");
            assert!(
                z.abs() < 4.0,
                "pixel ({px}, {py}): {got} against {want} (σ {sigma})"
            );
            if (px, py) == (8, 8) {
                let (x, y) = plane(8.5, 8.5);
                let point =
                    albedo / std::f64::consts::PI * point_light_irradiance(intensity, h, x, y);
                let z_point = (got - point) / sigma;
                println!("  unblurred (ρ/π) E = {point:.5}: z = {z_point:.2}");
                assert!(z_point.abs() > 4.0, "the test cannot see the kernel bias");
            }
        }
    }
}

/// The shipped glass scene (a glass sphere and a mirror cube lit by a small area light)
/// at `res` pixels with `integrator` (an `<integrator>` element) instead of its own.
fn glass_scene(test: &str, res: u32, integrator: &str) -> wavetrace::scene::Scene {
    let text = std::fs::read_to_string(common::repo("scenes/glass/glass.xml")).expect("glass.xml");
    let start = text.find("<integrator").expect("an integrator");
    let end = text.find("</integrator>").expect("its end") + "</integrator>".len();
    let text = format!("{}{integrator}{}", &text[..start], &text[end..])
        .replace("value=\"128\"", &format!("value=\"{res}\""))
        .replace("<scene version", &format!("<!-- {test} --><scene version"));
    let path = temp_file("photon", &format!("{test}.xml"), &text);
    common::load(&path)
}

/// Largest difference between two images relative to the larger value (plus 1e-3).
fn max_relative_difference(a: &wavetrace::image::Image, b: &wavetrace::image::Image) -> f64 {
    a.rgb
        .iter()
        .zip(&b.rgb)
        .map(|(&x, &y)| (x as f64 - y as f64).abs() / (x.abs().max(y.abs()) as f64 + 1e-3))
        .fold(0.0, f64::max)
}

/// A render is a function of the scene and the seed: the same photon map and image
/// whatever the batch size and however many passes the photon map takes. The photon
/// sets are identical (their counts are compared exactly); the images may differ in
/// the last bits of float sums, whose order depends on the atomics of the grid build
/// and on how batches and passes group them (as the path tracer's film sums regroup
/// with the batch size): at most 1e-4 relative.
#[test]
fn photon_renders_do_not_depend_on_batch_size_or_passes() {
    let device = device();
    for (integrator, per_pass) in [
        (
            r#"<integrator type="photonmapper"><integer name="photonCount" value="40000"/><float name="photonRadius" value="0.15"/></integrator>"#,
            4000,
        ),
        (
            r#"<integrator type="sppm"><integer name="photonsperiteration" value="6000"/><float name="radius" value="0.2"/></integrator>"#,
            500,
        ),
    ] {
        let sc = glass_scene("determinism", 24, integrator);
        let render = |options: wavetrace::render::RenderOptions| {
            let mut r = wavetrace::render::Renderer::new(&device, &sc, &options).expect("renderer");
            r.render(3, &mut |_, _| {}).expect("render")
        };
        let (a, sa) = render(Default::default());
        let (b, sb) = render(wavetrace::render::RenderOptions {
            max_batch_paths: Some(1000),
            max_photons_per_pass: Some(per_pass),
            ..Default::default()
        });
        let (pa, pb) = (sa.photons.expect("stats"), sb.photons.expect("stats"));
        println!(
            "{}: {pa:?}\n  small batches and passes: {pb:?}",
            sc.integrator.name
        );
        assert_eq!((pa.emitted, pa.stored), (pb.emitted, pb.stored));
        assert!(
            pb.passes > pa.passes && pb.retraced > 0,
            "the small run took passes"
        );
        let d = max_relative_difference(&a, &b);
        println!("  largest relative difference {d:.2e}");
        assert!(d < 1e-4, "{}: images differ by {d}", sc.integrator.name);
    }
}
