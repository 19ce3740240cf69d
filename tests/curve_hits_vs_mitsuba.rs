//! Curves as Mitsuba 3.9 makes them (`linearcurve`: round cone segments joined by
//! spheres, Embree's round linear curves): rays whose hits and misses Mitsuba recorded
//! (tests/data/curve_hits.json, made by tools/mitsuba_curves.py from
//! scenes/curves/curves.txt, plain and under a to_world) are traced on the GPU.
//! Mitsuba's misses must miss; at its hits the point, normals, uv (u around the curve,
//! v along all its segments) and shading tangent must be Mitsuba's.

mod common;

use common::mitsuba_values::v3;
use common::SurfaceHit;
use glam::Vec3;
use serde_json::Value;

#[test]
fn linear_curves_hit_like_mitsuba() {
    let text = std::fs::read_to_string(common::repo("tests/data/curve_hits.json"))
        .expect("tests/data/curve_hits.json (python3 tools/mitsuba_curves.py)");
    let data: Value = serde_json::from_str(&text).unwrap();
    let mut failures = Vec::new();
    let (mut checked, mut missed) = (0, 0);
    // The largest differences seen: point (relative to 1 + t), normal, u, v.
    let mut worst = [0.0f32; 4];
    for case in data["cases"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let hits = case["hits"].as_array().unwrap();
        let misses = case["misses"].as_array().unwrap();
        let rays: Vec<(Vec3, Vec3)> = hits
            .iter()
            .chain(misses)
            .map(|h| (v3(&h["o"]), v3(&h["d"])))
            .collect();
        let shape = case["shape"].as_str().unwrap();
        let dir = common::repo("scenes/curves");
        let found = common::surface_query(&common::shape_scene("curves", name, &dir, shape), &rays);
        missed += misses.len();
        checked += hits.len();
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
        ) in common::hits_both_found(case, &found, &mut failures)
        {
            let t_mi = h["t"].as_f64().unwrap() as f32;
            let p_mi = v3(&h["p"]);
            // Float precision at the scene's scale (a few units), as for the quadrics.
            if (t - t_mi).abs() > 2e-5 * (1.0 + t_mi) || (p - p_mi).length() > 2e-5 * 3.0 {
                failures.push(format!(
                    "{name}: point: ours {p} at t {t}, Mitsuba's {p_mi} at t {t_mi} ({ray})"
                ));
            }
            // Normals from the hit point and a centre on the axis: a point's rounding
            // (up to 2e-5 here, in either renderer) over the thin hair's radius (0.008)
            // tilts them by up to 2.5e-3 (1.7e-3 seen on lavapipe), and u by that / 2π.
            let n_mi = v3(&h["n"]);
            if (ng - n_mi).length() > 5e-3 || (ns - v3(&h["sh_n"])).length() > 5e-3 {
                failures.push(format!(
                    "{name}: normal: ours {ng} {ns}, Mitsuba's {n_mi} ({ray})"
                ));
            }
            if (ss - v3(&h["sh_s"])).length() > 5e-3 {
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
    eprintln!(
        "largest differences from Mitsuba: point {:.1e} (relative to 1 + t), normal {:.1e}, u {:.1e}, v {:.1e}",
        worst[0], worst[1], worst[2], worst[3]
    );
    assert!(
        checked >= 400 && missed >= 400,
        "{checked} hits, {missed} misses"
    );
    assert!(
        failures.is_empty(),
        "{} of {checked} hits and {missed} misses differ from Mitsuba's:\n{}",
        failures.len(),
        failures[..failures.len().min(20)].join("\n")
    );
}
