//! Mitsuba `.serialized` meshes (`scene::serialized::load`): the first mesh, and the
//! second through the file's table of offsets.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let path = wavetrace_fuzz::input_file("input.serialized", data);
    for shape_index in [0, 1] {
        if let Err(e) = wavetrace::scene::serialized::load(&path, shape_index) {
            wavetrace_fuzz::names_file(&e.to_string(), &path);
        }
    }
});
