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

impl Error {
    /// A problem at `line` of `file`.
    pub(crate) fn at(file: impl Into<PathBuf>, line: u32, message: impl Into<String>) -> Self {
        Error::At {
            file: file.into(),
            line,
            message: message.into(),
        }
    }

    /// A problem with `file` as a whole.
    pub(crate) fn file(file: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Error::File {
            file: file.into(),
            message: message.into(),
        }
    }
}
