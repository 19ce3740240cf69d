//! Image I/O, tonemapping and error metrics.

/// A linear RGB float image, row-major, top row first.
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<f32>,
}
