//! OpenEXR images: as a texture or environment map (`scene::texture::load_image`) and
//! as a partial render or reference (`image::exr::read_channels_with_text`, which
//! `render --resume`, `merge` and `bench --ref` use).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    wavetrace_fuzz::image("exr", data);
    let path = wavetrace_fuzz::input_file("input.exr", data);
    if let Err(e) = wavetrace::image::exr::read_channels_with_text(&path) {
        wavetrace_fuzz::names_file(&e.to_string(), &path);
    }
});
