//! SPIR-V of every kernel in `shaders/`, compiled by build.rs with glslang.

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));
