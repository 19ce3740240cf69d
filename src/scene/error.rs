//! Errors from reading a scene.

use std::path::PathBuf;

/// Something wrong with a scene file or a file it references.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A problem at a known place in a file.
    #[error("{}:{line}: {message}", file.display())]
    At {
        file: PathBuf,
        line: u32,
        message: String,
    },
    /// A problem with a whole file (missing, unreadable, malformed without a line).
    #[error("{}: {message}", file.display())]
    File { file: PathBuf, message: String },
}
