//! Mitsuba 3's `sdfgrid` as wavetrace traces it on the GPU: rays whose hits and misses
//! Mitsuba 3.9 recorded (tests/data/sdfgrid_hits.json, made by
//! tools/mitsuba_sdfgrid_hits.py on the torus grid of Mitsuba's regression suite, with
//! smooth and analytic normals, placed plainly, scaled and moved, and rotated: Mitsuba's
//! own rotated grid loses hits, its voxel boxes being the images of two corners, so
//! those are Mitsuba's hits of the grid placed by an instance) are traced with
//! surface_query.comp: Mitsuba's misses must miss, and at its hits the distance,
//! point, geometric and shading normals must be Mitsuba's. Then the loader's refusals:
//! a missing file, a grid of three channels or of one sample along an axis, an unknown
//! `normals`, an area emitter.

mod common;

use common::mitsuba_values::v3;
use common::SurfaceHit;
use glam::Vec3;
use serde_json::Value;

#[test]
fn torus_grid_hits_like_mitsuba() {
    let text = std::fs::read_to_string(common::repo("tests/data/sdfgrid_hits.json"))
        .expect("tests/data/sdfgrid_hits.json (python3 tools/mitsuba_sdfgrid_hits.py)");
    let data: Value = serde_json::from_str(&text).unwrap();
    let mut failures = Vec::new();
    let (mut checked, mut missed) = (0, 0);
    for case in data["cases"].as_array().unwrap() {
        let name = case["name"].as_str().unwrap();
        let shape = case["shape"].as_str().unwrap();
        let hits = case["hits"].as_array().unwrap();
        let misses = case["misses"].as_array().unwrap();
        let rays: Vec<(Vec3, Vec3)> = hits
            .iter()
            .chain(misses)
            .map(|h| (v3(&h["o"]), v3(&h["d"])))
            .collect();
        let dir = common::repo("../shared/scenes/mitsuba/regression/docs/scenes/sdfgrid");
        let found =
            common::surface_query(&common::shape_scene("sdfgrid", name, &dir, shape), &rays);
        for (m, f) in misses.iter().zip(&found[hits.len()..]) {
            missed += 1;
            if let Some(SurfaceHit { p, t, .. }) = f {
                failures.push(format!(
                    "{name}: miss: ours a hit at {p} (t {t}), Mitsuba's none (ray {} {})",
                    m["o"], m["d"]
                ));
            }
        }
        for (h, f) in hits.iter().zip(&found) {
            checked += 1;
            let mut bad = |what: &str, ours: String, theirs: String| {
                failures.push(format!("{name}: {what}: ours {ours}, Mitsuba's {theirs}"));
            };
            let Some(SurfaceHit { p, t, ng, ns, .. }) = *f else {
                bad("hit", "a miss".into(), format!("t = {}", h["t"]));
                continue;
            };
            let t_mi = h["t"].as_f64().unwrap() as f32;
            let p_mi = v3(&h["p"]);
            // Both solve the cubic to 1e-5 in t (Mitsuba's NumSolveEpsilon), from
            // different starting brackets (a voxel's tight box there, the voxel here).
            let scale = 1.0 + p_mi.abs().max_element();
            if (t - t_mi).abs() > 2e-5 * (1.0 + t_mi) || (p - p_mi).length() > 4e-5 * scale {
                bad(
                    "point",
                    format!("{p} at t {t}"),
                    format!("{p_mi} at t {t_mi}"),
                );
            }
            // Normals from the same samples at (nearly) the same point.
            let (n_mi, sh_n) = (v3(&h["n"]), v3(&h["sh_n"]));
            if (ng - n_mi).length() > 1e-3 {
                bad("geometric normal", ng.to_string(), n_mi.to_string());
            }
            if (ns - sh_n).length() > 1e-3 {
                bad("shading normal", ns.to_string(), sh_n.to_string());
            }
        }
    }
    assert!(checked > 400, "only {checked} hits recorded");
    assert!(missed > 400, "only {missed} misses recorded");
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

/// The load error of `shape` (with a grid file of `vol` bytes written beside it as
/// `grid.vol`, if given).
fn load_error(name: &str, shape: &str, vol: Option<Vec<u8>>) -> String {
    let dir = common::temp_dir("sdfgrid_errors");
    if let Some(bytes) = vol {
        std::fs::write(dir.join(format!("{name}.vol")), bytes).unwrap();
    }
    let xml =
        format!("<scene version=\"3.0.0\">\n<sensor type=\"perspective\"/>\n{shape}\n</scene>\n");
    let path = dir.join(format!("{name}.xml"));
    std::fs::write(&path, xml).unwrap();
    match wavetrace::scene::load(&path, &[]) {
        Ok(_) => panic!("{name}: loaded"),
        Err(e) => e.to_string(),
    }
}

fn vol(res: [i32; 3], channels: i32) -> Vec<u8> {
    let mut b = b"VOL\x03".to_vec();
    for v in [1, res[0], res[1], res[2], channels] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.extend_from_slice(&[0u8; 24]);
    let n = (res[0] * res[1] * res[2] * channels) as usize;
    for i in 0..n {
        b.extend_from_slice(&(i as f32 - 0.5 * n as f32).to_le_bytes());
    }
    b
}

fn grid_shape(name: &str, extra: &str) -> String {
    format!(
        "<shape type=\"sdfgrid\"><string name=\"filename\" value=\"{name}.vol\"/>{extra}</shape>"
    )
}

#[test]
fn bad_grids_are_refused_clearly() {
    let cases: [(&str, String, Option<Vec<u8>>, &str); 6] = [
        ("missing", grid_shape("missing", ""), None, "grid file"),
        (
            "rgb",
            grid_shape("rgb", ""),
            Some(vol([4, 4, 4], 3)),
            "3 channels, an sdfgrid has 1",
        ),
        (
            "flat",
            grid_shape("flat", ""),
            Some(vol([4, 1, 4], 1)),
            "at least 2 samples per axis",
        ),
        (
            "short",
            grid_shape("short", ""),
            Some(vol([4, 4, 4], 1)[..100].to_vec()),
            "float32 values need",
        ),
        (
            "normals",
            grid_shape("normals", "<string name=\"normals\" value=\"flat\"/>"),
            Some(vol([2, 2, 2], 1)),
            "none of \"analytic\", \"smooth\"",
        ),
        (
            "emitter",
            grid_shape(
                "emitter",
                "<emitter type=\"area\"><rgb name=\"radiance\" value=\"1\"/></emitter>",
            ),
            Some(vol([2, 2, 2], 1)),
            "cannot carry an area emitter",
        ),
    ];
    for (name, shape, bytes, want) in cases {
        let e = load_error(name, &shape, bytes);
        assert!(e.contains(want), "{name}: {e}");
        // file:line of the element and the parameter, said once.
        assert!(e.contains(&format!("{name}.xml:")), "{name}: {e}");
    }
    // A grid without a sign change holds no surface (Mitsuba refuses it too).
    let mut empty = vol([2, 2, 2], 1);
    let n = empty.len();
    for b in empty[48..n].chunks_exact_mut(4) {
        b.copy_from_slice(&1.0f32.to_le_bytes());
    }
    let e = load_error("empty", &grid_shape("empty", ""), Some(empty));
    assert!(
        e.contains("no voxel of the grid holds a sign change"),
        "{e}"
    );
}
