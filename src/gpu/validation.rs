//! The Khronos validation layer, on request: `WAVETRACE_VALIDATION=1` opens every
//! instance with `VK_LAYER_KHRONOS_validation` (Debian package
//! `vulkan-validationlayers`), its synchronization validation on
//! (`VkValidationFeaturesEXT`), and a `VK_EXT_debug_utils` messenger that prints
//! every warning and aborts the process at the first error, so that a test suite run
//! under it (`.ci/run`'s validation stage) cannot pass with one. This is how a
//! renderer tested only on lavapipe stays correct on every Vulkan device: the layer
//! checks the calls against the specification, not against one driver's leniency.

use std::ffi::{c_void, CStr};

use ash::vk;

use super::error::{Error, Result};

/// The environment variable that turns validation on (`1`).
pub const ENV: &str = "WAVETRACE_VALIDATION";

const LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Whether the user asked for validation.
pub fn requested() -> bool {
    std::env::var(ENV).is_ok_and(|v| v == "1")
}

/// What an instance needs for validation: the layer and the debug-utils extension.
/// Fails with a clear error when the layer is not installed.
pub fn instance_needs(entry: &ash::Entry) -> Result<(Vec<&'static CStr>, &'static CStr)> {
    // SAFETY: plain query of the loader.
    let layers =
        unsafe { entry.enumerate_instance_layer_properties() }.map_err(|result| Error::Vk {
            call: "vkEnumerateInstanceLayerProperties",
            result,
        })?;
    let present = layers
        .iter()
        .any(|l| l.layer_name_as_c_str().is_ok_and(|n| n == LAYER));
    if !present {
        return Err(Error::ValidationMissing);
    }
    Ok((vec![LAYER], ash::ext::debug_utils::NAME))
}

/// The synchronization-validation feature chained to the instance's create info.
pub fn features() -> [vk::ValidationFeatureEnableEXT; 1] {
    [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION]
}

/// A debug messenger of an instance, destroyed before it.
pub struct Messenger {
    loader: ash::ext::debug_utils::Instance,
    raw: vk::DebugUtilsMessengerEXT,
}

impl Messenger {
    /// Registers [`report`] for warnings and errors of every kind.
    pub fn new(entry: &ash::Entry, instance: &ash::Instance) -> Result<Messenger> {
        let loader = ash::ext::debug_utils::Instance::new(entry, instance);
        let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
            .message_severity(
                vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                    | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
            )
            .message_type(
                vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                    | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                    | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
            )
            .pfn_user_callback(Some(report));
        // SAFETY: valid create info; destroyed in `destroy` before the instance.
        let raw =
            unsafe { loader.create_debug_utils_messenger(&info, None) }.map_err(|result| {
                Error::Vk {
                    call: "vkCreateDebugUtilsMessengerEXT",
                    result,
                }
            })?;
        Ok(Messenger { loader, raw })
    }

    /// Destroys the messenger; call before destroying its instance.
    pub fn destroy(&self) {
        // SAFETY: the messenger was made from this loader's instance, which still lives.
        unsafe { self.loader.destroy_debug_utils_messenger(self.raw, None) };
    }
}

/// Prints a validation message; aborts on an error (an `extern "system"` function
/// cannot unwind, and a suite run under validation must not go on past one).
unsafe extern "system" fn report(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    _user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes valid callback data for the duration of the call.
    let message = unsafe { data.as_ref() }
        .and_then(|d| unsafe { d.message_as_c_str() })
        .map_or_else(|| "(no message)".into(), |m| m.to_string_lossy());
    if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
        eprintln!("wavetrace: Vulkan validation error: {message}\naborting ({ENV}=1)");
        std::process::abort();
    }
    eprintln!("wavetrace: Vulkan validation warning: {message}");
    vk::FALSE
}

/// Makes one call the specification forbids (a buffer of size 0,
/// VUID-VkBufferCreateInfo-size-00912), for the check that validation is really on:
/// under [`ENV`]=1 the process must abort here (`examples/validation_probe.rs`, run by
/// `.ci/run` before its validation stage). Without validation, returns the driver's
/// answer.
#[doc(hidden)]
pub fn provoke_error(device: &super::device::Device) -> Result<()> {
    let info = vk::BufferCreateInfo::default()
        .size(0)
        .usage(vk::BufferUsageFlags::STORAGE_BUFFER);
    // SAFETY: deliberately invalid (size 0) but harmless to a driver: the layer stops
    // the process first; without it the buffer, if made, is destroyed at once.
    let made = unsafe { device.raw().create_buffer(&info, None) };
    if let Ok(buffer) = made {
        // SAFETY: the buffer was just made and is unused.
        unsafe { device.raw().destroy_buffer(buffer, None) };
    }
    Ok(())
}
