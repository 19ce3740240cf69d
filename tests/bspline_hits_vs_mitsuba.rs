//! B-spline curves as Mitsuba 3.9 makes them (`bsplinecurve`: cubic B-spline tubes
//! swept by a circle, Embree's round B-spline curves): rays whose hits and misses
//! Mitsuba recorded (tests/data/bspline_hits.json, made by tools/mitsuba_bsplines.py
//! from scenes/curves/bsplines.txt, plain and under a to_world) are traced on the GPU
//! (common::surface_query) and by accel::bspline on the CPU. Mitsuba's misses must
//! miss; at its hits the point, normals, uv (u around the curve, v along all its
//! segments) and shading tangent must be Mitsuba's.

mod common;

use common::mitsuba_values::v3;
use common::SurfaceHit;
use glam::Vec3;
use serde_json::Value;
use wavetrace::accel::bspline::intersect_bspline;
use wavetrace::scene::shape::bsplinecurve::segment_points;

fn data() -> Value {
    let text = std::fs::read_to_string(common::repo("tests/data/bspline_hits.json"))
        .expect("tests/data/bspline_hits.json (python3 tools/mitsuba_bsplines.py)");
    serde_json::from_str(&text).unwrap()
}

fn rays(case: &Value) -> (usize, Vec<(Vec3, Vec3)>) {
    let hits = case["hits"].as_array().unwrap();
    let misses = case["misses"].as_array().unwrap();
    let rays = hits
        .iter()
        .chain(misses)
        .map(|h| (v3(&h["o"]), v3(&h["d"])))
        .collect();
    (hits.len(), rays)
}

/// Compares what was `found` along each ray of `case` with Mitsuba's records; pushes
/// the differences to `failures`, the largest ones seen to `worst` (point relative to
/// 1 + t, normal, u, v).
fn compare(
    case: &Value,
    found: &[Option<SurfaceHit>],
    failures: &mut Vec<String>,
    worst: &mut [f32; 4],
) {
    let name = case["name"].as_str().unwrap();
    for (
        h,
        SurfaceHit {
            p,
            t,
            ng,
            ns,
            ss,
            uv,
        },
        ray,
    ) in common::hits_both_found(case, found, failures)
    {
        let t_mi = h["t"].as_f64().unwrap() as f32;
        let p_mi = v3(&h["p"]);
        // Float precision at the scene's scale (a few units), as for linear curves.
        if (t - t_mi).abs() > 2e-5 * (1.0 + t_mi) || (p - p_mi).length() > 2e-5 * 3.0 {
            failures.push(format!(
                "{name}: point: ours {p} at t {t}, Mitsuba's {p_mi} at t {t_mi} ({ray})"
            ));
        }
        // Normals from the hit point and the curve's centre: a point's rounding (2e-5)
        // over the thin hair's radius (0.008) tilts them by up to 2.5e-3.
        let n_mi = v3(&h["n"]);
        if (ng - n_mi).length() > 5e-3 || (ns - v3(&h["sh_n"])).length() > 5e-3 {
            failures.push(format!(
                "{name}: normal: ours {ng} {ns}, Mitsuba's {n_mi} ({ray})"
            ));
        }
        if ss != Vec3::ZERO && (ss - v3(&h["sh_s"])).length() > 5e-3 {
            failures.push(format!(
                "{name}: tangent: ours {ss}, Mitsuba's {} ({ray})",
                h["sh_s"]
            ));
        }
        let uv_mi = [
            h["uv"][0].as_f64().unwrap() as f32,
            h["uv"][1].as_f64().unwrap() as f32,
        ];
        // u wraps around the curve; v to float precision of the segment parameter.
        let du = (uv[0] - uv_mi[0]).abs();
        let errs = [
            (p - p_mi).length() / (1.0 + t_mi),
            (ng - n_mi).length(),
            du.min(1.0 - du),
            (uv[1] - uv_mi[1]).abs(),
        ];
        for (w, e) in worst.iter_mut().zip(errs) {
            *w = w.max(e);
        }
        if du.min(1.0 - du) > 1e-3 || (uv[1] - uv_mi[1]).abs() > 5e-5 {
            failures.push(format!(
                "{name}: uv: ours {uv:?}, Mitsuba's {uv_mi:?} ({ray})"
            ));
        }
    }
}

fn report(what: &str, data: &Value, failures: &[String], worst: [f32; 4]) {
    let cases = data["cases"].as_array().unwrap();
    let count = |k: &str| -> usize { cases.iter().map(|c| c[k].as_array().unwrap().len()).sum() };
    let (checked, missed) = (count("hits"), count("misses"));
    eprintln!(
        "{what}: largest differences from Mitsuba: point {:.1e} (relative to 1 + t), normal {:.1e}, u {:.1e}, v {:.1e}",
        worst[0], worst[1], worst[2], worst[3]
    );
    assert!(
        checked >= 400 && missed >= 400,
        "{checked} hits, {missed} misses"
    );
    assert!(
        failures.is_empty(),
        "{what}: {} of {checked} hits and {missed} misses differ from Mitsuba's:\n{}",
        failures.len(),
        failures[..failures.len().min(20)].join("\n")
    );
}

#[test]
fn bspline_curves_hit_like_mitsuba_on_the_gpu() {
    let data = data();
    let mut failures = Vec::new();
    let mut worst = [0.0f32; 4];
    for case in data["cases"].as_array().unwrap() {
        let (_, rays) = rays(case);
        let shape = case["shape"].as_str().unwrap();
        let dir = common::repo("scenes/curves");
        let name = case["name"].as_str().unwrap();
        let found =
            common::surface_query(&common::shape_scene("bsplines", name, &dir, shape), &rays);
        compare(case, &found, &mut failures, &mut worst);
    }
    report("GPU", &data, &failures, worst);
}

/// accel::bspline, the GLSL's mirror, against the same records: every segment tested
/// in turn (no tree), the geometry from accel::bspline::surface.
#[test]
fn bspline_curves_hit_like_mitsuba_on_the_cpu() {
    let data = data();
    let mut failures = Vec::new();
    let mut worst = [0.0f32; 4];
    for case in data["cases"].as_array().unwrap() {
        let (_, rays) = rays(case);
        let shape = case["shape"].as_str().unwrap();
        let dir = common::repo("scenes/curves");
        let name = case["name"].as_str().unwrap();
        let scene = common::load(&common::shape_scene("bsplines_cpu", name, &dir, shape));
        let m = &scene.meshes[0];
        let n = m.indices.len();
        let found: Vec<Option<SurfaceHit>> = rays
            .iter()
            .map(|&(o, d)| {
                let mut best: Option<(f32, f32, usize)> = None;
                for k in 0..n {
                    let tmax = best.map_or(f32::MAX, |b| b.0);
                    if let Some((t, u)) = intersect_bspline(o, d, &segment_points(m, k), 0.0, tmax)
                    {
                        best = Some((t, u, k));
                    }
                }
                best.map(|(t, u, k)| {
                    let p = o + t * d;
                    let (n_, around, dpdu) =
                        wavetrace::accel::bspline::surface(&segment_points(m, k), p, u);
                    SurfaceHit {
                        p,
                        t,
                        ng: n_,
                        ns: n_,
                        ss: (dpdu - n_ * n_.dot(dpdu)).normalize(),
                        uv: [around, (u + k as f32) / n as f32],
                    }
                })
            })
            .collect();
        compare(case, &found, &mut failures, &mut worst);
    }
    report("CPU", &data, &failures, worst);
}
