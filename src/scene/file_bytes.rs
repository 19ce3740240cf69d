//! The bytes of a mesh file, memory-mapped: the OBJ and PLY readers parse them in
//! place, in parallel, so a file in the page cache is never copied, and one on disk is
//! read as the parser's threads first touch its pages.
//!
//! `std::fs::read` copies the whole file, on one core, into freshly zeroed memory
//! before parsing can start (for the 8 M-triangle height field's PLY, the copy alone
//! took 8% of the load and the page faults of the new memory as much again); a mapping
//! costs a page fault per 64 KiB, taken by whichever thread parses there. Files that
//! cannot be mapped (pipes, special files) are read into memory instead.

use std::fs::File;
use std::ops::Deref;
use std::path::Path;

use super::Error;

/// A file's contents: mapped, or read when mapping is not possible.
pub enum FileBytes {
    Mapped(memmap2::Mmap),
    Read(Vec<u8>),
}

impl FileBytes {
    /// Opens `path` and maps it (or reads it); errors name the file.
    pub fn open(path: &Path) -> Result<FileBytes, Error> {
        let cannot = |e: std::io::Error| Error::file(path, format!("cannot read: {e}"));
        let file = File::open(path).map_err(cannot)?;
        let meta = file.metadata().map_err(cannot)?;
        if meta.is_file() && meta.len() > 0 {
            // SAFETY: the map is read-only and private. Rust requires the bytes behind
            // a slice not to change while it is borrowed; they would only if another
            // process rewrote the file while we parse it (and truncating it would raise
            // SIGBUS), the contract of every reader that maps its input. The parsers
            // treat the bytes as untrusted and index them with bounds checks.
            if let Ok(map) = unsafe { memmap2::Mmap::map(&file) } {
                return Ok(FileBytes::Mapped(map));
            }
        }
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(&mut &file, &mut bytes).map_err(cannot)?;
        Ok(FileBytes::Read(bytes))
    }
}

impl Deref for FileBytes {
    type Target = [u8];

    fn deref(&self) -> &[u8] {
        match self {
            FileBytes::Mapped(m) => m,
            FileBytes::Read(v) => v,
        }
    }
}
