//! Shapes as Mitsuba 3.9 makes them: for every Mitsuba shape wavetrace loads, rays
//! whose hits and misses Mitsuba recorded (tests/data/shape_hits.json, made by
//! tools/mitsuba_shapes.py from the shapes of scenes/shapes/) are traced on the GPU:
//! Mitsuba's misses must miss (a spurious hit is an error too), and at its hits the
//! point, normals, uv and shading tangent (sh_frame.s: ∂p/∂u made orthogonal to the
//! shading normal, which orients normal maps and anisotropic BSDFs) must be Mitsuba's. Covers the built-in tables of `cube` and `rectangle`,
//! the analytic `disk`, `sphere` and `cylinder`, OBJ, PLY (ascii and binary) and
//! serialized files with and without vertex normals, `face_normals`,
//! `flip_tex_coords`, `flip_normals` and `to_world` with shears and mirrors.

mod common;

use common::mitsuba_values::v3;
use common::SurfaceHit;
use glam::Vec3;
use serde_json::Value;

/// Distance between two uv values, u on a circle where the shape wraps around in u
/// (quadrics: u = φ / 2π; the disk's v).
fn uv_close(a: [f32; 2], b: [f32; 2], wrap: [bool; 2], tol: f32) -> bool {
    (0..2).all(|k| {
        let d = (a[k] - b[k]).abs();
        let d = if wrap[k] { d.min(1.0 - d) } else { d };
        d <= tol
    })
}

#[test]
fn every_shape_hits_like_mitsuba() {
    let text = std::fs::read_to_string(common::repo("tests/data/shape_hits.json"))
        .expect("tests/data/shape_hits.json (python3 tools/mitsuba_shapes.py)");
    let data: Value = serde_json::from_str(&text).unwrap();
    let mut failures = Vec::new();
    let mut checked = 0;
    let mut missed = 0;
    for case in data["cases"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let shape = case["shape"].as_str().unwrap();
        let hits = case["hits"].as_array().unwrap();
        let misses = case["misses"]
            .as_array()
            .expect("misses (python3 tools/mitsuba_shapes.py)");
        let rays: Vec<(Vec3, Vec3)> = hits
            .iter()
            .chain(misses)
            .map(|h| (v3(&h["o"]), v3(&h["d"])))
            .collect();
        let dir = common::repo("scenes/shapes");
        let found = common::surface_query(&common::shape_scene("shapes", name, &dir, shape), &rays);
        for (m, f) in misses.iter().zip(&found[hits.len()..]) {
            missed += 1;
            if let Some(SurfaceHit { p, t, .. }) = f {
                failures.push(format!(
                    "{name}: miss: ours a hit at {p} (t {t}), Mitsuba's none (ray {} {})",
                    m["o"], m["d"]
                ));
            }
        }
        let kind = shape.split('"').nth(1).unwrap_or("");
        let wrap = match kind {
            "sphere" | "cylinder" => [true, false],
            "disk" => [false, true],
            _ => [false, false],
        };
        for (h, f) in hits.iter().zip(&found) {
            checked += 1;
            let mut bad = |what: &str, ours: String, theirs: String| {
                failures.push(format!("{name}: {what}: ours {ours}, Mitsuba's {theirs}"));
            };
            let Some(SurfaceHit {
                p,
                t,
                ng,
                ns,
                ss,
                uv,
            }) = *f
            else {
                bad("hit", "a miss".into(), format!("t = {}", h["t"]));
                continue;
            };
            let t_mi = h["t"].as_f64().unwrap() as f32;
            let p_mi = v3(&h["p"]);
            // Positions and distances to float precision at the scene's scale (a few
            // units): Mitsuba intersects in object space, wavetrace in world space.
            let scale = 1.0 + p_mi.abs().max_element();
            if (t - t_mi).abs() > 2e-5 * (1.0 + t_mi) || (p - p_mi).length() > 2e-5 * scale {
                bad(
                    "point",
                    format!("{p} at t {t}"),
                    format!("{p_mi} at t {t_mi}"),
                );
            }
            let (n_mi, sh_n, sh_s) = (v3(&h["n"]), v3(&h["sh_n"]), v3(&h["sh_s"]));
            // wavetrace turns the geometric normal to the side of the shading normal
            // (Mitsuba keeps a mesh's face normal as its winding says, which a
            // mirroring to_world turns against the vertex normals).
            let n_expect = if n_mi.dot(sh_n) < 0.0 { -n_mi } else { n_mi };
            // Normals and tangents to 1e-4 (0.006 degrees): float rounding of
            // interpolated and transformed vectors.
            if (ng - n_expect).length() > 1e-4 {
                bad("geometric normal", ng.to_string(), n_expect.to_string());
            }
            // Rotations about a non-unit axis (Rodrigues' formula with the axis as
            // written, in both renderers) scale and shear; Mitsuba 3.9 then turns the
            // vertex normals by that matrix, not its inverse transpose, so its shading
            // normals lean off the surface. wavetrace keeps them perpendicular: only
            // points, geometric normals and uvs are compared there.
            let normals_as_mitsuba = !name.contains("nonunit");
            if normals_as_mitsuba && (ns - sh_n).length() > 1e-4 {
                bad("shading normal", ns.to_string(), sh_n.to_string());
            }
            if normals_as_mitsuba && (ss - sh_s).length() > 1e-3 {
                bad("shading tangent", ss.to_string(), sh_s.to_string());
            }
            let uv_mi = [
                h["uv"][0].as_f64().unwrap() as f32,
                h["uv"][1].as_f64().unwrap() as f32,
            ];
            if !uv_close(uv, uv_mi, wrap, 2e-5) {
                bad("uv", format!("{uv:?}"), format!("{uv_mi:?}"));
            }
        }
    }
    assert!(checked > 800, "only {checked} hits recorded");
    assert!(missed > 300, "only {missed} misses recorded");
    // One example per case and quantity, with how often it happened.
    let mut seen: Vec<(String, usize, String)> = Vec::new();
    for f in &failures {
        let key = f.split(": ours").next().unwrap_or(f).to_string();
        match seen.iter_mut().find(|(k, _, _)| *k == key) {
            Some(e) => e.1 += 1,
            None => seen.push((key, 1, f.clone())),
        }
    }
    let summary: Vec<String> = seen
        .iter()
        .map(|(_, n, example)| format!("{n:3} x {example}"))
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {checked} hits and {missed} misses differ from Mitsuba's:\n{}",
        failures.len(),
        summary.join("\n")
    );
}
