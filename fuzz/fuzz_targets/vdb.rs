//! OpenVDB `.vdb` grids (`scene::vdb::read_vdb`): the default grid (the first scalar
//! `density`, else the first scalar grid) and one chosen by name.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let path = wavetrace_fuzz::input_file("input.vdb", data);
    for name in [None, Some("temperature")] {
        if let Err(e) = wavetrace::scene::vdb::read_vdb(&path, name) {
            wavetrace_fuzz::names_file(&e, &path);
        }
    }
});
