//! Storage buffers and their memory.

use std::sync::Arc;

use ash::vk;
use bytemuck::Pod;

use super::device::{Device, Inner};
use super::error::{Error, Result, VkContext};

/// Where a buffer's memory lives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Location {
    /// Device-local; the host reaches it through staging copies (or directly, where
    /// the device memory is also host-visible, as on lavapipe and integrated GPUs).
    Gpu,
    /// Host-visible and coherent, for uploads and read-backs.
    Host,
}

/// A storage buffer with its own memory allocation.
pub struct Buffer {
    device: Arc<Inner>,
    pub(crate) raw: vk::Buffer,
    memory: vk::DeviceMemory,
    size: u64,
    mapped: Option<*mut u8>,
    label: String,
}

// SAFETY: the mapped pointer is only dereferenced through &self/&mut self methods that
// copy plain bytes; Vulkan memory may be accessed from any thread.
unsafe impl Send for Buffer {}
// SAFETY: as above; shared access only reads.
unsafe impl Sync for Buffer {}

impl Buffer {
    /// Creates a buffer of `size` bytes (at least 16) usable as a storage, texel or uniform buffer, for
    /// indirect dispatch arguments, and as a copy source and destination. It must fit
    /// one storage-buffer binding (`maxStorageBufferRange`); see [`Buffer::texels`] for
    /// buffers read only through texel views.
    pub fn new(device: &Device, label: &str, size: u64, location: Location) -> Result<Buffer> {
        let size = size.max(16).next_multiple_of(4);
        let limit = device.info().max_storage_buffer_range;
        if size > limit {
            return Err(Error::BufferTooLarge {
                label: label.into(),
                size,
                limit,
            });
        }
        Buffer::allocate(device, label, size, location)
    }

    /// A device buffer holding `data` that kernels read only through texel views of
    /// `texel_bytes`-byte texels (scene arrays): it may exceed one storage-buffer
    /// binding, up to `maxTexelBufferElements` texels and the largest allocation.
    pub fn texels<T: Pod>(
        device: &Device,
        label: &str,
        data: &[T],
        texel_bytes: u64,
    ) -> Result<Buffer> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let size = (bytes.len() as u64).max(16).next_multiple_of(16);
        let info = device.info();
        let limit =
            (info.max_texel_buffer_elements * texel_bytes).min(info.max_memory_allocation_size);
        if size > limit {
            return Err(Error::TexelBufferTooLarge {
                label: label.into(),
                size,
                limit,
            });
        }
        let buffer = Buffer::allocate(device, label, size, Location::Gpu)?;
        buffer.write(device, 0, bytes)?;
        Ok(buffer)
    }

    /// Creates the buffer and its memory; `size` is checked against the caller's limit.
    fn allocate(device: &Device, label: &str, size: u64, location: Location) -> Result<Buffer> {
        let raw_dev = device.raw();
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(
                vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::STORAGE_TEXEL_BUFFER
                    | vk::BufferUsageFlags::UNIFORM_BUFFER
                    | vk::BufferUsageFlags::INDIRECT_BUFFER
                    | vk::BufferUsageFlags::TRANSFER_SRC
                    | vk::BufferUsageFlags::TRANSFER_DST,
            )
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid create info.
        let raw = unsafe { raw_dev.create_buffer(&info, None) }.vk("vkCreateBuffer")?;
        // SAFETY: raw is a buffer of this device.
        let req = unsafe { raw_dev.get_buffer_memory_requirements(raw) };
        let (first, fallback) = match location {
            Location::Gpu => (
                vk::MemoryPropertyFlags::DEVICE_LOCAL,
                vk::MemoryPropertyFlags::empty(),
            ),
            Location::Host => (
                vk::MemoryPropertyFlags::HOST_VISIBLE
                    | vk::MemoryPropertyFlags::HOST_COHERENT
                    | vk::MemoryPropertyFlags::HOST_CACHED,
                vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT,
            ),
        };
        let Some(type_index) = device
            .memory_type(req.memory_type_bits, first)
            .or_else(|| device.memory_type(req.memory_type_bits, fallback))
        else {
            // SAFETY: unused buffer of this device.
            unsafe { raw_dev.destroy_buffer(raw, None) };
            return Err(Error::NoMemoryType {
                label: label.into(),
                wanted: first,
            });
        };
        let alloc = vk::MemoryAllocateInfo::default()
            .allocation_size(req.size)
            .memory_type_index(type_index);
        // SAFETY: valid allocation info.
        let memory = match unsafe { raw_dev.allocate_memory(&alloc, None) } {
            Ok(m) => m,
            Err(result) => {
                // SAFETY: unused buffer of this device.
                unsafe { raw_dev.destroy_buffer(raw, None) };
                return Err(match result {
                    vk::Result::ERROR_OUT_OF_DEVICE_MEMORY
                    | vk::Result::ERROR_OUT_OF_HOST_MEMORY => Error::OutOfMemory {
                        label: label.into(),
                        size,
                        heap: device.info().device_memory,
                    },
                    result => Error::Vk {
                        call: "vkAllocateMemory",
                        result,
                    },
                });
            }
        };
        let buffer = Buffer {
            device: device.inner.clone(),
            raw,
            memory,
            size,
            mapped: None,
            label: label.into(),
        };
        // SAFETY: memory is fresh and matches the buffer's requirements.
        unsafe { raw_dev.bind_buffer_memory(raw, memory, 0) }.vk("vkBindBufferMemory")?;
        let coherent =
            vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
        let mut buffer = buffer;
        if device.memory_flags(type_index).contains(coherent) {
            // SAFETY: host-visible memory, mapped once for the buffer's lifetime.
            let ptr = unsafe {
                raw_dev.map_memory(memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty())
            }
            .vk("vkMapMemory")?;
            buffer.mapped = Some(ptr as *mut u8);
        }
        Ok(buffer)
    }

    /// A device buffer holding `data` (at least 16 bytes, zero-padded).
    pub fn from_slice<T: Pod>(device: &Device, label: &str, data: &[T]) -> Result<Buffer> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let buffer = Buffer::new(device, label, bytes.len() as u64, Location::Gpu)?;
        buffer.write(device, 0, bytes)?;
        Ok(buffer)
    }

    pub fn size(&self) -> u64 {
        self.size
    }

    pub fn label(&self) -> &str {
        &self.label
    }

    /// Writes bytes at `offset`, directly when mapped, else through a staging copy.
    /// Must not race with GPU work that uses the buffer.
    pub fn write(&self, device: &Device, offset: u64, bytes: &[u8]) -> Result<()> {
        assert!(
            offset + bytes.len() as u64 <= self.size,
            "write past the end of '{}'",
            self.label
        );
        if let Some(ptr) = self.mapped {
            // SAFETY: in bounds (asserted), memory is mapped and coherent.
            unsafe {
                std::ptr::copy_nonoverlapping(bytes.as_ptr(), ptr.add(offset as usize), bytes.len())
            };
            return Ok(());
        }
        let staging = Buffer::new(device, "staging upload", bytes.len() as u64, Location::Host)?;
        staging.write(device, 0, bytes)?;
        copy_now(device, &staging, 0, self, offset, bytes.len() as u64)
    }

    /// Reads the whole buffer as `T`s (its size rounded down to whole elements).
    pub fn read<T: Pod>(&self, device: &Device) -> Result<Vec<T>> {
        let n = self.size as usize / std::mem::size_of::<T>();
        let mut out = vec![T::zeroed(); n];
        let bytes: &mut [u8] = bytemuck::cast_slice_mut(&mut out);
        if let Some(ptr) = self.mapped {
            // SAFETY: in bounds, mapped and coherent; GPU work has completed.
            unsafe { std::ptr::copy_nonoverlapping(ptr, bytes.as_mut_ptr(), bytes.len()) };
            return Ok(out);
        }
        let staging = Buffer::new(
            device,
            "staging read-back",
            bytes.len() as u64,
            Location::Host,
        )?;
        copy_now(device, self, 0, &staging, 0, bytes.len() as u64)?;
        let ptr = staging.mapped.expect("host buffers are mapped");
        // SAFETY: as above, on the staging buffer.
        unsafe { std::ptr::copy_nonoverlapping(ptr, bytes.as_mut_ptr(), bytes.len()) };
        Ok(out)
    }
}

/// Copies between buffers and waits for the copy to finish.
fn copy_now(
    device: &Device,
    src: &Buffer,
    src_offset: u64,
    dst: &Buffer,
    dst_offset: u64,
    size: u64,
) -> Result<()> {
    let mut cmd = super::command::CommandList::new(device)?;
    cmd.copy(src, src_offset, dst, dst_offset, size);
    cmd.submit_and_wait()
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: callers wait for GPU work before dropping buffers it uses.
        unsafe {
            self.device.raw.destroy_buffer(self.raw, None);
            self.device.raw.free_memory(self.memory, None);
        }
    }
}

/// A byte count printed for people: `512 B`, `12.3 KiB`, `1.50 GiB`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ByteSize(pub u64);

impl std::fmt::Display for ByteSize {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        const UNITS: [&str; 4] = ["KiB", "MiB", "GiB", "TiB"];
        let b = self.0;
        if b < 1024 {
            return write!(f, "{b} B");
        }
        let mut v = b as f64 / 1024.0;
        let mut unit = 0;
        while v >= 1024.0 && unit + 1 < UNITS.len() {
            v /= 1024.0;
            unit += 1;
        }
        let digits = if v < 10.0 {
            2
        } else if v < 100.0 {
            1
        } else {
            0
        };
        write!(f, "{v:.digits$} {}", UNITS[unit])
    }
}

#[cfg(test)]
mod tests {
    use super::ByteSize;

    #[test]
    fn byte_sizes_read_well() {
        let s = |b| ByteSize(b).to_string();
        assert_eq!(s(0), "0 B");
        assert_eq!(s(1023), "1023 B");
        assert_eq!(s(1536), "1.50 KiB");
        assert_eq!(s(128 << 20), "128 MiB");
        assert_eq!(s(2 << 30), "2.00 GiB");
        assert_eq!(s(45 << 30), "45.0 GiB");
    }
}
