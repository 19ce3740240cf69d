//! Stanford PLY meshes, ASCII (through ply-rs) and binary of either byte order (our
//! own reader): `scene::ply::load`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let path = wavetrace_fuzz::input_file("input.ply", data);
    if let Err(e) = wavetrace::scene::ply::load(&path) {
        wavetrace_fuzz::names_file(&e.to_string(), &path);
    }
});
