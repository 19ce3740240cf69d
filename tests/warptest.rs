//! `wavetrace warptest`: a correct sampler passes and a deliberately wrong pdf fails,
//! the histogram image written in both cases; bad parameters are clear errors.

mod common;

use common::wavetrace;

/// Runs `wavetrace warptest ARGS -o <temp>.png`: (exit status, stdout, stderr, PNG).
fn warptest(name: &str, args: &[&str]) -> (i32, String, String, Option<image::RgbImage>) {
    let png = common::temp_file("warptest", &format!("{name}.png"), "");
    std::fs::remove_file(&png).expect("remove placeholder");
    let mut all = vec!["warptest"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", png.to_str().unwrap()]);
    let (code, out, err) = wavetrace(&all);
    let img = image::open(&png).ok().map(|i| i.to_rgb8());
    (code, out, err, img)
}

/// 200k samples: enough that the mismatched pdf's X² is in the tens of thousands,
/// and the correct samplers pass at 1% with probability 0.99 each (fixed seeds, so
/// the outcome is the same every run).
#[test]
fn correct_samplers_pass_and_a_wrong_pdf_fails_with_images() {
    for (name, args) in [
        ("cosine", vec!["cosine_hemisphere", "--samples", "200000"]),
        (
            "ggx",
            vec![
                "roughconductor",
                "--alpha-u",
                "0.1",
                "--alpha-v",
                "0.4",
                "--theta",
                "60",
                "--samples",
                "200000",
            ],
        ),
        (
            "principled",
            vec![
                "principled",
                "--alpha",
                "0.2",
                "--theta",
                "40",
                "--samples",
                "200000",
            ],
        ),
        (
            "principledthin",
            vec![
                "principledthin",
                "--alpha-u",
                "0.1",
                "--alpha-v",
                "0.3",
                "--theta",
                "70",
                "--samples",
                "200000",
            ],
        ),
        (
            "measured",
            vec![
                "measured",
                "--theta",
                "50",
                "--phi",
                "120",
                "--samples",
                "200000",
            ],
        ),
        (
            "blendbsdf",
            vec![
                "blendbsdf",
                "--alpha",
                "0.3",
                "--theta",
                "50",
                "--samples",
                "200000",
            ],
        ),
        ("hg", vec!["hg", "--g", "-0.6", "--samples", "200000"]),
        ("disk", vec!["square_to_disk", "--samples", "200000"]),
        // A directionalarea light's ray origins (the routine the photon and particle
        // tracers call) on each kind of shape it samples: a mesh through its triangle
        // table, a disk, a sphere.
        (
            "directionalarea",
            vec!["directionalarea", "--samples", "200000"],
        ),
        (
            "directionalarea_disk",
            vec!["directionalarea_disk", "--samples", "200000"],
        ),
        (
            "directionalarea_sphere",
            vec!["directionalarea_sphere", "--samples", "200000"],
        ),
    ] {
        let (code, out, err, img) = warptest(name, &args);
        assert_eq!(code, 0, "{name}: {out}{err}");
        assert!(
            out.contains("passes") && out.contains("X² ="),
            "{name}: {out}"
        );
        let img = img.unwrap_or_else(|| panic!("{name}: no image written"));
        assert!(
            img.width() > 2 * img.height() / 2,
            "{name}: three panels side by side"
        );
    }
    let (code, out, err, img) = warptest("wrong", &["mismatched_cosine", "--samples", "200000"]);
    assert_eq!(code, 1, "{out}{err}");
    assert!(
        out.contains("FAILS") && out.contains("p-value = 0"),
        "{out}"
    );
    assert!(img.is_some(), "the failing test writes its image too");
    // The same points against the density of a mesh's triangles chosen uniformly (not
    // by area): rejected (X² near 34,000 for 1,023 degrees of freedom).
    let (code, out, err, _) = warptest(
        "wrong_area",
        &["mismatched_directionalarea", "--samples", "200000"],
    );
    assert_eq!(code, 1, "{out}{err}");
    assert!(
        out.contains("FAILS") && out.contains("p-value = 0"),
        "{out}"
    );
}

#[test]
fn bad_parameters_are_errors() {
    for (args, needle) in [
        (vec!["teapot"], "unknown warptest target"),
        (
            vec!["diffuse", "--g", "0.5"],
            "--g does not apply to 'diffuse'",
        ),
        (vec!["hg", "--g", "1.5"], "(-1, 1)"),
        (vec!["roughdielectric", "--eta", "1"], "differ from 1"),
        (vec!["ggx", "--alpha", "nan"], "positive"),
    ] {
        let (code, _, err, img) = warptest("bad", &args);
        assert_eq!(code, 1, "{args:?}: {err}");
        assert!(
            err.contains(needle) && !err.contains("panicked"),
            "{args:?}: {err}"
        );
        assert!(img.is_none());
    }
}

/// `wavetrace warptest hair`: β_m and β_n from --alpha-u and --alpha-v, a viewer
/// below the surface (hair scatters both ways).
#[test]
fn hair_target_passes() {
    let (code, out, err, img) = warptest(
        "hair",
        &[
            "hair",
            "--alpha-u",
            "0.15",
            "--alpha-v",
            "0.25",
            "--eta",
            "1.4",
            "--theta",
            "110",
            "--samples",
            "200000",
        ],
    );
    assert_eq!(code, 0, "{out}{err}");
    assert!(
        out.contains("passes") && out.contains("longitudinal_roughness: 0.15"),
        "{out}"
    );
    assert!(img.is_some(), "hair: no image written");
}
