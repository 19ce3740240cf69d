//! Mitsuba `.vol` grids (`scene::medium::read_vol`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let path = wavetrace_fuzz::input_file("input.vol", data);
    if let Err(e) = wavetrace::scene::medium::read_vol(&path) {
        wavetrace_fuzz::names_file(&e, &path);
    }
});
