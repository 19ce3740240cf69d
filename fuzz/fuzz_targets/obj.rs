//! Wavefront OBJ meshes (`scene::obj::load`, our own parser).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let path = wavetrace_fuzz::input_file("input.obj", data);
    if let Err(e) = wavetrace::scene::obj::load(&path, true) {
        wavetrace_fuzz::names_file(&e.to_string(), &path);
    }
});
