//! wavetrace: a physically based wavefront path tracer whose rendering runs in GLSL
//! compute kernels on Vulkan.
//!
//! Data flows one way: scene file -> [`scene::Scene`] (plain Rust) -> [`accel`] BVH ->
//! GPU buffers ([`gpu`]) -> wavefront kernels ([`render`]) -> film -> [`image`].
//! The progressive viewer (`viewer`, cargo feature `viewer`, on by default) drives
//! [`render`] in a GLFW window.

pub mod accel;
pub mod bench;
pub mod gpu;
pub mod image;
pub mod render;
pub mod scene;
#[cfg(feature = "viewer")]
pub mod viewer;
pub mod warptest;
