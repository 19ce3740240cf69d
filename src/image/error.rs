//! Errors from reading, writing and comparing images.
//!
//! A message says its cause itself, after the path (`x.exr: No such file or directory
//! (os error 2)`), and so no variant also hands that cause on as its `source()`: a
//! printer that walks the chain (anyhow's `{:#}` in `main`) would say it again, and the
//! EXR crate's error a third time (its I/O variant both shows the I/O error and returns
//! it as its source). The field is called `cause` because thiserror makes a field named
//! `source` the source.

use std::path::PathBuf;

/// Something wrong with an image file, or two images that cannot be compared.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The EXR library could not read or write the file.
    #[error("{}: {cause}", path.display())]
    Exr {
        path: PathBuf,
        cause: ::exr::error::Error,
    },
    /// The PNG encoder could not write the file.
    #[error("{}: {cause}", path.display())]
    Png {
        path: PathBuf,
        cause: ::image::ImageError,
    },
    /// The Radiance HDR encoder could not write the file.
    #[error("{}: {cause}", path.display())]
    Rgbe {
        path: PathBuf,
        cause: ::image::ImageError,
    },
    /// Writing a file failed.
    #[error("{}: {cause}", path.display())]
    Io {
        path: PathBuf,
        cause: std::io::Error,
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
