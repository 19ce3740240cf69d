//! The driver and width recorded for a machine (`wavetrace driver --calibrate`,
//! src/gpu/driver_choice.rs) take over a command-line run, say so in the device line,
//! and render the image the system's driver renders; a record of another machine, or
//! `WAVETRACE_DRIVER=system`, leaves the system's driver in charge.
//!
//! The mechanism is checked with the system's driver at 128 bits (a width it is not
//! started at), so it runs on any machine. Where a newer lavapipe is installed
//! (`tools/lavapipe.sh --prebuilt`, which `.ci/run` runs where Debian sid can be
//! reached), a record of it at 512 bits renders the Cornell box as the system's driver
//! does; `WAVETRACE_REQUIRE_PREBUILT=1` (set by `.ci/run` once it installed one) makes
//! its absence a failure instead of a skip; there the scene is read from storage
//! buffers, and through texel buffers (`WAVETRACE_SCENE_TEXELS`) to the same bits.

mod common;

use std::path::Path;
use std::process::Command;

use wavetrace::gpu::driver_choice::machine;

/// Renders the Cornell box at 48², 4 spp with XDG_CACHE_HOME = `cache`:
/// (stderr, image).
fn render(cache: &Path, out: &Path, env: &[(&str, &str)]) -> (String, wavetrace::image::Image) {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_wavetrace"));
    cmd.current_dir(common::repo(""))
        .args(["render", "scenes/cbox/cbox_path.xml", "-D", "res=48"])
        .args(["--spp", "4", "--seed", "1", "-o"])
        .arg(out)
        .env("XDG_CACHE_HOME", cache)
        .env_remove("WAVETRACE_DRIVER")
        .env_remove("WAVETRACE_DRIVER_CHOSEN")
        .env_remove("LP_NATIVE_VECTOR_WIDTH")
        .env_remove("VK_ICD_FILENAMES")
        .env_remove("VK_DRIVER_FILES");
    for (k, v) in env {
        cmd.env(k, v);
    }
    let o = cmd.output().expect("run wavetrace");
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "render failed: {err}");
    let img = wavetrace::image::Image::read_exr(out).expect("read the render");
    (err, img)
}

fn device_line(stderr: &str) -> &str {
    stderr
        .lines()
        .find(|l| l.starts_with("device:"))
        .unwrap_or_else(|| panic!("no device line in {stderr}"))
}

#[test]
fn a_recorded_width_takes_over_and_renders_the_same_image() {
    let dir = common::temp_dir("driver_choice_width");
    let cache = dir.join("cache");
    let (plain, reference) = render(&cache, &dir.join("plain.exr"), &[]);
    assert!(!device_line(&plain).contains("128 bits"), "{plain}");
    assert!(!plain.contains("driver:"), "{plain}");

    common::write_driver_record(&cache, &machine(), None, 128);
    let (chosen, img) = render(&cache, &dir.join("chosen.exr"), &[]);
    assert!(device_line(&chosen).contains("128 bits"), "{chosen}");
    assert!(
        chosen.contains("driver: the system's driver at 128 bits, chosen for this machine"),
        "{chosen}"
    );
    let d = common::largest_relative_difference(&reference, &img);
    assert!(d < 1e-3, "the 128-bit render differs by {d}");

    // WAVETRACE_DRIVER=system, and a record of another machine, leave it alone.
    let (system, _) = render(
        &cache,
        &dir.join("system.exr"),
        &[("WAVETRACE_DRIVER", "system")],
    );
    assert!(!device_line(&system).contains("128 bits"), "{system}");
    common::write_driver_record(&cache, "another machine [avx2]", None, 128);
    let (other, _) = render(&cache, &dir.join("other.exr"), &[]);
    assert!(!device_line(&other).contains("128 bits"), "{other}");
    assert!(!other.contains("driver:"), "{other}");
}

#[test]
fn a_recorded_newer_lavapipe_at_512_bits_renders_the_same_image() {
    let Some(driver) = common::installed_prebuilt() else {
        return;
    };
    let dir = common::temp_dir("driver_choice_prebuilt");
    let cache = dir.join("cache");
    let (plain, reference) = render(&cache, &dir.join("plain.exr"), &[]);
    common::write_driver_record(&cache, &machine(), Some(&driver), 512);
    let (chosen, img) = render(&cache, &dir.join("chosen.exr"), &[]);
    let line = device_line(&chosen);
    assert!(line.contains("512 bits"), "{chosen}");
    assert_ne!(line, device_line(&plain), "the driver did not change");
    assert!(
        chosen.contains("at 512 bits, chosen for this machine"),
        "{chosen}"
    );
    let d = common::largest_relative_difference(&reference, &img);
    assert!(d < 1e-3, "the 512-bit render differs by {d}");

    // Mesa 22.3 reads the scene through texel buffers, the newer driver from storage
    // buffers (DeviceInfo::scene_storage); WAVETRACE_SCENE_TEXELS=1 makes it read them
    // through texel buffers too, with the same image bit for bit. From storage buffers
    // at 16 lanes the box's 32 triangles are tested in turn (plan::flat_prims_max),
    // through texel buffers its tree is walked: the same bits again.
    assert!(!plain.contains("(into storage buffers)"), "{plain}");
    assert!(chosen.contains("(into storage buffers)"), "{chosen}");
    assert!(
        chosen.contains("its 32 primitives tested in turn"),
        "{chosen}"
    );
    assert!(!plain.contains("tested in turn"), "{plain}");
    let (texels, texel_img) = render(
        &cache,
        &dir.join("texels.exr"),
        &[("WAVETRACE_SCENE_TEXELS", "1")],
    );
    assert!(device_line(&texels).contains("512 bits"), "{texels}");
    assert!(!texels.contains("(into storage buffers)"), "{texels}");
    assert!(!texels.contains("tested in turn"), "{texels}");
    assert_eq!(
        common::largest_relative_difference(&img, &texel_img),
        0.0,
        "texel and storage buffers render different images"
    );
}
