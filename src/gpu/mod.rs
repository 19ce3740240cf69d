//! Vulkan through ash: the only module that imports it.
//!
//! `render/` speaks [`Device`], [`Buffer`], [`Kernel`], [`DescriptorSet`] and
//! [`CommandList`]; nothing outside this module sees a `vk::` type.

pub mod buffer;
pub mod command;
pub mod device;
pub mod driver_choice;
pub mod error;
pub mod kernel;
pub mod layout;
pub mod letterbox;
pub mod records;
pub mod shaders;
pub mod spec;
pub mod spec_ids;
pub mod specialize;
pub mod swapchain;
pub mod validation;

pub use buffer::{Buffer, ByteSize, Location};
pub use command::{CommandList, KernelTimes};
pub use device::{Device, DeviceInfo, DeviceKind, SurfaceRequest};
pub use error::{Error, Result};
pub use kernel::{BindingKind, BindingLayout, DescriptorSet, Kernel, KernelSpec, SceneAccess};
pub use spec::{Spec, SpecValues};
pub use swapchain::{Presented, Swapchain};
