//! Image I/O, tonemapping and error metrics.

pub mod exr;
pub mod metrics;
pub mod png;

pub use self::exr::{read_exr, write_exr};
pub use self::png::write_png;

use std::path::PathBuf;

/// A linear RGB float image, row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    /// Three floats per pixel.
    pub rgb: Vec<f32>,
}

impl Image {
    pub fn new(width: u32, height: u32) -> Image {
        Image {
            width,
            height,
            rgb: vec![0.0; width as usize * height as usize * 3],
        }
    }

    /// RGB of pixel (x, y).
    pub fn pixel(&self, x: u32, y: u32) -> [f32; 3] {
        let i = 3 * (y as usize * self.width as usize + x as usize);
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }
}

/// An image file that could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("{}: {message}", path.display())]
    File { path: PathBuf, message: String },
}

pub type Result<T> = std::result::Result<T, Error>;

pub(crate) fn file_error(path: &std::path::Path, message: impl std::fmt::Display) -> Error {
    Error::File {
        path: path.to_path_buf(),
        message: message.to_string(),
    }
}
