//! Media against answers known in closed form or by an independent computation:
//! Beer-Lambert transmittance through a slab (camera rays and shadow rays, homogeneous
//! and grid), a white furnace of a non-absorbing medium, and dense scattering against
//! a float64 random walk on the host.

mod common;

use std::path::Path;

use common::media::{assert_finite, render_stats, vol_bytes};
use wavetrace::image::Image;

/// A grid of density 1 everywhere but one corner voxel of 4: with a single majorant
/// (majorant_resolution_factor 0) tracking in the constant part sees a majorant 4
/// times the extinction, so delta tracking takes null collisions and ratio tracking
/// multiplies real factors (3/4) rather than 0 or 1.
fn constant_grid_file(test: &str) -> std::path::PathBuf {
    let n = 8;
    let mut data = vec![1.0f32; n * n * n];
    data[0] = 4.0;
    let path = std::env::temp_dir().join(format!(
        "wavetrace-test-{}-{test}-const.vol",
        std::process::id()
    ));
    std::fs::write(&path, vol_bytes([n as i32; 3], &data)).expect("write vol");
    path
}

/// The slab's medium: homogeneous, or the constant grid on the slab's box.
fn slab_medium(kind: &str, sigma: f32, albedo: f32, z0: f32, z1: f32, vol: &Path) -> String {
    if kind == "homogeneous" {
        format!(
            r#"<medium type="homogeneous" name="interior"><rgb name="sigma_t" value="{sigma}"/><rgb name="albedo" value="{albedo}"/></medium>"#
        )
    } else {
        format!(
            r#"<medium type="heterogeneous" name="interior">
        <volume type="gridvolume" name="sigma_t"><string name="filename" value="{}"/>
            <transform name="to_world"><scale x="4" y="4" z="{}"/><translate x="-2" y="-2" z="{z0}"/></transform></volume>
        <float name="scale" value="{sigma}"/><rgb name="albedo" value="{albedo}"/>
        <integer name="majorant_resolution_factor" value="0"/></medium>"#,
            vol.display(),
            z1 - z0
        )
    }
}

/// A slab z in [z0, z1], x and y in [-2, 2], null boundary, with `medium` inside.
fn slab_shape(z0: f32, z1: f32, medium: &str) -> String {
    format!(
        r#"<shape type="cube"><bsdf type="null"/>
    <transform name="to_world"><scale x="2" y="2" z="{}"/><translate z="{}"/></transform>
    {medium}</shape>"#,
        0.5 * (z1 - z0),
        0.5 * (z0 + z1)
    )
}

/// Per pixel, the mean of its three channels (they are not independent samples).
fn pixel_means(img: &Image) -> Vec<f64> {
    img.rgb
        .chunks(3)
        .map(|c| (c[0] as f64 + c[1] as f64 + c[2] as f64) / 3.0)
        .collect()
}

/// Relative error allowed where a result is exact in exact arithmetic: lavapipe's
/// exp() is accurate to about 1e-4 relative, not to f32 rounding.
const EXACT: f64 = 5e-4;

/// Mean and standard error of the mean of `v`.
fn mean_se(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

/// Transmittance through a slab of thickness d = 0.5 and extinction 2 equals
/// e^{-σt d} = e^{-1}:
/// - camera rays (free-flight sampling) through the slab towards an emitter of
///   radiance 1, seen through a 2° field of view (slant paths at most 3e-4 longer):
///   homogeneous absorber (closed form, exact), homogeneous with albedo 0.5 (the ray
///   passes only if it samples no collision), and the constant grid (delta tracking
///   with null collisions);
/// - shadow rays from a white diffuse plane to a distant point light through the slab
///   (transmittance estimators): homogeneous (closed form, exact) and the constant
///   grid (ratio tracking), each as the pixel ratio to the same render without slab
///   (identical camera samples: same seed).
///
/// Stochastic cases: a z-test of the image mean (4.5 standard errors: a false alarm
/// has probability 7e-6).
#[test]
fn slab_transmittance_is_beer_lambert() {
    let device = common::device();
    let vol = constant_grid_file("slab");
    let (sigma, d) = (2.0f32, 0.5f32);
    let want = (-(sigma * d) as f64).exp();
    let sensor = |z: f32, fov: f32, res: u32| {
        format!(
            r#"<sensor type="perspective"><float name="fov" value="{fov}"/>
    <transform name="to_world"><lookat origin="0, 0, {z}" target="0, 0, -10" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="{res}"/><integer name="height" value="{res}"/><rfilter type="box"/></film></sensor>"#
        )
    };
    // Camera rays: the slab at z in [0, 0.5], an emitter at z = -2 facing the camera.
    for (kind, albedo, exact) in [
        ("homogeneous", 0.0, true),
        ("homogeneous", 0.5, false),
        ("grid", 0.5, false),
    ] {
        let xml = format!(
            r#"<scene version="3.0.0">
<integrator type="vol_path_simple"><integer name="max_depth" value="1"/></integrator>
{}
<shape type="rectangle"><transform name="to_world"><scale value="5"/><translate z="-2"/></transform>
    <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
{}
</scene>"#,
            sensor(5.0, 2.0, 32),
            slab_shape(0.0, d, &slab_medium(kind, sigma, albedo, 0.0, d, &vol)),
        );
        let path = common::temp_file("slab", &format!("camera_{kind}_{albedo}.xml"), &xml);
        let (img, stats) = render_stats(&device, &common::load(&path), None, 64, 1);
        assert_eq!(stats.discarded, 0);
        let px = pixel_means(&img);
        let (m, se) = mean_se(&px);
        println!("camera rays, {kind}, albedo {albedo}: mean {m:.5} ± {se:.5}, e^-1 = {want:.5}");
        if exact {
            assert!((m - want).abs() < EXACT * want, "{kind}: {m} vs {want}");
        } else {
            // Binomial standard error of the 65536 samples (each passes or not).
            let se = (want * (1.0 - want) / (px.len() as f64 * 64.0)).sqrt();
            assert!((m - want).abs() < 4.5 * se, "{kind}: {m} vs {want} ± {se}");
        }
    }
    // Shadow rays: a white plane at z = 0 seen from z = 1, the slab at z in [2, 2.5],
    // a point light at z = 1000 (irradiance 1 at the plane).
    let render_plane = |slab: &str, name: &str| {
        let xml = format!(
            r#"<scene version="3.0.0">
<integrator type="vol_path_mis"><integer name="max_depth" value="2"/></integrator>
{}
<emitter type="point"><point name="position" x="0" y="0" z="1000"/><rgb name="intensity" value="1000000"/></emitter>
<shape type="rectangle"><transform name="to_world"><scale value="3"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf></shape>
{slab}
</scene>"#,
            sensor(1.0, 10.0, 32)
        );
        let path = common::temp_file("slab", &format!("shadow_{name}.xml"), &xml);
        let (img, stats) = render_stats(&device, &common::load(&path), None, 16, 2);
        assert_eq!(stats.discarded, 0);
        img
    };
    let open = render_plane("", "open");
    for (kind, exact) in [("homogeneous", true), ("grid", false)] {
        let slab = slab_shape(
            2.0,
            2.0 + d,
            &slab_medium(kind, sigma, 0.5, 2.0, 2.0 + d, &vol),
        );
        let img = render_plane(&slab, kind);
        let ratios: Vec<f64> = pixel_means(&img)
            .iter()
            .zip(&pixel_means(&open))
            .map(|(&a, &b)| {
                assert!(b > 0.2, "the open plane is lit: {b}");
                a / b
            })
            .collect();
        let (m, se) = mean_se(&ratios);
        println!("shadow rays, {kind}: mean ratio {m:.5} ± {se:.5}, e^-1 = {want:.5}");
        if exact {
            assert!(
                ratios.iter().all(|r| (r - want).abs() < EXACT * want),
                "{kind}: closed form off"
            );
        } else {
            assert!(
                se > 0.0 && (m - want).abs() < 4.5 * se,
                "{kind}: {m} vs {want} ± {se}"
            );
        }
    }
}

/// White furnace: a non-absorbing medium (albedo 1) inside a null sphere, under a
/// constant environment of radiance 1 and nothing else, returns exactly 1 along every
/// ray. vol_path_simple with neither Russian roulette nor a depth limit within the 64
/// bounces dispatched carries weight exactly 1 on every sample (so does vol_path_mis
/// where the medium does not sample emitters; grey homogeneous and
/// grid media, here the smoke grid and a procedural cloud: scattering weights are the
/// albedo); vol_path_mis (emitter sampling with
/// transmittance, MIS) and coloured extinction are right on average (z-test of the
/// image mean, 4.5 standard errors).
#[test]
fn furnace_non_absorbing_medium_returns_the_light() {
    let device = common::device();
    let smoke = common::repo("scenes/media/smoke.vol");
    let media = [
        ("grey", r#"<medium type="homogeneous" name="interior"><rgb name="sigma_t" value="2"/><rgb name="albedo" value="1"/><phase type="hg"><float name="g" value="0.6"/></phase></medium>"#.to_string()),
        ("grey, no emitter sampling", r#"<medium type="homogeneous" name="interior"><rgb name="sigma_t" value="2"/><rgb name="albedo" value="1"/><boolean name="sample_emitters" value="false"/></medium>"#.to_string()),
        ("coloured", r#"<medium type="homogeneous" name="interior"><rgb name="sigma_t" value="0.1, 0.5, 1"/><float name="scale" value="3"/><rgb name="albedo" value="1"/></medium>"#.to_string()),
        ("grid", format!(r#"<medium type="heterogeneous" name="interior"><volume type="gridvolume" name="sigma_t"><string name="filename" value="{}"/>
            <transform name="to_world"><scale value="2"/><translate x="-1" y="-1" z="-1"/></transform></volume>
            <float name="scale" value="4"/><rgb name="albedo" value="1"/></medium>"#, smoke.display())),
        ("cloud", r#"<medium type="heterogeneous" name="interior"><volume type="cloud" name="sigma_t"><integer name="resolution" value="32"/>
            <transform name="to_world"><scale value="2"/><translate x="-1" y="-1" z="-1"/></transform></volume>
            <float name="scale" value="6"/><rgb name="albedo" value="1"/></medium>"#.to_string()),
    ];
    for (name, medium) in &media {
        let xml = format!(
            r#"<scene version="3.0.0">
<integrator type="vol_path_mis"><integer name="rr_depth" value="1000"/></integrator>
<sensor type="perspective"><float name="fov" value="30"/>
    <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/><rfilter type="box"/></film></sensor>
<emitter type="constant"><rgb name="radiance" value="1"/></emitter>
<shape type="sphere"><bsdf type="null"/>{medium}</shape>
</scene>"#
        );
        let file = format!("{}.xml", name.replace([' ', ','], "_"));
        let scene = common::load(&common::temp_file("furnace", &file, &xml));
        for integrator in ["vol_path_simple", "vol_path_mis"] {
            let (img, stats) = render_stats(&device, &scene, Some(integrator), 32, 3);
            assert_eq!(stats.discarded, 0);
            let px = pixel_means(&img);
            let (m, se) = mean_se(&px);
            let worst = img
                .rgb
                .iter()
                .map(|&v| (v as f64 - 1.0).abs())
                .fold(0.0, f64::max);
            println!("furnace {name}, {integrator}: mean {m:.5} ± {se:.5}, worst pixel off by {worst:.2e}");
            // Without emitter sampling in the medium vol_path_mis is exact too.
            let exact = (integrator == "vol_path_simple" && *name != "coloured")
                || name.ends_with("no emitter sampling");
            if exact {
                assert!(worst < 1e-4, "{name}: a pixel is off by {worst}");
            } else {
                assert!(
                    (m - 1.0).abs() < 4.5 * se.max(1e-6),
                    "{name}, {integrator}: {m} ± {se}"
                );
            }
        }
    }
}

/// The white-furnace sphere of `dense_scattering_matches_a_float64_random_walk` by an
/// independent random walk in f64: camera rays through uniform points of the image
/// plane (pinhole at z = 5 looking down -z, 20° field of view), free flights of rate
/// σt, HG scattering, escape within `max_depth` segments (max_depth - 1 scatterings)
/// seen as radiance 1, as is every ray that misses the unit sphere. Returns the image
/// mean and its standard error.
fn furnace_walk(sigma_t: f64, g: f64, max_depth: u32, paths: u32, seed: u64) -> (f64, f64) {
    use glam::DVec3;
    let mut rng = common::stats::SplitMix64(seed);
    let tan = 10f64.to_radians().tan();
    let exit = |x: DVec3, w: DVec3| {
        let b = x.dot(w);
        -b + (b * b - (x.length_squared() - 1.0)).max(0.0).sqrt()
    };
    let (mut sum, mut sum2) = (0.0, 0.0);
    for _ in 0..paths {
        let (px, py) = (
            (2.0 * rng.next_f64() - 1.0) * tan,
            (2.0 * rng.next_f64() - 1.0) * tan,
        );
        let mut w = DVec3::new(px, py, -1.0).normalize();
        let o = DVec3::new(0.0, 0.0, 5.0);
        let b = o.dot(w);
        let disc = b * b - (o.length_squared() - 1.0);
        let mut value = 1.0;
        if disc > 0.0 {
            value = 0.0;
            let mut x = o + (-b - disc.sqrt()) * w;
            for k in 0..max_depth {
                let s = exit(x, w);
                let t = -(1.0 - rng.next_f64()).ln() / sigma_t;
                if t >= s {
                    value = 1.0;
                    break;
                }
                if k + 1 == max_depth {
                    break;
                }
                x += t * w;
                let (u1, u2) = (rng.next_f64(), rng.next_f64());
                let cos = if g == 0.0 {
                    1.0 - 2.0 * u1
                } else {
                    let sq = (1.0 - g * g) / (1.0 - g + 2.0 * g * u1);
                    ((1.0 + g * g - sq * sq) / (2.0 * g)).clamp(-1.0, 1.0)
                };
                let sin = (1.0 - cos * cos).max(0.0).sqrt();
                let phi = 2.0 * std::f64::consts::PI * u2;
                let (e1, e2) = w.any_orthonormal_pair();
                w = (sin * phi.cos() * e1 + sin * phi.sin() * e2 + cos * w).normalize();
            }
        }
        sum += value;
        sum2 += value * value;
    }
    let n = paths as f64;
    let mean = sum / n;
    (mean, ((sum2 / n - mean * mean) / n).sqrt())
}

/// Dense scattering (σt = 1e4, albedo 1, isotropic; a unit sphere in a white sky, so
/// 9000 mean free paths across, truncated at 256 segments, no Russian roulette): the
/// image mean against the f64 random walk above. The unbounded case converges too
/// slowly for any test (scenes/media/README.md: paths of thousands of scatterings, and
/// Russian roulette makes the estimator's variance infinite), so the truncated one is
/// compared: every renderer must get the same number for it.
///
/// Measured (2 x 128 spp, 16 x 16; walk 300k paths): the walk 0.9213 ± 0.0005,
/// wavetrace 0.913 (-0.9%), Mitsuba 3.9 scalar_rgb 0.828 (-10%). Both lose light to
/// float32 positions: a step of 1e-4 on coordinates near 1 is rounded to 1.2e-7, and
/// components of a step below half an ulp vanish, which slows the walk (wavetrace with
/// the sphere moved to x = 8: -2.8%, to x = 100: -21%); Mitsuba also starts every ray
/// leaving a surface 1.8e-4 off it (its RayEpsilon of 8.9e-5 times 1 + |p|), two mean
/// free paths here. With g = 0.99 (a transport length of 100 scatterings) the walk
/// gives 0.3577 ± 0.0006, wavetrace 0.3590 ± 0.0006, Mitsuba 0.3512 ± 0.0006; at
/// σt = 100 all three agree to 0.03% (0.9273). So the tolerance here is 2%: it holds
/// wavetrace's float32 limit and fails a renderer as far off as Mitsuba.
#[test]
fn dense_scattering_matches_a_float64_random_walk() {
    let device = common::device();
    let xml = r#"<scene version="3.0.0">
<integrator type="volpath"><integer name="max_depth" value="256"/><integer name="rr_depth" value="100000"/></integrator>
<sensor type="perspective"><float name="fov" value="20"/>
    <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/><rfilter type="box"/></film></sensor>
<emitter type="constant"/>
<shape type="sphere"><bsdf type="null"/><medium type="homogeneous" name="interior">
    <rgb name="sigma_t" value="1"/><float name="scale" value="10000"/><rgb name="albedo" value="1"/></medium></shape>
</scene>"#;
    let scene = common::load(&common::temp_file("dense", "dense.xml", xml));
    let (a, sa) = render_stats(&device, &scene, None, 128, 1);
    let (b, sb) = render_stats(&device, &scene, None, 128, 2);
    assert_finite("dense sphere", &a, &sa);
    assert_finite("dense sphere", &b, &sb);
    let (ma, mb) = (common::mean(&a), common::mean(&b));
    let mean = 0.5 * (ma + mb);
    // Standard error of the mean of the two renders, from their per-pixel difference
    // (one channel: the medium is grey, the three are the same samples).
    let diffs: Vec<f64> = a
        .rgb
        .chunks_exact(3)
        .zip(b.rgb.chunks_exact(3))
        .map(|(x, y)| (x[0] - y[0]) as f64)
        .collect();
    let (_, se_diff) = mean_se(&diffs);
    let se = 0.5 * se_diff;
    let (walk, walk_se) = furnace_walk(1e4, 0.0, 256, 300_000, 9);
    let rel = mean / walk - 1.0;
    println!(
        "dense sphere: wavetrace {mean:.4} ± {se:.4} ({:.2} + {:.2} s), f64 walk {walk:.4} ± {walk_se:.4}: {:+.2}%",
        sa.seconds,
        sb.seconds,
        100.0 * rel
    );
    assert!(
        rel.abs() < 0.02,
        "dense sphere: {mean} ± {se} against the random walk's {walk} ± {walk_se}"
    );
}
