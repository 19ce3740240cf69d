//! Errors from setting up or running a render.

use std::path::PathBuf;

use crate::gpu::ByteSize;

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
    /// A scene array larger than every binding the device lets it use.
    #[error(
        "scene buffer '{label}' needs {}, more than this device can address for it ({} in \
         {bindings} binding{}): {remedy}",
        ByteSize(*size),
        ByteSize(*limit),
        if *bindings == 1 { "" } else { "s" }
    )]
    SceneTooLarge {
        label: &'static str,
        size: u64,
        limit: u64,
        bindings: u32,
        remedy: &'static str,
    },
    /// The scene's buffers exceed the device's memory.
    #[error(
        "the scene needs {} of device memory, more than the device has ({}); the largest \
         buffer is {largest}: use fewer triangles, or smaller textures and grids",
        ByteSize(*needed),
        ByteSize(*available)
    )]
    SceneMemory {
        needed: u64,
        available: u64,
        largest: String,
    },
    /// A partial render that cannot be read, written or merged.
    #[error(transparent)]
    Partial(#[from] super::partial::Error),
    /// Render options that cannot work (zero samples, an empty film, ...).
    #[error("{0}")]
    Options(String),
}

pub type Result<T> = std::result::Result<T, Error>;
