//! Vulkan through ash: the only module that imports it.

pub mod layout;
