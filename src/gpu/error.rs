//! Errors from the Vulkan layer.

use ash::vk;

use super::buffer::ByteSize;

/// Something the GPU layer could not do.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error(
        "the Vulkan loader (libvulkan.so.1) could not be loaded: {0}\n\
         install it and a driver: sudo apt-get install libvulkan1 mesa-vulkan-drivers \
         (or run tools/setup.sh)"
    )]
    LoaderMissing(String),
    #[error(
        "no Vulkan device with a compute queue was found\n\
         install a driver, e.g. lavapipe for the CPU: sudo apt-get install mesa-vulkan-drivers \
         (or run tools/setup.sh)"
    )]
    NoDevice,
    #[error(
        "WAVETRACE_VALIDATION=1 asks for the Khronos validation layer, which is not installed\n\
         install it with: sudo apt-get install vulkan-validationlayers"
    )]
    ValidationMissing,
    #[error("cannot show a window with Vulkan: {0}")]
    NoPresentation(String),
    #[error("no Vulkan device matches --device {selector:?}; available:\n{available}")]
    DeviceNotFound { selector: String, available: String },
    #[error("Vulkan call {call} failed: {result}")]
    Vk {
        call: &'static str,
        result: vk::Result,
    },
    #[error("no memory type for buffer '{label}' (wanted {wanted:?})")]
    NoMemoryType {
        label: String,
        wanted: vk::MemoryPropertyFlags,
    },
    #[error(
        "buffer '{label}' needs {size} bytes, more than this device allows in one storage \
         buffer ({limit} bytes); render a smaller image or fewer samples per batch"
    )]
    BufferTooLarge {
        label: String,
        size: u64,
        limit: u64,
    },
    #[error(
        "buffer '{label}' needs {}, more than this device allows in one texel-buffer view \
         ({})", ByteSize(*size), ByteSize(*limit)
    )]
    TexelBufferTooLarge {
        label: String,
        size: u64,
        limit: u64,
    },
    #[error(
        "the device ran out of memory allocating buffer '{label}' ({}; its largest memory \
         heap holds {})", ByteSize(*size), ByteSize(*heap)
    )]
    OutOfMemory { label: String, size: u64, heap: u64 },
    #[error("environment variable {var}={value:?} is not one of: {expected}")]
    Environment {
        var: &'static str,
        value: String,
        expected: &'static str,
    },
    #[error("cannot write the kernel trace {path}: {why}")]
    KernelTrace { path: String, why: String },
    #[error("invalid SPIR-V for kernel '{0}'")]
    BadSpirv(String),
    #[error("descriptor set {set} has {expected} bindings but {got} buffers were given")]
    BindingCount {
        set: u32,
        expected: usize,
        got: usize,
    },
}

/// Result alias of the GPU layer.
pub type Result<T> = std::result::Result<T, Error>;

/// Attaches the name of the Vulkan call to a `vk::Result`.
pub(crate) trait VkContext<T> {
    fn vk(self, call: &'static str) -> Result<T>;
}

impl<T> VkContext<T> for std::result::Result<T, vk::Result> {
    fn vk(self, call: &'static str) -> Result<T> {
        self.map_err(|result| Error::Vk { call, result })
    }
}
