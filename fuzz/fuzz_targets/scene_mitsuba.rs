//! Scene files (both dialects; this target's corpus holds Mitsuba 3 scenes), with
//! includes, `<default>`s and leading `-D name=value` lines as definitions, loaded
//! and planned as `wavetrace render` does before it opens a device.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| wavetrace_fuzz::scene(data));
