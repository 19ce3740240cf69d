//! Curve files of `linearcurve` (`scene::shape::linearcurve::parse`, our own parser).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let path = wavetrace_fuzz::input_file("input.txt", data);
    if let Err(e) = wavetrace::scene::shape::linearcurve::parse(&path, data) {
        wavetrace_fuzz::names_file(&e.to_string(), &path);
    }
});
