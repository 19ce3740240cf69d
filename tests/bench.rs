//! `wavetrace bench`: the table and the JSON it writes, and its errors.

mod common;

use common::{temp_file, wavetrace};
use serde_json::Value;

#[test]
fn ao_bench_prints_a_table_and_writes_json() {
    let json_path = temp_file("bench_ao", "ao.json", "");
    let json_arg = json_path.to_str().expect("utf-8 temp path");
    let (code, out, err) = wavetrace(&[
        "bench",
        "scenes/ao/ao.xml",
        "--ref",
        "scenes/refs/ao.exr",
        "--spp",
        "1,4",
        "--json",
        json_arg,
        "-q",
    ]);
    assert_eq!(code, 0, "stdout:\n{out}\nstderr:\n{err}");

    // The table: a header, then one line per sample count, in the order asked.
    let lines: Vec<&str> = out.lines().collect();
    let header = lines
        .iter()
        .position(|l| l.contains("relMSE") && l.contains("efficiency"))
        .unwrap_or_else(|| panic!("no table header in:\n{out}"));
    let rows: Vec<Vec<f64>> = lines[header + 1..header + 3]
        .iter()
        .map(|l| {
            l.split_whitespace()
                .map(|t| t.parse().unwrap_or_else(|_| panic!("bad number in {l:?}")))
                .collect()
        })
        .collect();
    assert_eq!(rows[0][0], 1.0);
    assert_eq!(rows[1][0], 4.0);
    for r in &rows {
        assert_eq!(
            r.len(),
            7,
            "spp seconds MSE RMSE relMSE Mrays/s efficiency: {r:?}"
        );
        // MSE is RMSE squared.
        assert!((r[2] - r[3] * r[3]).abs() <= 1e-3 * r[2], "{r:?}");
        assert!(r.iter().all(|v| v.is_finite() && *v > 0.0), "{r:?}");
    }
    assert!(
        out.contains("GPU time per kernel at 4 spp"),
        "no kernel times:\n{out}"
    );

    // The JSON holds the same rows and the context of the run.
    let text = std::fs::read_to_string(&json_path).expect("read the JSON");
    let v: Value = serde_json::from_str(&text).expect("valid JSON");
    assert_eq!(v["integrator"], "ao");
    assert_eq!(v["sampler"], "independent");
    assert_eq!(v["width"], 128);
    assert_eq!(v["height"], 128);
    assert!(v["device"].as_str().is_some_and(|d| !d.is_empty()));
    assert!(v["startup"]["pipeline_seconds"].as_f64().is_some());
    assert!(v["startup"]["warmup_seconds"].as_f64().is_some());
    let rows = v["rows"].as_array().expect("rows");
    assert_eq!(rows.len(), 2);
    let num = |r: &Value, k: &str| {
        r[k].as_f64()
            .unwrap_or_else(|| panic!("{k} is not a number in {r}"))
    };
    assert_eq!(num(&rows[0], "spp"), 1.0);
    assert_eq!(num(&rows[1], "spp"), 4.0);
    for r in rows {
        assert!(num(r, "seconds") > 0.0);
        assert!(num(r, "rays") >= 128.0 * 128.0 * num(r, "spp"));
        assert!(num(r, "efficiency") > 0.0);
        assert!(num(r, "mse") > 0.0);
        assert_eq!(num(r, "requested_spp"), num(r, "spp"));
    }
    // Per-kernel times for the largest count (from a render with timestamps of its
    // own); the timed renders record none.
    assert!(rows[1]["kernels"]["intersect"]["seconds"]
        .as_f64()
        .is_some());
    assert_eq!(rows[0]["kernels"].as_object().map(|k| k.len()), Some(0));
    // Four times the samples: relMSE falls about fourfold (unbiased AO, variance
    // ~ 1/spp; the reference's own relMSE, ~1e-4 at 16384 spp, is negligible). A
    // factor of 2.5 leaves room for noise in the 1-spp estimate of the error.
    let (e1, e4) = (num(&rows[0], "rel_mse"), num(&rows[1], "rel_mse"));
    assert!(e4 * 2.5 < e1, "relMSE {e1} at 1 spp, {e4} at 4 spp");
}

#[test]
fn bench_renders_the_count_the_sampler_rounds_to() {
    // --sampler stratified rounds 2 spp up to 4 (a square), as Mitsuba does; the row
    // says both and bench notes it.
    let json_path = temp_file("bench_stratified", "s.json", "");
    let (code, out, err) = wavetrace(&[
        "bench",
        "scenes/ao/ao.xml",
        "--ref",
        "scenes/refs/ao.exr",
        "--spp",
        "2",
        "--sampler",
        "stratified",
        "--json",
        json_path.to_str().expect("utf-8 temp path"),
        "-q",
    ]);
    assert_eq!(code, 0, "stdout:\n{out}\nstderr:\n{err}");
    assert!(err.contains("rounds 2 spp to 4"), "{err}");
    assert!(out.contains("sampler stratified"), "{out}");
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&json_path).unwrap()).unwrap();
    assert_eq!(v["sampler"], "stratified");
    assert_eq!(v["rows"][0]["spp"], 4);
    assert_eq!(v["rows"][0]["requested_spp"], 2);

    let (code, _, err) = wavetrace(&[
        "bench",
        "scenes/ao/ao.xml",
        "--ref",
        "scenes/refs/ao.exr",
        "--sampler",
        "sobolish",
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("unknown sampler 'sobolish'"), "{err}");
    assert!(err.contains("multijitter"), "{err}");
}

#[test]
fn reference_of_another_size_is_a_clear_error() {
    // cbox.xml renders 256x256; ao.exr is 128x128.
    let (code, _, err) = wavetrace(&[
        "bench",
        "scenes/cbox/cbox.xml",
        "--ref",
        "scenes/refs/ao.exr",
        "--spp",
        "1",
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(!err.contains("panicked"), "{err}");
    for needle in ["scenes/refs/ao.exr", "128x128", "256x256", "cbox.xml"] {
        assert!(err.contains(needle), "stderr lacks {needle:?}:\n{err}");
    }
}

#[test]
fn bad_spp_list_and_missing_reference_are_errors() {
    let (code, _, err) = wavetrace(&[
        "bench",
        "scenes/ao/ao.xml",
        "--ref",
        "scenes/refs/ao.exr",
        "--spp",
        "1,0",
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("--spp"), "{err}");

    let (code, _, err) = wavetrace(&["bench", "scenes/ao/ao.xml", "--ref", "/nonexistent/ref.exr"]);
    assert_eq!(code, 1, "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains("/nonexistent/ref.exr"), "{err}");
}

/// `bench --sensor I` measures sensor I of a scene with several (here a second camera
/// of another size, whose own render is the reference), and an index out of range is
/// an error naming the scene and how many sensors it has.
#[test]
fn bench_picks_a_sensor() {
    let text = std::fs::read_to_string(common::repo("scenes/ao/ao.xml")).expect("ao.xml");
    let second = r#"    <sensor type="perspective">
        <float name="fov" value="50"/>
        <transform name="to_world"><lookat origin="3, 3, 4" target="0, 0.5, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
        <film type="hdrfilm"><integer name="width" value="48"/><integer name="height" value="32"/><rfilter type="box"/></film>
    </sensor>
"#;
    let at = text.find("</sensor>").expect("a sensor") + "</sensor>\n".len();
    let scene = format!(
        "{}    <path value=\"{}\"/>\n{second}{}",
        &text[..at],
        common::repo("scenes/ao").display(),
        &text[at..]
    );
    let path = temp_file("bench_sensor", "two.xml", &scene);
    let reference = path.with_file_name("ref.exr");
    let (p, r) = (path.to_str().unwrap(), reference.to_str().unwrap());
    let (code, _, err) = wavetrace(&[
        "render", p, "--sensor", "1", "--spp", "64", "--seed", "9", "-q", "-o", r,
    ]);
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = wavetrace(&[
        "bench", p, "--ref", r, "--sensor", "1", "--spp", "1,4", "-q",
    ]);
    assert_eq!(code, 0, "stdout:\n{out}\nstderr:\n{err}");
    assert!(out.contains("relMSE"), "{out}");
    // Without --sensor: the first camera, 128x128, against the 48x32 reference.
    let (code, _, err) = wavetrace(&["bench", p, "--ref", r, "--spp", "1", "-q"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("48x32") && err.contains("128x128"), "{err}");
    let (code, _, err) = wavetrace(&["bench", p, "--ref", r, "--sensor", "2", "--spp", "1", "-q"]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("two.xml") && err.contains("the scene has 2 sensors (0 to 1)"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(path.parent().unwrap());
}
