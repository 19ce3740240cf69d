//! Inputs the fuzzers of `fuzz/` (`tools/fuzz.sh`) found, or that stand for a class
//! of them, each kept in `fuzz/regressions/`: every one must give an error that names
//! the file and the problem, never a panic, a hang or a huge allocation. No GPU.

use std::path::PathBuf;

/// A file of `fuzz/regressions`.
fn input(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fuzz/regressions")
        .join(name)
}

/// Asserts that `message` names `file` and says `problem`.
fn names(message: &str, file: &str, problem: &str) {
    assert!(
        message.contains(file),
        "error does not name '{file}': {message}"
    );
    assert!(
        message.contains(problem),
        "error does not say '{problem}': {message}"
    );
}

/// An EXR header claiming 100000 x 100000 pixels in a 421-byte file: refused from
/// the header, before the exr crate or we allocate 120 GB of pixel storage.
#[test]
fn exr_with_a_huge_data_window_is_refused_before_allocating() {
    let path = input("exr_huge_data_window.exr");
    let e = wavetrace::scene::texture::load_image(&path, false).unwrap_err();
    names(
        &e,
        "exr_huge_data_window.exr",
        "100000 x 100000 pixels is more than wavetrace reads",
    );
    let e = wavetrace::image::exr::read_channels_with_text(&path).unwrap_err();
    names(
        &e.to_string(),
        "exr_huge_data_window.exr",
        "100000 x 100000 pixels is more than wavetrace reads",
    );
}

/// An EXR whose header allows 1.3 GB blocks and whose first block claims that many
/// bytes (found by the `exr` target: the exr crate reserved the claimed size before
/// reading). Refused from the header: no block of a real image comes near 256 MiB.
#[test]
fn exr_with_huge_blocks_is_refused_before_allocating() {
    let path = input("exr_huge_block.exr");
    let e = wavetrace::scene::texture::load_image(&path, false).unwrap_err();
    names(&e, "exr_huge_block.exr", "MiB wavetrace reads");
    let e = wavetrace::image::exr::read_channels_with_text(&path).unwrap_err();
    names(&e.to_string(), "exr_huge_block.exr", "MiB wavetrace reads");
}

/// A `.vol` header whose four sizes multiply past 2^64 (found by the `vol` target:
/// the product overflowed).
#[test]
fn vol_whose_size_overflows_is_refused() {
    let path = input("vol_size_overflow.vol");
    let e = wavetrace::scene::medium::read_vol(&path).err().unwrap();
    names(
        &e,
        "vol_size_overflow.vol",
        "values is more than wavetrace accepts",
    );
}

/// An ASCII PLY whose format line has a version number past 2^64 (found by the `ply`
/// target: ply-rs unwraps its parse of it).
#[test]
fn ply_with_a_huge_version_number_is_refused() {
    let path = input("ply_version_overflow.ply");
    let e = wavetrace::scene::ply::load(&path).unwrap_err();
    names(
        &e.to_string(),
        "ply_version_overflow.ply",
        "version number out of range",
    );
}
