//! The bytes of a mesh file, memory-mapped: the OBJ and PLY readers parse them in
//! place, in parallel, so a file in the page cache is never copied, and one on disk is
//! read as the parser's threads first touch its pages.
//!
//! `std::fs::read` of a 1.3 GB OBJ took about 0.4 s on one core before parsing could
//! start (a copy into 1.3 GB of freshly zeroed memory); the mapping costs a page fault
//! per 64 KiB, taken by whichever thread parses there. Files that cannot be mapped
//! (pipes, special files) are read into memory instead.

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
            // SAFETY: the map is read-only and private to this process. Its contents
            // change only if another process writes the file while we parse it, which
            // gives wrong values (caught as parse errors or not) but no undefined
            // behaviour in the parsers: they treat the bytes as untrusted input and
            // index them with bounds checks. Truncating the file meanwhile would raise
            // SIGBUS, as it does for every reader that maps its input.
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
