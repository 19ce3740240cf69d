//! JPEG images as a texture or environment map reads them
//! (`scene::texture::load_image`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| wavetrace_fuzz::image("jpg", data));
