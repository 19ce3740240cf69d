//! The commands of the `wavetrace` binary that need more than a few lines.

pub mod render;
