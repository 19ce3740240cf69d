//! Ellipsoids as Mitsuba 3.9 makes them (`ellipsoids`: closed-form hits, back faces
//! culled): rays whose hits and misses Mitsuba recorded (tests/data/ellipsoids_hits.json,
//! made by tools/mitsuba_ellipsoids.py from scenes/ellipsoids/ellipsoids.ply: plain,
//! with extent and scale_factor, under a to_world; rays from inside ellipsoids among
//! them) are traced on the GPU (common::surface_query) and on the CPU
//! (Ellipsoid::intersect, every ellipsoid in turn). Mitsuba's misses must miss; at its
//! hits the point and normals must be Mitsuba's and uv (0, 0).

mod common;

use common::mitsuba_values::v3;
use common::SurfaceHit;
use glam::Vec3;
use serde_json::Value;

fn data() -> Value {
    let text = std::fs::read_to_string(common::repo("tests/data/ellipsoids_hits.json"))
        .expect("tests/data/ellipsoids_hits.json (python3 tools/mitsuba_ellipsoids.py)");
    serde_json::from_str(&text).unwrap()
}

fn rays(case: &Value) -> Vec<(Vec3, Vec3)> {
    let hits = case["hits"].as_array().unwrap();
    let misses = case["misses"].as_array().unwrap();
    hits.iter()
        .chain(misses)
        .map(|h| (v3(&h["o"]), v3(&h["d"])))
        .collect()
}

fn scene_of(test: &str, case: &Value) -> std::path::PathBuf {
    let dir = common::repo("scenes/ellipsoids");
    let name = case["name"].as_str().unwrap();
    common::shape_scene(test, name, &dir, case["shape"].as_str().unwrap())
}

/// Compares what was `found` along each ray of `case` with Mitsuba's records; pushes
/// the differences to `failures`, the largest seen to `worst` (point relative to
/// 1 + t, normal).
fn compare(
    case: &Value,
    found: &[Option<SurfaceHit>],
    failures: &mut Vec<String>,
    worst: &mut [f32; 2],
) {
    let name = case["name"].as_str().unwrap();
    for (
        h,
        SurfaceHit {
            p, t, ng, ns, uv, ..
        },
        ray,
    ) in common::hits_both_found(case, found, failures)
    {
        let t_mi = h["t"].as_f64().unwrap() as f32;
        let p_mi = v3(&h["p"]);
        // Mitsuba's own roots stray from the exact (double) ones by up to 5.3e-5 of 1 + t
        // on the small ellipsoids of the extent case (3.7e-6 elsewhere; measured by
        // solving its stored ellipsoids in double): ours, in float, are within 1e-6.
        if (t - t_mi).abs() > 1e-4 * (1.0 + t_mi) || (p - p_mi).length() > 1e-4 * (1.0 + t_mi) {
            failures.push(format!(
                "{name}: point: ours {p} at t {t}, Mitsuba's {p_mi} at t {t_mi} ({ray})"
            ));
        }
        let n_mi = v3(&h["n"]);
        // A point 5e-5 off on a 0.1-wide ellipsoid tilts the normal by ~2e-3.
        if (ng - n_mi).length() > 5e-3 || (ns - v3(&h["sh_n"])).length() > 5e-3 {
            failures.push(format!(
                "{name}: normal: ours {ng} {ns}, Mitsuba's {n_mi} ({ray})"
            ));
        }
        if uv != [0.0, 0.0] {
            failures.push(format!("{name}: uv: ours {uv:?}, Mitsuba's (0, 0) ({ray})"));
        }
        worst[0] = worst[0].max((p - p_mi).length() / (1.0 + t_mi));
        worst[1] = worst[1].max((ng - n_mi).length());
    }
}

fn report(what: &str, data: &Value, failures: &[String], worst: [f32; 2]) {
    let cases = data["cases"].as_array().unwrap();
    let count = |k: &str| -> usize { cases.iter().map(|c| c[k].as_array().unwrap().len()).sum() };
    let (checked, missed) = (count("hits"), count("misses"));
    eprintln!(
        "{what}: largest differences from Mitsuba: point {:.1e} (relative to 1 + t), normal {:.1e}",
        worst[0], worst[1]
    );
    assert!(
        checked >= 600 && missed >= 600,
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
fn ellipsoids_hit_like_mitsuba_on_the_gpu() {
    let data = data();
    let mut failures = Vec::new();
    let mut worst = [0.0f32; 2];
    for case in data["cases"].as_array().unwrap() {
        let found = common::surface_query(&scene_of("ellipsoids", case), &rays(case));
        compare(case, &found, &mut failures, &mut worst);
    }
    report("GPU", &data, &failures, worst);
}

#[test]
fn ellipsoids_hit_like_mitsuba_on_the_cpu() {
    let data = data();
    let mut failures = Vec::new();
    let mut worst = [0.0f32; 2];
    for case in data["cases"].as_array().unwrap() {
        let scene = common::load(&scene_of("ellipsoids_cpu", case));
        let ells = &scene.meshes[0].ellipsoids;
        let found: Vec<Option<SurfaceHit>> = rays(case)
            .iter()
            .map(|&(o, d)| {
                let mut best: Option<(f32, usize)> = None;
                for (k, e) in ells.iter().enumerate() {
                    let tmax = best.map_or(f32::MAX, |b| b.0);
                    if let Some(t) = e.intersect(o, d, 0.0, tmax) {
                        best = Some((t, k));
                    }
                }
                best.map(|(t, k)| {
                    let p = o + t * d;
                    let n = ells[k].normal(p);
                    SurfaceHit {
                        p,
                        t,
                        ng: n,
                        ns: n,
                        ss: Vec3::ZERO,
                        uv: [0.0, 0.0],
                    }
                })
            })
            .collect();
        compare(case, &found, &mut failures, &mut worst);
    }
    report("CPU", &data, &failures, worst);
}

/// `ellipsoidsmesh` (tests/data/ellipsoidsmesh_hits.json, tools/mitsuba_ellipsoidsmesh.py:
/// the same file as Mitsuba's icosahedron shells, plain and under a to_world, and box
/// shells with extent and scale_factor; no ray starts inside a shell, where Mitsuba
/// culls back faces and wavetrace does not): the GPU finds Mitsuba's hits and misses,
/// its points, its flat normals and its uv (a mesh without uvs: the barycentrics).
#[test]
fn ellipsoidsmesh_hits_like_mitsuba_on_the_gpu() {
    let text = std::fs::read_to_string(common::repo("tests/data/ellipsoidsmesh_hits.json"))
        .expect("tests/data/ellipsoidsmesh_hits.json (python3 tools/mitsuba_ellipsoidsmesh.py)");
    let data: Value = serde_json::from_str(&text).unwrap();
    let mut failures = Vec::new();
    let mut worst = [0.0f32; 3];
    for case in data["cases"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let found = common::surface_query(&scene_of("ellipsoidsmesh", case), &rays(case));
        for (
            h,
            SurfaceHit {
                p, t, ng, ns, uv, ..
            },
            ray,
        ) in common::hits_both_found(case, &found, &mut failures)
        {
            let t_mi = h["t"].as_f64().unwrap() as f32;
            let p_mi = v3(&h["p"]);
            let n_mi = v3(&h["n"]);
            let uv_mi = [
                h["uv"][0].as_f64().unwrap() as f32,
                h["uv"][1].as_f64().unwrap() as f32,
            ];
            let duv = (uv[0] - uv_mi[0]).abs().max((uv[1] - uv_mi[1]).abs());
            if (t - t_mi).abs() > 1e-5 * (1.0 + t_mi) || (p - p_mi).length() > 1e-5 * (1.0 + t_mi) {
                failures.push(format!(
                    "{name}: point: ours {p} at t {t}, Mitsuba's {p_mi} at t {t_mi} ({ray})"
                ));
            }
            if (ng - n_mi).length() > 1e-4 || (ns - v3(&h["sh_n"])).length() > 1e-4 {
                failures.push(format!(
                    "{name}: normal: ours {ng} {ns}, Mitsuba's {n_mi} ({ray})"
                ));
            }
            if duv > 1e-4 {
                failures.push(format!(
                    "{name}: uv: ours {uv:?}, Mitsuba's {uv_mi:?} ({ray})"
                ));
            }
            worst[0] = worst[0].max((p - p_mi).length() / (1.0 + t_mi));
            worst[1] = worst[1].max((ng - n_mi).length());
            worst[2] = worst[2].max(duv);
        }
    }
    eprintln!(
        "ellipsoidsmesh: largest differences from Mitsuba: point {:.1e} (relative to 1 + t), \
         normal {:.1e}, uv {:.1e}",
        worst[0], worst[1], worst[2]
    );
    let count = |k: &str| -> usize {
        data["cases"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c[k].as_array().unwrap().len())
            .sum()
    };
    assert!(count("hits") >= 600 && count("misses") >= 600);
    assert!(
        failures.is_empty(),
        "{} differences from Mitsuba's ellipsoidsmesh:\n{}",
        failures.len(),
        failures[..failures.len().min(20)].join("\n")
    );
}

/// Loader errors name the file and the line, or the file and the ellipsoid.
#[test]
fn ellipsoids_loader_errors() {
    let dir = std::env::temp_dir().join("wavetrace_ellipsoids_errors");
    std::fs::create_dir_all(&dir).unwrap();
    let header = std::fs::read_to_string(common::repo("scenes/ellipsoids/ellipsoids.ply"))
        .unwrap()
        .lines()
        .take(18)
        .collect::<Vec<_>>()
        .join("\n")
        .replace("element vertex 16", "element vertex 1");
    let bad = dir.join("nan.ply");
    std::fs::write(
        &bad,
        format!("{header}\n0 0 0 0 0 1 0.5 -1 -1 nan 1 0 0 0\n"),
    )
    .unwrap();
    let cases = [
        (
            "<shape type=\"ellipsoids\"><string name=\"filename\" value=\"missing.ply\"/></shape>",
            vec!["missing.ply", "not found", ":4"],
        ),
        ("<shape type=\"ellipsoids\"/>", vec!["needs a 'filename'", ":4"]),
        (
            "<shape type=\"ellipsoids\"><string name=\"filename\" value=\"nan.ply\"/></shape>",
            vec!["nan.ply:19: ellipsoid 0: 'scale_2' is not finite"],
        ),
        (
            "<shape type=\"ellipsoids\"><string name=\"filename\" value=\"nan.ply\"/><float name=\"extent\" value=\"-1\"/></shape>",
            vec!["extent", "positive", ":4"],
        ),
        (
            "<shape type=\"ellipsoidsmesh\"><string name=\"filename\" value=\"nan.ply\"/><string name=\"shell\" value=\"uv_sphere\"/></shape>",
            vec!["'uv_sphere'", "not supported yet", ":4"],
        ),
        (
            "<shape type=\"ellipsoidsmesh\"><string name=\"filename\" value=\"nan.ply\"/><string name=\"shell\" value=\"ball\"/></shape>",
            vec!["unknown shell 'ball'", ":4"],
        ),
        (
            "<shape type=\"ellipsoidsmesh\"><string name=\"filename\" value=\"nan.ply\"/></shape>",
            vec!["nan.ply:19: ellipsoid 0: 'scale_2' is not finite"],
        ),
    ];
    for (i, (shape, wants)) in cases.iter().enumerate() {
        let path = common::shape_scene("ellipsoids_errors", &format!("e{i}"), &dir, shape);
        let err = wavetrace::scene::load(&path, &[]).unwrap_err().to_string();
        eprintln!("case {i}: {err}");
        for w in wants {
            assert!(err.contains(w), "case {i}: '{err}' lacks '{w}'");
        }
    }
}

/// With B-spline curves in the same scene (moved out of the way), whose control points
/// come first in the grid buffer, the ellipsoids' side table still lines up.
#[test]
fn ellipsoids_after_bspline_curves() {
    let data = data();
    let case = &data["cases"][0];
    let shape = format!(
        "<shape type=\"bsplinecurve\"><string name=\"filename\" value=\"../curves/bsplines.txt\"/><transform name=\"to_world\"><translate value=\"100, 0, 0\"/></transform></shape>\n{}",
        case["shape"].as_str().unwrap()
    );
    let dir = common::repo("scenes/ellipsoids");
    let scene = common::shape_scene("ellipsoids_curves", "both", &dir, &shape);
    let found = common::surface_query(&scene, &rays(case));
    let mut failures = Vec::new();
    let mut worst = [0.0f32; 2];
    compare(case, &found, &mut failures, &mut worst);
    assert!(
        failures.is_empty(),
        "{}",
        failures[..failures.len().min(10)].join("\n")
    );
}
