//! Errors from setting up or running a render.

use std::path::PathBuf;

/// Why a render could not be set up or run.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error(transparent)]
    Gpu(#[from] crate::gpu::Error),
    /// The scene names an integrator, or parameters, the renderer cannot use.
    #[error("{}{}: {message}", file.display(), line.map(|l| format!(":{l}")).unwrap_or_default())]
    Integrator {
        file: PathBuf,
        line: Option<u32>,
        message: String,
    },
    /// Render options that cannot work (zero samples, an empty film, ...).
    #[error("{0}")]
    Options(String),
}

pub type Result<T> = std::result::Result<T, Error>;
