//! Errors from reading, writing and comparing images.

use std::path::PathBuf;

/// Something wrong with an image file, or two images that cannot be compared.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The EXR library could not read or write the file.
    #[error("{}: {source}", path.display())]
    Exr {
        path: PathBuf,
        source: ::exr::error::Error,
    },
    /// The PNG encoder could not write the file.
    #[error("{}: {source}", path.display())]
    Png {
        path: PathBuf,
        source: ::image::ImageError,
    },
    /// The Radiance HDR encoder could not write the file.
    #[error("{}: {source}", path.display())]
    Rgbe {
        path: PathBuf,
        source: ::image::ImageError,
    },
    /// Writing a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The file was read but is not an image we can use (too large, wrong channels).
    #[error("{}: {message}", path.display())]
    Format { path: PathBuf, message: String },
    /// Two images compared pixel by pixel have different sizes.
    #[error("cannot compare a {width}x{height} image with a {ref_width}x{ref_height} reference")]
    SizeMismatch {
        width: u32,
        height: u32,
        ref_width: u32,
        ref_height: u32,
    },
    /// tev (the HDR viewer) could not be reached or stopped listening.
    #[error("tev at {address}: {message}")]
    Tev { address: String, message: String },
    /// A comparison parameter makes no sense (for example a zero block size).
    #[error("{0}")]
    Parameter(String),
}
