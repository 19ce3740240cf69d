//! Emitter sampling in its GLSL form (shaders/emitter/emitter.glsl, through
//! shaders/tests/emitter_sample.comp): the emitter is chosen uniformly (as Mitsuba 3
//! and Nori choose) and a mesh light's triangle in proportion to area (chi-square
//! tests), and the density that MIS evaluates when a ray hits a light equals the
//! density with which emitter sampling produced that very point, and the sampled
//! directions follow that density (chi-square over a 2D histogram of directions).

mod common;

use common::stats::{chi2, sidak, SphereGrid};
use glam::Vec3;
use wavetrace::accel::{prims_from_scene, Bvh, FlatPrims};
use wavetrace::gpu::layout::{Frame, NONE};
use wavetrace::gpu::{shaders, Buffer, CommandList, DescriptorSet, Kernel, Location};
use wavetrace::render::scene_buffers::SceneRecords;
use wavetrace::scene::{envmap, Emitter, Scene, Texture};

const N: u32 = 200_000;
/// Chi-square tests in this file, for the Šidák correction of a 1% family level.
const TESTS: usize = 6;

struct Probe {
    wi: Vec3,
    pdf: f32,
    dist: f32,
    pdf_hit: f32,
    prim: u32,
    emitter: u32,
}

/// Samples N emitter points from `x` on the GPU.
fn probe(scene: &Scene, bvh: &Bvh, records: &SceneRecords, x: Vec3) -> Vec<Probe> {
    let _ = scene;
    run_probe(bvh, records, x, None, 0)
}

/// Runs shaders/tests/emitter_sample.comp: N samples from `x`, or, given `dirs`, the
/// density of emitter sampling from `x` in each direction (in `pdf_hit`), the emitter
/// choice handing out whole strata of `emitter_strata` (0: by the power cdf).
fn run_probe(
    bvh: &Bvh,
    records: &SceneRecords,
    x: Vec3,
    dirs: Option<&[[f32; 4]]>,
    emitter_strata: u32,
) -> Vec<Probe> {
    let device = common::device();
    let (layout, buffers) = common::upload_scene(&device, bvh, records, 3, 24);
    let count = dirs.map_or(N, |d| d.len() as u32);
    let frame = Frame {
        emitter_count: records.emitters.len() as u32,
        env_emitter: records.env_emitter,
        emitter_strata,
        ..Default::default()
    };
    let frame = Buffer::from_slice(&device, "frame", &[frame]).unwrap();
    let out = Buffer::new(&device, "probes", count as u64 * 32, Location::Gpu).unwrap();
    let dir_buf = Buffer::from_slice(&device, "directions", dirs.unwrap_or(&[[0.0; 4]])).unwrap();
    let set = DescriptorSet::new(&layout, 1, &[&frame, &out, &dir_buf]).unwrap();
    let kernel = Kernel::new(
        &device,
        "emitter_sample",
        shaders::TESTS_EMITTER_SAMPLE,
        &layout,
        &FlatPrims::of(bvh, 0).constants(),
    )
    .unwrap();
    let mut push = [0u32; 6];
    push[..3].copy_from_slice(&x.to_array().map(f32::to_bits));
    push[3] = count;
    push[4] = 11;
    push[5] = dirs.is_some() as u32;
    let mut cmd = CommandList::new(&device).unwrap();
    cmd.dispatch(
        &kernel,
        &[&buffers.set, &set],
        bytemuck::cast_slice(&push),
        [count.div_ceil(64), 1, 1],
    );
    cmd.submit_and_wait().unwrap();
    let raw: Vec<[f32; 4]> = out.read(&device).unwrap();
    raw.chunks(2)
        .take(count as usize)
        .map(|p| Probe {
            wi: Vec3::new(p[0][0], p[0][1], p[0][2]),
            pdf: p[0][3],
            dist: p[1][0],
            pdf_hit: p[1][1],
            prim: p[1][2].to_bits(),
            emitter: p[1][3].to_bits(),
        })
        .collect()
}

/// Four lights around the origin, facing it: a quad, a fan of four triangles of areas
/// 1/2 : 1 : 3 : 6, a sphere, and a point light.
fn scene() -> Scene {
    scene_with(["", "", "", ""])
}

/// `scene()` with `extra` inside each emitter (quad, fan, sphere, point light).
fn scene_with(extra: [&str; 4]) -> Scene {
    // Tests run in parallel: each call writes its own files.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let dir = format!(
        "emitters-{}",
        CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
    );
    let fan = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv -2 0 0\nv 0 -3 0\nv 4 0 0\n\
               f 1 2 3\nf 1 3 4\nf 1 4 5\nf 1 5 6\n";
    let obj = common::temp_file(&dir, "fan.obj", fan);
    let xml = format!(
        r#"<scene version="3.0.0">
    <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film></sensor>
    <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="180"/><translate value="0, 0, 3"/></transform>
        <emitter type="area"><rgb name="radiance" value="2, 1, 0.5"/>{}</emitter></shape>
    <shape type="obj"><string name="filename" value="{}"/>
        <transform name="to_world"><scale value="0.5"/><translate value="0, 0, -4"/></transform>
        <emitter type="area"><rgb name="radiance" value="1"/>{}</emitter></shape>
    <shape type="sphere"><point name="center" value="5, 0, 0"/><float name="radius" value="0.7"/>
        <emitter type="area"><rgb name="radiance" value="3"/>{}</emitter></shape>
    <emitter type="point"><point name="position" value="0, 4, 0"/><rgb name="intensity" value="2"/>{}</emitter>
</scene>"#,
        extra[0],
        obj.display(),
        extra[1],
        extra[2],
        extra[3]
    );
    common::load(&common::temp_file(&dir, "scene.xml", &xml))
}

/// Asserts that `probes` chose emitter i in proportion to `weights[i]` (chi-square at
/// this file's Šidák level); `rule` names the choice in the messages.
fn assert_emitter_choice(probes: &[Probe], weights: &[f64], rule: &str) {
    let total: f64 = weights.iter().sum();
    let mut observed = vec![0.0; weights.len()];
    for p in probes {
        observed[p.emitter as usize] += 1.0;
    }
    let expected: Vec<f64> = weights.iter().map(|w| w / total * N as f64).collect();
    let r = chi2(&observed, &expected);
    println!(
        "emitters {rule}: observed {observed:?}, expected {expected:?}, p = {:.4}",
        r.p_value
    );
    assert!(
        r.p_value > sidak(0.01, TESTS),
        "emitters are not chosen {rule}: p = {:.3e}",
        r.p_value
    );
}

#[test]
fn emitters_are_chosen_uniformly_and_triangles_by_area() {
    let s = scene();
    let bvh = Bvh::build(prims_from_scene(&s));
    let records = SceneRecords::new(&s, &bvh);
    let probes = probe(&s, &bvh, &records, Vec3::ZERO);
    let level = sidak(0.01, TESTS);

    // Every emitter alike, whatever its power, as Mitsuba 3 (sampling_weight 1 each)
    // and Nori choose.
    assert_emitter_choice(&probes, &vec![1.0; s.emitters.len()], "uniformly");

    // Triangles of the fan (shape 1) by area, from the triangles the sampled
    // directions hit.
    let first = s.meshes[0].indices.len() as u32;
    let mut tri = [0.0f64; 4];
    for p in probes.iter().filter(|p| p.prim != NONE) {
        let prim = bvh.prims[p.prim as usize];
        if prim.shape == 1 {
            tri[(prim.index - first) as usize] += 1.0;
        }
    }
    let n: f64 = tri.iter().sum();
    let fan = &s.meshes[1];
    let area: Vec<f64> = fan
        .indices
        .iter()
        .map(|t| {
            let p = t.map(|i| fan.positions[i as usize]);
            0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length() as f64
        })
        .collect();
    assert_eq!(area.len(), 4);
    let total_area: f64 = area.iter().sum();
    let expected: Vec<f64> = area.iter().map(|a| a / total_area * n).collect();
    let r = chi2(&tri, &expected);
    println!(
        "fan triangles: observed {tri:?}, expected {expected:?}, p = {:.4}",
        r.p_value
    );
    assert!(
        r.p_value > level,
        "triangles are not chosen by area: p = {:.3e}",
        r.p_value
    );
}

#[test]
fn sampled_directions_follow_the_density() {
    // From a point that sees every light, with no occluder between: the density of
    // emitter sampling in a direction is then what the MIS code evaluates at the light
    // the direction hits (zero where it hits none; the point light is a delta and
    // appears in no cell).
    let s = scene();
    let bvh = Bvh::build(prims_from_scene(&s));
    let records = SceneRecords::new(&s, &bvh);
    let x = Vec3::new(0.1, -0.2, 0.3);
    assert_directions_follow_the_density(&bvh, &records, x, "directions");
}

/// Chi-square test of the directions emitter sampling draws from `x` (non-delta
/// samples with pdf > 0) against the density `emitter_pdf_hit` reports along each
/// direction, over a 48 x 96 grid of the sphere. Returns the integral of that density
/// over the sphere (as the expected counts sum it), over N.
fn assert_directions_follow_the_density(
    bvh: &Bvh,
    records: &SceneRecords,
    x: Vec3,
    name: &str,
) -> f64 {
    let grid = SphereGrid::new(Vec3::new(0.3, 0.2, 1.0), 48, 96);
    let mut observed = vec![0.0; grid.cells()];
    for p in run_probe(bvh, records, x, None, 0) {
        if p.pdf > 0.0
            && p.dist.is_finite()
            && records.emitters[p.emitter as usize].kind != wavetrace::gpu::layout::EMITTER_POINT
        {
            if let Some(c) = grid.cell_of(p.wi) {
                observed[c] += 1.0;
            }
        }
    }
    // Expected counts: the density integrated over each cell at 4 x 4 points, and at
    // 48 x 48 where those disagree or all miss a cell that samples reached (cells a
    // light's outline crosses: the density jumps there, and a coarse rule would
    // misjudge how much of the cell the light covers).
    let cell_integrals = |cells: &[usize], k: usize| -> Vec<f64> {
        let (dirs, w) = grid.quadrature_of(cells, k);
        let pdf = run_probe(bvh, records, x, Some(&dirs), 0);
        (0..cells.len())
            .map(|c| {
                (c * k * k..(c + 1) * k * k)
                    .map(|q| pdf[q].pdf_hit as f64 * w[q])
                    .sum()
            })
            .collect()
    };
    let all: Vec<usize> = (0..grid.cells()).collect();
    let coarse = 4;
    let (dirs, _) = grid.quadrature_of(&all, coarse);
    let pdf = run_probe(bvh, records, x, Some(&dirs), 0);
    let edges: Vec<usize> = all
        .iter()
        .copied()
        .filter(|&c| {
            let v = &pdf[c * coarse * coarse..(c + 1) * coarse * coarse];
            let (lo, hi) = v.iter().fold((f32::MAX, 0f32), |(lo, hi), p| {
                (lo.min(p.pdf_hit), hi.max(p.pdf_hit))
            });
            (hi > 0.0 && lo < hi * 0.9) || (hi == 0.0 && observed[c] > 0.0)
        })
        .collect();
    let mut expected = cell_integrals(&all, coarse);
    for (c, v) in edges.iter().zip(cell_integrals(&edges, 48)) {
        expected[*c] = v;
    }
    let expected: Vec<f64> = expected.iter().map(|e| e * N as f64).collect();
    let r = chi2(&observed, &expected);
    let (o, e): (f64, f64) = (observed.iter().sum(), expected.iter().sum());
    println!(
        "{name}: {o} samples in cells, {e:.1} expected ({} of {} cells at 48 x 48), \
         X² = {:.1}, dof {}, p = {:.4}",
        edges.len(),
        grid.cells(),
        r.statistic,
        r.dof,
        r.p_value
    );
    assert!(
        r.p_value > sidak(0.01, TESTS),
        "{name}: sampled directions do not follow the density: p = {:.3e}",
        r.p_value
    );
    e / N as f64
}

#[test]
fn density_on_a_hit_equals_the_density_of_sampling_it() {
    let s = scene();
    let bvh = Bvh::build(prims_from_scene(&s));
    let records = SceneRecords::new(&s, &bvh);
    let point = records
        .emitters
        .iter()
        .position(|e| e.kind == wavetrace::gpu::layout::EMITTER_POINT)
        .unwrap();
    let mut checked = 0;
    let mut mismatched = 0;
    for p in probe(&s, &bvh, &records, Vec3::new(0.1, -0.2, 0.3)) {
        assert!(p.pdf.is_finite() && p.pdf >= 0.0 && p.wi.is_finite());
        if p.emitter as usize == point {
            // A delta light: its choice probability, at its true distance.
            assert_eq!(p.pdf, records.alias[point].pmf);
            let d = (Vec3::new(0.0, 4.0, 0.0) - Vec3::new(0.1, -0.2, 0.3)).length();
            assert!((p.dist - d).abs() < 1e-5 * d);
            continue;
        }
        assert!(
            p.pdf > 0.0,
            "every area light faces the point: no sample may fail"
        );
        checked += 1;
        if (p.pdf_hit - p.pdf).abs() > 1e-3 * p.pdf {
            mismatched += 1;
        }
    }
    // Directions grazing a sphere's rim can miss it in float arithmetic.
    println!("{mismatched} of {checked} samples disagree");
    assert!(checked > N as usize / 2);
    assert!(
        mismatched * 10_000 < checked,
        "{mismatched} of {checked} samples: pdf at the hit != sampling pdf"
    );
}

#[test]
fn environment_density_matches_on_escape() {
    let xml = r#"<scene version="3.0.0">
    <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film></sensor>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <shape type="sphere"><point name="center" value="3, 0, 0"/><float name="radius" value="1"/>
        <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
</scene>"#;
    let s = common::load(&common::temp_file("emitters", "env.xml", xml));
    let bvh = Bvh::build(prims_from_scene(&s));
    let records = SceneRecords::new(&s, &bvh);
    let env = records.env_emitter as usize;
    let mut escaped = 0;
    for p in probe(&s, &bvh, &records, Vec3::ZERO)
        .iter()
        .filter(|p| p.emitter as usize == env)
    {
        // Directions towards the sphere light hit it: the environment behind it is
        // not where the ray ends.
        if p.prim == NONE {
            escaped += 1;
            assert!(
                (p.pdf_hit - p.pdf).abs() <= 1e-6 * p.pdf,
                "{} vs {}",
                p.pdf_hit,
                p.pdf
            );
        }
    }
    assert!(
        escaped > N / 10,
        "only {escaped} environment samples escaped"
    );
}

/// An environment map with a small bright sun, turned by to_world: sampled directions
/// follow the density the sampler reports (chi-square over the map's lat-long cells,
/// expected counts from the solid-angle pdf of the CPU reference, scene::envmap), the
/// reported pdf equals that reference, and the density MIS evaluates on escape equals
/// the density of sampling.
#[test]
fn environment_map_sampling_matches_its_pdf() {
    let (w, h) = (64u32, 32u32);
    let mut sky = wavetrace::image::Image::new(w, h);
    for y in 0..h {
        for x in 0..w {
            let v = (y as f32 + 0.5) / h as f32;
            sky.set_pixel(
                x,
                y,
                [0.2 + 0.3 * (1.0 - v), 0.3 + 0.4 * (1.0 - v), 0.6 + 0.1 * v],
            );
        }
    }
    for (x, y) in [(40, 9), (41, 9), (40, 10), (41, 10)] {
        sky.set_pixel(x, y, [2000.0, 1800.0, 1500.0]);
    }
    let exr = common::temp_file("emitters-envmap", "sky.exr", "");
    sky.write_exr(&exr).unwrap();
    let xml = format!(
        r#"<scene version="3.0.0">
    <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film></sensor>
    <emitter type="envmap"><string name="filename" value="{}"/><float name="scale" value="2"/>
        <transform name="to_world"><rotate x="0.2822175" y="0.9407250" z="-0.1881450" angle="50"/></transform></emitter>
    <shape type="rectangle"><transform name="to_world"><scale value="0.01"/><translate value="0, 0, 100"/></transform></shape>
</scene>"#,
        exr.display()
    );
    let s = common::load(&common::temp_file("emitters-envmap", "scene.xml", &xml));
    let Emitter::EnvMap {
        texture, to_world, ..
    } = s.emitters[0].clone()
    else {
        panic!("{:?}", s.emitters[0])
    };
    let Texture::Bitmap { texels, .. } = &s.textures[texture as usize] else {
        panic!()
    };
    let dist = envmap::Distribution::build(w, h, texels, true);
    let bvh = Bvh::build(prims_from_scene(&s));
    let records = SceneRecords::new(&s, &bvh);
    let probes = probe(&s, &bvh, &records, Vec3::ZERO);

    // Bins of 2 x 2 map cells in (u, v); expected counts integrate the solid-angle pdf
    // over each bin, dω = 2π² sin θ du dv, by 4 x 4 midpoints (exact for a density
    // constant on cells).
    let (bu, bv) = (w as usize / 2, h as usize / 2);
    let to_local = to_world.transpose();
    let mut observed = vec![0.0; bu * bv];
    let (mut checked, mut mismatched) = (0, 0);
    for p in &probes {
        assert!(
            p.pdf > 0.0 && p.pdf.is_finite(),
            "no sample may fail: {}",
            p.pdf
        );
        let local = to_local * p.wi;
        let uv = envmap::direction_to_uv(local);
        let i = ((uv.x * bu as f32) as usize).min(bu - 1);
        let j = ((uv.y * bv as f32) as usize).min(bv - 1);
        observed[j * bu + i] += 1.0;
        let reference = dist.pdf(local) as f32;
        // Within rounding of a cell edge the two sides may pick different cells.
        let edge = |x: f32| (x - x.round()).abs() < 1e-3;
        if edge(uv.x * w as f32) || edge(uv.y * h as f32) {
            continue;
        }
        checked += 1;
        if (p.pdf - reference).abs() > 1e-3 * reference
            || (p.prim == NONE && (p.pdf_hit - p.pdf).abs() > 1e-3 * p.pdf)
        {
            mismatched += 1;
        }
    }
    let pi = std::f64::consts::PI;
    let k = 4;
    let mut expected = vec![0.0; bu * bv];
    for j in 0..bv {
        for i in 0..bu {
            let mut sum = 0.0;
            for a in 0..k {
                for b in 0..k {
                    let u = (i as f64 + (a as f64 + 0.5) / k as f64) / bu as f64;
                    let v = (j as f64 + (b as f64 + 0.5) / k as f64) / bv as f64;
                    let d = envmap::uv_to_direction(glam::Vec2::new(u as f32, v as f32));
                    let sin = (v * pi).sin();
                    sum += dist.pdf(d) * 2.0 * pi * pi * sin / (bu * bv * k * k) as f64;
                }
            }
            expected[j * bu + i] = sum * N as f64;
        }
    }
    let total: f64 = expected.iter().sum();
    assert!(
        (total / N as f64 - 1.0).abs() < 1e-3,
        "pdf integrates to {}",
        total / N as f64
    );
    let r = chi2(&observed, &expected);
    println!(
        "envmap sampling: chi2 {:.1}, dof {}, p = {:.4}; {mismatched} of {checked} pdfs disagree",
        r.statistic, r.dof, r.p_value
    );
    assert!(
        r.p_value > sidak(0.01, TESTS),
        "envmap samples do not follow the pdf: p = {:.3e}",
        r.p_value
    );
    // The sun's four texels carry most of the power: most samples go there.
    let sun = probes
        .iter()
        .filter(|p| {
            let uv = envmap::direction_to_uv(to_local * p.wi);
            (uv.x * w as f32 - 40.0).abs() < 3.0 && (uv.y * h as f32 - 10.0).abs() < 3.0
        })
        .count();
    assert!(sun > N as usize / 2, "only {sun} samples near the sun");
    assert!(
        mismatched * 10_000 < checked,
        "{mismatched} of {checked}: reported pdf != reference or != pdf on escape"
    );
}

/// With a stratifying sampler the emitter choice hands out whole strata
/// (shaders/emitter/emitter.glsl, emitter_choose): emitter i owns strata
/// [Q_i, Q_{i+1}) of k, Q_i = i + round((k - n) C_i) with C_i the power cdf. The
/// choice follows those probabilities (chi-square), delta lights report theirs, and the
/// density MIS evaluates on a hit is still the density of sampling that point.
#[test]
fn emitters_chosen_by_whole_strata_keep_their_densities() {
    let s = scene();
    let bvh = Bvh::build(prims_from_scene(&s));
    let records = SceneRecords::new(&s, &bvh);
    let n = records.emitters.len();
    assert_eq!(n, 4);
    // 11 strata: 7 to share by sampling weight, so the rounding matters.
    let k = 11u32;
    let cdf: Vec<f64> = records.alias[..n]
        .iter()
        .map(|e| f32::from_bits(e.prim) as f64)
        .collect();
    let q = |i: usize| -> f64 {
        if i >= n {
            k as f64
        } else {
            i as f64 + ((k as f64 - n as f64) * cdf[i] + 0.5).floor()
        }
    };
    let pmf: Vec<f64> = (0..n).map(|i| (q(i + 1) - q(i)) / k as f64).collect();
    assert!(pmf.iter().all(|&p| p >= 1.0 / k as f64));
    assert!((pmf.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    // The weights' pmf (1/4 each) is not a multiple of 1/11: the test sees the
    // difference.
    assert!(pmf
        .iter()
        .zip(&records.alias[..n])
        .any(|(q, e)| (q - e.pmf as f64).abs() > 0.02));

    let x = Vec3::new(0.1, -0.2, 0.3);
    let probes = run_probe(&bvh, &records, x, None, k);
    let (mut checked, mut mismatched) = (0, 0);
    for p in &probes {
        if records.emitters[p.emitter as usize].kind == wavetrace::gpu::layout::EMITTER_POINT {
            assert!((p.pdf as f64 - pmf[p.emitter as usize]).abs() < 1e-6);
            continue;
        }
        assert!(p.pdf > 0.0, "every area light faces the point");
        checked += 1;
        if (p.pdf_hit - p.pdf).abs() > 1e-3 * p.pdf {
            mismatched += 1;
        }
    }
    assert_emitter_choice(&probes, &pmf, &format!("by whole strata of {k}"));
    println!("{mismatched} of {checked} samples disagree");
    assert!(
        mismatched * 10_000 < checked,
        "{mismatched} of {checked} samples: pdf at the hit != sampling pdf"
    );
}

/// Lights whose radiance is an 8 x 4 bitmap with one texel 60 times brighter than the
/// rest and one black, around the origin, facing it: a rectangle (nearest filtering),
/// a sphere (bilinear, clamped, to_uv a quarter turn), a second rectangle (bilinear,
/// mirrored wrap, to_uv flipping u), all sampled by their texture, and a cube (its six
/// faces share the uv square: sampled by area).
fn textured_scene() -> Scene {
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let dir = format!(
        "emitters-textured-{}",
        CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
    );
    let mut img = wavetrace::image::Image::new(8, 4);
    for y in 0..4 {
        for x in 0..8 {
            img.set_pixel(x, y, [0.5 + 0.2 * x as f32, 1.0 + 0.3 * y as f32, 0.8]);
        }
    }
    img.set_pixel(5, 1, [60.0, 50.0, 40.0]);
    img.set_pixel(2, 3, [0.0; 3]);
    let exr = common::temp_file(&dir, "light.exr", "");
    img.write_exr(&exr).unwrap();
    let tex = |filter: &str, wrap: &str, to_uv: &str| {
        format!(
            r#"<texture type="bitmap" name="radiance"><string name="filename" value="{}"/>
            <string name="filter_type" value="{filter}"/><string name="wrap_mode" value="{wrap}"/>
            <transform name="to_uv">{to_uv}</transform></texture>"#,
            exr.display()
        )
    };
    let xml = format!(
        r#"<scene version="3.0.0">
    <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film></sensor>
    <shape type="rectangle"><transform name="to_world"><scale x="1.5" y="0.8"/><rotate x="1" angle="180"/><translate value="0, 0, 3"/></transform>
        <emitter type="area">{}</emitter></shape>
    <shape type="sphere"><point name="center" value="3, 0.5, 0"/><float name="radius" value="0.8"/>
        <emitter type="area">{}</emitter></shape>
    <shape type="rectangle"><transform name="to_world"><rotate z="1" angle="30"/><translate value="0, 0, -3"/></transform>
        <emitter type="area">{}</emitter></shape>
    <shape type="cube"><transform name="to_world"><scale value="0.5"/><translate value="0, -4, 0"/></transform>
        <emitter type="area">{}</emitter></shape>
</scene>"#,
        tex("nearest", "repeat", ""),
        tex(
            "bilinear",
            "clamp",
            r#"<rotate z="1" angle="90"/><translate x="1"/>"#
        ),
        tex("bilinear", "mirror", r#"<scale x="-1"/><translate x="1"/>"#),
        tex("nearest", "repeat", ""),
    );
    common::load(&common::temp_file(&dir, "scene.xml", &xml))
}

/// Textured emitters draw their points by their texture (scene::textured_emitter,
/// shaders/emitter/emitter_texture.glsl): the density MIS evaluates on a hit equals the
/// density of sampling that point, which equals the CPU reference's (the texture-space
/// density over the rectangle's area per unit uv, to solid angle), and the bright
/// texel gets the share of samples its luminance asks for.
#[test]
fn textured_emitters_are_sampled_by_their_texture() {
    use wavetrace::gpu::layout::{
        EMITTER_AREA, EMITTER_KIND_BIT_TEXTURE_SAMPLED, EMITTER_KIND_BIT_TEXTURE_SPHERE,
    };
    use wavetrace::scene::textured_emitter::{AffineUvMap, TextureSampling};
    let s = textured_scene();
    let bvh = Bvh::build(prims_from_scene(&s));
    let records = SceneRecords::new(&s, &bvh);
    // Emitters in scene order (no point lights): rectangle, sphere, rectangle, cube.
    let widths: Vec<u32> = records.emitters.iter().map(|e| e.dist_width).collect();
    assert_eq!(
        widths,
        [8, 8, 8, 0],
        "which emitters sample by their texture"
    );
    // The kernels' kinds: texture-sampled lights (one a sphere), and the cube's area
    // sampling.
    assert_eq!(
        records.emitter_kinds(),
        1 << EMITTER_KIND_BIT_TEXTURE_SAMPLED
            | 1 << EMITTER_KIND_BIT_TEXTURE_SPHERE
            | 1 << EMITTER_AREA
    );

    let x = Vec3::new(0.1, -0.2, 0.3);
    let Emitter::TexturedArea { texture, .. } = s.emitters[0] else {
        panic!("{:?}", s.emitters[0])
    };
    let sampling = TextureSampling::new(&s.textures[texture as usize]).unwrap();
    let map = AffineUvMap::of_mesh(&s.meshes[0]).unwrap();
    // uv of a point of the first rectangle: solve x - origin = u du + v dv.
    let uv_of = |y: Vec3| {
        let q = y - map.origin;
        let (a, b, c) = (map.du.dot(map.du), map.du.dot(map.dv), map.dv.dot(map.dv));
        let (e, f) = (q.dot(map.du), q.dot(map.dv));
        let det = a * c - b * b;
        glam::Vec2::new((c * e - b * f) / det, (a * f - b * e) / det)
    };
    let (mut checked, mut mismatched, mut reference_checked, mut bright) = (0, 0, 0, 0);
    for p in run_probe(&bvh, &records, x, None, 0) {
        assert!(p.pdf.is_finite() && p.pdf >= 0.0 && p.wi.is_finite());
        if p.pdf == 0.0 {
            continue; // the far side of the sphere or the cube
        }
        if p.emitter == 1 {
            // Near the sphere's outline the densities (∝ d² / cos) differ by the
            // rounding of cos, the normal found from the hit against the sampled one,
            // and grazing directions may miss: as for any area-sampled sphere.
            let e = &records.emitters[1];
            let y = x + p.wi * p.dist;
            let n = (y - Vec3::from(e.position)) / e.radius;
            if n.dot(-p.wi) < 0.02 {
                continue;
            }
        }
        checked += 1;
        if (p.pdf_hit - p.pdf).abs() > 1e-3 * p.pdf {
            mismatched += 1;
        }
        if p.emitter == 0 {
            let y = x + p.wi * p.dist;
            let uv = uv_of(y);
            let texel = uv * glam::Vec2::new(8.0, 4.0);
            if texel.floor() == glam::Vec2::new(5.0, 1.0) {
                bright += 1;
            }
            // Within rounding of a texel edge the two may pick different texels.
            let edge = |v: f32| (v - v.round()).abs() < 1e-3;
            if edge(texel.x) || edge(texel.y) {
                continue;
            }
            let cos = map.normal.dot(-p.wi);
            let reference = records.alias[0].pmf * sampling.density(sampling.texture_point(uv))
                / map.jacobian()
                * p.dist
                * p.dist
                / cos;
            reference_checked += 1;
            assert!(
                (p.pdf - reference).abs() < 1e-3 * reference,
                "pdf {} at uv {uv}, reference {reference}",
                p.pdf
            );
        }
    }
    println!(
        "{mismatched} of {checked} samples disagree; {reference_checked} checked against the CPU"
    );
    assert!(checked > N as usize / 2 && reference_checked > N as usize / 10);
    assert!(
        mismatched * 10_000 < checked,
        "{mismatched} of {checked} samples: pdf at the hit != sampling pdf"
    );
    // The bright texel's share of the first rectangle's samples: its luminance over
    // the texture's sum (about 0.56), against 1/32 for area sampling.
    let share = sampling.dist.cell_probability(5, 1);
    let first = records.alias[0].pmf as f64 * N as f64;
    let observed = bright as f64 / first;
    assert!(
        (observed - share).abs() < 0.02,
        "bright texel: {observed} of the rectangle's samples, {share} expected"
    );
}

/// The directions textured emitters draw follow the density MIS evaluates
/// (chi-square), which therefore integrates to the probability of a usable sample.
#[test]
fn textured_emitter_directions_follow_the_density() {
    let s = textured_scene();
    let bvh = Bvh::build(prims_from_scene(&s));
    let records = SceneRecords::new(&s, &bvh);
    let x = Vec3::new(0.1, -0.2, 0.3);
    let integral = assert_directions_follow_the_density(&bvh, &records, x, "textured directions");
    // The rectangles face x whole: their samples are all usable, so the density
    // integrates to at least their choice probabilities.
    let rectangles = (records.alias[0].pmf + records.alias[2].pmf) as f64;
    assert!(
        integral > rectangles && integral < 1.0,
        "{integral} vs {rectangles}"
    );
}

/// Mitsuba's `sampling_weight` sets how often emitter sampling chooses an emitter
/// (chi-square), and an impossible weight is an error that names it.
#[test]
fn emitters_are_chosen_in_proportion_to_their_sampling_weights() {
    let w = |v: &str| format!(r#"<float name="sampling_weight" value="{v}"/>"#);
    let (quad, fan, sphere, point) = (w("3"), String::new(), w("0.5"), w("2"));
    let s = scene_with([&quad, &fan, &sphere, &point]);
    let bvh = Bvh::build(prims_from_scene(&s));
    let records = SceneRecords::new(&s, &bvh);
    let probes = probe(&s, &bvh, &records, Vec3::ZERO);
    // The renderer's emitter order: point lights first, then the scene's.
    assert_emitter_choice(&probes, &[2.0, 3.0, 1.0, 0.5], "by sampling_weight");

    for (weights, message) in [
        (
            [w("-1"), w("1"), w("1"), w("1")],
            "sampling_weight must be a finite number >= 0",
        ),
        (
            [w("0"), w("0"), w("0"), w("0")],
            "every emitter has sampling_weight 0",
        ),
    ] {
        let dir = format!("emitters-weights-{}", message.len());
        let xml = r#"<scene version="3.0.0">
    <sensor type="perspective"/>
    <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/>A</emitter></shape>
    <shape type="sphere"><emitter type="area"><rgb name="radiance" value="1"/>B</emitter></shape>
    <emitter type="point">C</emitter>
    <emitter type="constant">D</emitter>
</scene>"#
            .replace('A', &weights[0])
            .replace('B', &weights[1])
            .replace('C', &weights[2])
            .replace('D', &weights[3]);
        let path = common::temp_file(&dir, "scene.xml", &xml);
        let err = wavetrace::scene::load(&path, &[])
            .expect_err(message)
            .to_string();
        assert!(err.contains(message), "{err}");
    }
}
