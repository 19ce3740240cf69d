//! Curve files of `linearcurve` and `bsplinecurve` (`scene::shape::linearcurve::parse`,
//! `scene::shape::bsplinecurve::parse`, our own parser).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let path = wavetrace_fuzz::input_file("input.txt", data);
    if let Err(e) = wavetrace::scene::shape::linearcurve::parse(&path, data) {
        wavetrace_fuzz::names_file(&e.to_string(), &path);
    }
    if let Err(e) = wavetrace::scene::shape::bsplinecurve::parse(&path, data) {
        wavetrace_fuzz::names_file(&e.to_string(), &path);
    }
});
