//! The command line on bad input: a clear error naming the file (and line where
//! known), exit status 1, never a panic.

mod common;

use common::{repo, temp_file, wavetrace};

fn assert_error(args: &[&str], needles: &[&str]) {
    let (code, _, err) = wavetrace(args);
    assert_eq!(code, 1, "exit status for {args:?}; stderr: {err}");
    assert!(!err.contains("panicked"), "panic for {args:?}: {err}");
    for n in needles {
        assert!(err.contains(n), "stderr for {args:?} lacks {n:?}:\n{err}");
    }
}

const CAMERA: &str = r#"<sensor type="perspective"><float name="fov" value="40"/>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>"#;

#[test]
fn missing_scene_file() {
    assert_error(
        &["render", "/nonexistent/scene.xml"],
        &["/nonexistent/scene.xml"],
    );
}

#[test]
fn malformed_xml_names_file_and_line() {
    let p = temp_file(
        "cli_malformed",
        "bad.xml",
        "<scene version=\"3.0.0\">\n  <shape type=\"obj\">\n</scene>\n",
    );
    assert_error(&["render", p.to_str().unwrap()], &["bad.xml:"]);
}

#[test]
fn unknown_plugin_type_names_line() {
    let xml = format!("<scene version=\"3.0.0\">\n{CAMERA}\n<shape type=\"teapot\"/>\n</scene>\n");
    let p = temp_file("cli_plugin", "plugin.xml", &xml);
    assert_error(
        &["render", p.to_str().unwrap()],
        &["plugin.xml:4", "teapot"],
    );
}

#[test]
fn missing_mesh_names_the_mesh_path() {
    let xml = format!(
        "<scene version=\"3.0.0\">\n{CAMERA}\n<shape type=\"obj\"><string name=\"filename\" value=\"nowhere.obj\"/></shape>\n</scene>\n"
    );
    let p = temp_file("cli_mesh", "mesh.xml", &xml);
    assert_error(
        &["render", p.to_str().unwrap()],
        &["mesh.xml:4", "nowhere.obj"],
    );
}

#[test]
fn nan_in_an_obj_names_the_obj_line() {
    let obj = temp_file(
        "cli_nan",
        "nan.obj",
        "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n",
    );
    let xml = format!(
        "<scene version=\"3.0.0\">\n{CAMERA}\n<shape type=\"obj\"><string name=\"filename\" value=\"{}\"/></shape>\n</scene>\n",
        obj.display()
    );
    let p = temp_file("cli_nan", "nan.xml", &xml);
    assert_error(&["render", p.to_str().unwrap()], &["nan.obj:3"]);
}

#[test]
fn impossible_parameters_are_refused() {
    let xml = format!("<scene version=\"3.0.0\">\n<integrator type=\"ao\"><float name=\"max_t\" value=\"-2\"/></integrator>\n{CAMERA}\n</scene>\n");
    let p = temp_file("cli_param", "param.xml", &xml);
    assert_error(
        &["render", p.to_str().unwrap(), "-o", "/tmp/never.exr"],
        &["param.xml:2", "max_t"],
    );
    assert_error(
        &["render", p.to_str().unwrap(), "--integrator", "nope"],
        &["'nope' is not implemented"],
    );
    let scene = repo("scenes/ao/ao.xml");
    assert_error(&["render", scene.to_str().unwrap(), "--spp", "0"], &["spp"]);
    assert_error(
        &["render", scene.to_str().unwrap(), "-D", "novalue"],
        &["NAME=VALUE"],
    );
}

#[test]
fn renders_writes_exr_and_png_and_reports_speed() {
    let dir = std::env::temp_dir().join(format!("wavetrace-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("ao.exr");
    let scene = repo("scenes/ao/ao.xml");
    let (code, _, err) = wavetrace(&[
        "render",
        scene.to_str().unwrap(),
        "--spp",
        "2",
        "-o",
        out.to_str().unwrap(),
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("device:"), "{err}");
    assert!(err.contains("rays/s"), "{err}");
    let img = wavetrace::image::Image::read_exr(&out).expect("read back the EXR");
    assert!(img.width > 0 && img.rgb.iter().all(|v| v.is_finite()));
    assert!(out.with_extension("png").exists());
}

#[test]
fn info_describes_the_scene() {
    let scene = repo("scenes/ao/ao.xml");
    let (code, out, err) = wavetrace(&["info", scene.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    for needle in [
        "triangles:",
        "bvh:",
        "integrator:",
        "camera:",
        "features:    triangles, vertex normals",
    ] {
        assert!(out.contains(needle), "info lacks {needle}:\n{out}");
    }
    assert!(out.contains("sampler:     independent (seed 0)"), "{out}");
    // The sample count a sampler renders, rounded as Mitsuba rounds it.
    let (code, out, err) = wavetrace(&[
        "info",
        scene.to_str().unwrap(),
        "--sampler",
        "orthogonal",
        "--spp",
        "64",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("sampler:     orthogonal (seed 0, jitter true, strength 2)"),
        "{out}"
    );
    assert!(
        out.contains("samples:     121 per pixel (64 asked for, rounded by the sampler)"),
        "{out}"
    );
}

#[test]
fn render_reports_the_rounded_sample_count() {
    let dir = std::env::temp_dir().join(format!("wavetrace-cli-round-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("ao.exr");
    let scene = repo("scenes/ao/ao.xml");
    let (code, _, err) = wavetrace(&[
        "render",
        scene.to_str().unwrap(),
        "--spp",
        "3",
        "--sampler",
        "stratified",
        "-o",
        out.to_str().unwrap(),
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains(
            "warning: stratified: Sample count should be square and power of two, rounding to 4"
        ),
        "{err}"
    );
    assert!(
        err.contains("at 4 spp with 'ao', sampler 'stratified'"),
        "{err}"
    );
    assert_error(
        &["render", scene.to_str().unwrap(), "--sampler", "halton"],
        &["unknown sampler 'halton'", "zsobol"],
    );
}

#[test]
fn a_scene_without_emitters_warns_of_a_black_image() {
    let xml = format!(
        r#"<scene version="3.0.0"><integrator type="path"/>{CAMERA}<shape type="sphere"/></scene>"#
    );
    let scene = temp_file("no_emitters", "scene.xml", &xml);
    let out = scene.with_extension("exr");
    let (code, _, err) = wavetrace(&[
        "render",
        scene.to_str().unwrap(),
        "--spp",
        "1",
        "-o",
        out.to_str().unwrap(),
        "-q",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("has no emitters"), "{err}");
}
