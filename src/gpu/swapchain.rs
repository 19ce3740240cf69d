//! Showing pictures in a window: the swapchain of the surface a device was opened
//! for ([`Device::with_surface`]) and a picture of fixed size (the film's) that each
//! frame's pixels are copied into and blitted from, scaled to fit and letterboxed.
//!
//! A frame is one submission: copy the 8-bit pixels (a buffer a compute kernel wrote)
//! into the picture, clear the window's image, blit the picture into the largest
//! rectangle of the picture's aspect ratio centred in it, present. The pixels never
//! come back to the host.

use ash::vk;

use super::buffer::Buffer;
use super::device::Device;
use super::error::{Error, Result, VkContext};

/// Grey of the bars around a letterboxed picture (linear 8-bit value).
const BAR_GREY: f32 = 0.05;

/// Where the picture lies in a window: x, y, width, height in window pixels.
pub type Placement = (i32, i32, u32, u32);

/// The largest rectangle of the picture's aspect ratio that fits the window, centred
/// (the picture's own size where the window is exactly that).
pub fn letterbox(window: (u32, u32), picture: (u32, u32)) -> Placement {
    let (ww, wh) = (window.0.max(1) as f64, window.1.max(1) as f64);
    let (pw, ph) = (picture.0.max(1) as f64, picture.1.max(1) as f64);
    let scale = (ww / pw).min(wh / ph);
    let w = ((pw * scale).round() as u32).clamp(1, window.0.max(1));
    let h = ((ph * scale).round() as u32).clamp(1, window.1.max(1));
    (
        ((window.0.max(1) - w) / 2) as i32,
        ((window.1.max(1) - h) / 2) as i32,
        w,
        h,
    )
}

/// What presenting a frame found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Presented {
    /// The frame is on screen.
    Shown,
    /// The window changed size (or the surface otherwise no longer matches): call
    /// [`Swapchain::resize`] and present again.
    Stale,
}

/// A window's swapchain and the picture it shows.
pub struct Swapchain {
    device: Device,
    loader: ash::khr::swapchain::Device,
    raw: vk::SwapchainKHR,
    images: Vec<vk::Image>,
    format: vk::Format,
    present_mode: vk::PresentModeKHR,
    extent: vk::Extent2D,
    picture: vk::Image,
    picture_memory: vk::DeviceMemory,
    picture_size: (u32, u32),
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    acquired: vk::Semaphore,
    /// One per swapchain image: its frame's copy and blit are done.
    drawn: Vec<vk::Semaphore>,
}

impl Swapchain {
    /// The swapchain of `device`'s surface for a window of `window` pixels, showing
    /// a picture of `picture` pixels.
    pub fn new(device: &Device, window: (u32, u32), picture: (u32, u32)) -> Result<Swapchain> {
        if device.inner.surface.is_none() {
            return Err(Error::NoPresentation(
                "the device was opened without a window surface".into(),
            ));
        }
        let raw_dev = device.raw();
        let loader = ash::khr::swapchain::Device::new(&device.inner.instance, raw_dev);
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(device.inner.command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: valid pool of this device.
        let cmd =
            unsafe { raw_dev.allocate_command_buffers(&alloc) }.vk("vkAllocateCommandBuffers")?[0];
        let mut chain = Swapchain {
            device: device.clone(),
            loader,
            raw: vk::SwapchainKHR::null(),
            images: Vec::new(),
            format: vk::Format::UNDEFINED,
            present_mode: vk::PresentModeKHR::FIFO,
            extent: vk::Extent2D::default(),
            picture: vk::Image::null(),
            picture_memory: vk::DeviceMemory::null(),
            picture_size: picture,
            cmd,
            fence: vk::Fence::null(),
            acquired: vk::Semaphore::null(),
            drawn: Vec::new(),
        };
        // SAFETY: valid create infos; the objects are destroyed in Drop.
        unsafe {
            chain.fence = raw_dev
                .create_fence(&vk::FenceCreateInfo::default(), None)
                .vk("vkCreateFence")?;
            chain.acquired = raw_dev
                .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
                .vk("vkCreateSemaphore")?;
        }
        chain.resize(window)?;
        chain.create_picture()?;
        Ok(chain)
    }

    /// The window's pixel format and present mode, in words.
    pub fn describe(&self) -> String {
        format!(
            "{}x{} {:?}, {:?}",
            self.extent.width, self.extent.height, self.format, self.present_mode
        )
    }

    /// The size of the window's images.
    pub fn extent(&self) -> (u32, u32) {
        (self.extent.width, self.extent.height)
    }

    /// The format of the picture: 8-bit RGBA, sRGB-encoded values stored as they are
    /// (an `_SRGB` picture where the window's format is one, so the blit between them
    /// changes no value).
    fn picture_format(&self) -> vk::Format {
        match self.format {
            vk::Format::B8G8R8A8_SRGB
            | vk::Format::R8G8B8A8_SRGB
            | vk::Format::A8B8G8R8_SRGB_PACK32 => vk::Format::R8G8B8A8_SRGB,
            _ => vk::Format::R8G8B8A8_UNORM,
        }
    }

    fn create_picture(&mut self) -> Result<()> {
        let raw = self.device.raw();
        let (w, h) = self.picture_size;
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(self.picture_format())
            .extent(vk::Extent3D {
                width: w,
                height: h,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(vk::ImageUsageFlags::TRANSFER_SRC | vk::ImageUsageFlags::TRANSFER_DST)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid create info; destroyed in Drop.
        self.picture = unsafe { raw.create_image(&info, None) }.vk("vkCreateImage")?;
        // SAFETY: image of this device.
        let req = unsafe { raw.get_image_memory_requirements(self.picture) };
        let index = self
            .device
            .memory_type(req.memory_type_bits, vk::MemoryPropertyFlags::DEVICE_LOCAL)
            .or_else(|| {
                self.device
                    .memory_type(req.memory_type_bits, vk::MemoryPropertyFlags::empty())
            })
            .ok_or_else(|| Error::NoMemoryType {
                label: "window picture".into(),
                wanted: vk::MemoryPropertyFlags::DEVICE_LOCAL,
            })?;
        let alloc = vk::MemoryAllocateInfo::default()
            .allocation_size(req.size)
            .memory_type_index(index);
        // SAFETY: valid allocation; freed in Drop after the image.
        unsafe {
            self.picture_memory = raw.allocate_memory(&alloc, None).vk("vkAllocateMemory")?;
            raw.bind_image_memory(self.picture, self.picture_memory, 0)
                .vk("vkBindImageMemory")?;
        }
        Ok(())
    }

    /// Makes the swapchain again for a window of `window` pixels (after a resize, or
    /// when presenting found it [`Presented::Stale`]).
    pub fn resize(&mut self, window: (u32, u32)) -> Result<()> {
        let device = self.device.clone();
        let surface = device
            .inner
            .surface
            .as_ref()
            .ok_or_else(|| Error::NoPresentation("no window surface".into()))?;
        let raw_dev = device.raw();
        let phys = device.inner.physical;
        // SAFETY: surface and physical device belong to this device's instance.
        let (caps, formats, modes) = unsafe {
            (
                surface
                    .loader
                    .get_physical_device_surface_capabilities(phys, surface.raw)
                    .vk("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?,
                surface
                    .loader
                    .get_physical_device_surface_formats(phys, surface.raw)
                    .vk("vkGetPhysicalDeviceSurfaceFormatsKHR")?,
                surface
                    .loader
                    .get_physical_device_surface_present_modes(phys, surface.raw)
                    .vk("vkGetPhysicalDeviceSurfacePresentModesKHR")?,
            )
        };
        if !caps
            .supported_usage_flags
            .contains(vk::ImageUsageFlags::TRANSFER_DST)
        {
            return Err(Error::NoPresentation(
                "the window's images cannot be copied to (no TRANSFER_DST usage)".into(),
            ));
        }
        let preferred = [
            vk::Format::B8G8R8A8_UNORM,
            vk::Format::R8G8B8A8_UNORM,
            vk::Format::B8G8R8A8_SRGB,
            vk::Format::R8G8B8A8_SRGB,
        ];
        let chosen = preferred
            .iter()
            .find_map(|p| formats.iter().find(|f| f.format == *p))
            .or_else(|| formats.first())
            .copied()
            .ok_or_else(|| Error::NoPresentation("the window offers no pixel format".into()))?;
        // Mailbox never makes the renderer wait for the display; FIFO always exists.
        let present_mode = if modes.contains(&vk::PresentModeKHR::MAILBOX) {
            vk::PresentModeKHR::MAILBOX
        } else {
            vk::PresentModeKHR::FIFO
        };
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: window
                    .0
                    .max(caps.min_image_extent.width)
                    .min(caps.max_image_extent.width),
                height: window
                    .1
                    .max(caps.min_image_extent.height)
                    .min(caps.max_image_extent.height),
            }
        };
        // SAFETY: nothing of the old swapchain is in flight once the device is idle.
        unsafe { raw_dev.device_wait_idle() }.vk("vkDeviceWaitIdle")?;
        self.destroy_chain_semaphores();
        let old = self.raw;
        if extent.width == 0 || extent.height == 0 {
            // A minimized window: nothing to present to until it is restored.
            if old != vk::SwapchainKHR::null() {
                // SAFETY: idle, and no image of it is acquired.
                unsafe { self.loader.destroy_swapchain(old, None) };
            }
            self.raw = vk::SwapchainKHR::null();
            self.images.clear();
            self.extent = extent;
            return Ok(());
        }
        let mut count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            count = count.min(caps.max_image_count);
        }
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface.raw)
            .min_image_count(count)
            .image_format(chosen.format)
            .image_color_space(chosen.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(vk::ImageUsageFlags::TRANSFER_DST)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(vk::CompositeAlphaFlagsKHR::OPAQUE)
            .present_mode(present_mode)
            .clipped(true)
            .old_swapchain(old);
        // SAFETY: valid create info for this device's surface.
        let raw = unsafe { self.loader.create_swapchain(&info, None) };
        if old != vk::SwapchainKHR::null() {
            // SAFETY: retired by the new one (or failed); the device is idle.
            unsafe { self.loader.destroy_swapchain(old, None) };
        }
        self.raw = vk::SwapchainKHR::null();
        self.raw = raw.vk("vkCreateSwapchainKHR")?;
        // SAFETY: valid swapchain.
        self.images =
            unsafe { self.loader.get_swapchain_images(self.raw) }.vk("vkGetSwapchainImagesKHR")?;
        let picture_format_changes = self.format != vk::Format::UNDEFINED
            && self.format != chosen.format
            && self.picture != vk::Image::null();
        self.format = chosen.format;
        self.present_mode = present_mode;
        self.extent = extent;
        for _ in 0..self.images.len() {
            // SAFETY: valid create info; destroyed with the chain.
            let s = unsafe { raw_dev.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
                .vk("vkCreateSemaphore")?;
            self.drawn.push(s);
        }
        if picture_format_changes {
            self.destroy_picture();
            self.create_picture()?;
        }
        Ok(())
    }

    /// Shows `pixels` (the picture's size, 4 bytes a pixel: R, G, B, A, top row
    /// first) in the window, letterboxed.
    pub fn present(&mut self, pixels: &Buffer) -> Result<Presented> {
        if self.raw == vk::SwapchainKHR::null() {
            return Ok(Presented::Stale);
        }
        let raw_dev = self.device.raw();
        // SAFETY: valid swapchain and semaphore; the semaphore is unsignaled (the
        // last submission that waited on it finished).
        let index = match unsafe {
            self.loader
                .acquire_next_image(self.raw, u64::MAX, self.acquired, vk::Fence::null())
        } {
            Ok((index, _suboptimal)) => index,
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => return Ok(Presented::Stale),
            Err(result) => {
                return Err(Error::Vk {
                    call: "vkAcquireNextImageKHR",
                    result,
                })
            }
        };
        let image = self.images[index as usize];
        self.record(pixels, image)?;
        let waits = [self.acquired];
        let stages = [vk::PipelineStageFlags::TRANSFER];
        let cmds = [self.cmd];
        let signals = [self.drawn[index as usize]];
        let submit = [vk::SubmitInfo::default()
            .wait_semaphores(&waits)
            .wait_dst_stage_mask(&stages)
            .command_buffers(&cmds)
            .signal_semaphores(&signals)];
        let queue = self.device.inner.queue;
        // SAFETY: recorded command buffer; the fence is unsignaled.
        unsafe {
            raw_dev
                .queue_submit(queue, &submit, self.fence)
                .vk("vkQueueSubmit")?;
        }
        let swapchains = [self.raw];
        let indices = [index];
        let present = vk::PresentInfoKHR::default()
            .wait_semaphores(&signals)
            .swapchains(&swapchains)
            .image_indices(&indices);
        // SAFETY: the image was acquired and its drawing is submitted.
        let presented = unsafe { self.loader.queue_present(queue, &present) };
        // SAFETY: the fence belongs to the submission above.
        unsafe {
            raw_dev
                .wait_for_fences(&[self.fence], true, u64::MAX)
                .vk("vkWaitForFences")?;
            raw_dev.reset_fences(&[self.fence]).vk("vkResetFences")?;
        }
        match presented {
            Ok(false) => Ok(Presented::Shown),
            Ok(true) | Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(Presented::Stale),
            Err(result) => Err(Error::Vk {
                call: "vkQueuePresentKHR",
                result,
            }),
        }
    }

    /// Records the frame: pixels to picture, clear, blit into the letterbox, ready to
    /// present.
    fn record(&self, pixels: &Buffer, image: vk::Image) -> Result<()> {
        let raw = self.device.raw();
        let cmd = self.cmd;
        let color = color_range();
        let layers = vk::ImageSubresourceLayers::default()
            .aspect_mask(vk::ImageAspectFlags::COLOR)
            .layer_count(1);
        let (pw, ph) = self.picture_size;
        let (x, y, w, h) = letterbox((self.extent.width, self.extent.height), self.picture_size);
        // SAFETY: the command buffer is not in use (the last frame's fence was waited
        // on); every handle belongs to this device.
        unsafe {
            raw.reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())
                .vk("vkResetCommandBuffer")?;
            raw.begin_command_buffer(
                cmd,
                &vk::CommandBufferBeginInfo::default()
                    .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
            )
            .vk("vkBeginCommandBuffer")?;
            // The pixels were written by a compute kernel in an earlier submission.
            let written = [vk::MemoryBarrier::default()
                .src_access_mask(vk::AccessFlags::SHADER_WRITE | vk::AccessFlags::TRANSFER_WRITE)
                .dst_access_mask(vk::AccessFlags::TRANSFER_READ)];
            let images = [
                transition(
                    self.picture,
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    vk::AccessFlags::empty(),
                    vk::AccessFlags::TRANSFER_WRITE,
                ),
                transition(
                    image,
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    vk::AccessFlags::empty(),
                    vk::AccessFlags::TRANSFER_WRITE,
                ),
            ];
            raw.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::COMPUTE_SHADER | vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::TRANSFER,
                vk::DependencyFlags::empty(),
                &written,
                &[],
                &images,
            );
            let copy = [vk::BufferImageCopy::default()
                .image_subresource(layers)
                .image_extent(vk::Extent3D {
                    width: pw,
                    height: ph,
                    depth: 1,
                })];
            raw.cmd_copy_buffer_to_image(
                cmd,
                pixels.raw,
                self.picture,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &copy,
            );
            let grey = vk::ClearColorValue {
                float32: [BAR_GREY, BAR_GREY, BAR_GREY, 1.0],
            };
            raw.cmd_clear_color_image(
                cmd,
                image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &grey,
                &[color],
            );
            let ready = [
                transition(
                    self.picture,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    vk::AccessFlags::TRANSFER_WRITE,
                    vk::AccessFlags::TRANSFER_READ,
                ),
                transition(
                    image,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    vk::AccessFlags::TRANSFER_WRITE,
                    vk::AccessFlags::TRANSFER_WRITE,
                ),
            ];
            raw.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::TRANSFER,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &ready,
            );
            let corner = |x: i32, y: i32| vk::Offset3D { x, y, z: 1 };
            let blit = [vk::ImageBlit::default()
                .src_subresource(layers)
                .src_offsets([vk::Offset3D::default(), corner(pw as i32, ph as i32)])
                .dst_subresource(layers)
                .dst_offsets([
                    vk::Offset3D { x, y, z: 0 },
                    corner(x + w as i32, y + h as i32),
                ])];
            // One window pixel per picture pixel: copy exactly; else interpolate.
            let filter = if (w, h) == (pw, ph) {
                vk::Filter::NEAREST
            } else {
                vk::Filter::LINEAR
            };
            raw.cmd_blit_image(
                cmd,
                self.picture,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &blit,
                filter,
            );
            let present = [transition(
                image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                vk::ImageLayout::PRESENT_SRC_KHR,
                vk::AccessFlags::TRANSFER_WRITE,
                vk::AccessFlags::empty(),
            )];
            raw.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::BOTTOM_OF_PIPE,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &present,
            );
            raw.end_command_buffer(cmd).vk("vkEndCommandBuffer")?;
        }
        Ok(())
    }

    fn destroy_chain_semaphores(&mut self) {
        let raw = self.device.raw();
        for s in self.drawn.drain(..) {
            // SAFETY: the device is idle when this is called.
            unsafe { raw.destroy_semaphore(s, None) };
        }
    }

    fn destroy_picture(&mut self) {
        let raw = self.device.raw();
        // SAFETY: the device is idle when this is called; null handles are ignored.
        unsafe {
            raw.destroy_image(self.picture, None);
            raw.free_memory(self.picture_memory, None);
        }
        self.picture = vk::Image::null();
        self.picture_memory = vk::DeviceMemory::null();
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        let device = self.device.clone();
        let raw = device.raw();
        // SAFETY: wait for everything in flight, then destroy what this owns; the
        // surface outlives it (the device holds it).
        unsafe {
            let _ = raw.device_wait_idle();
        }
        self.destroy_chain_semaphores();
        self.destroy_picture();
        // SAFETY: as above.
        unsafe {
            if self.raw != vk::SwapchainKHR::null() {
                self.loader.destroy_swapchain(self.raw, None);
            }
            raw.destroy_semaphore(self.acquired, None);
            raw.destroy_fence(self.fence, None);
            raw.free_command_buffers(self.device.inner.command_pool, &[self.cmd]);
        }
    }
}

/// The colour of an image's one level and layer.
fn color_range() -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange::default()
        .aspect_mask(vk::ImageAspectFlags::COLOR)
        .level_count(1)
        .layer_count(1)
}

/// The barrier taking `image`'s colour from layout `from` to `to`, after accesses `src`
/// and before `dst`.
fn transition(
    image: vk::Image,
    from: vk::ImageLayout,
    to: vk::ImageLayout,
    src: vk::AccessFlags,
    dst: vk::AccessFlags,
) -> vk::ImageMemoryBarrier<'static> {
    vk::ImageMemoryBarrier::default()
        .image(image)
        .old_layout(from)
        .new_layout(to)
        .src_access_mask(src)
        .dst_access_mask(dst)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .subresource_range(color_range())
}

#[cfg(test)]
mod tests {
    use super::letterbox;

    #[test]
    fn letterbox_fits_and_centres_the_picture() {
        // Exactly the picture's size: one pixel for one.
        assert_eq!(letterbox((128, 96), (128, 96)), (0, 0, 128, 96));
        // A wider window: bars left and right, full height.
        assert_eq!(letterbox((400, 100), (100, 100)), (150, 0, 100, 100));
        // A taller window: bars above and below, full width.
        assert_eq!(letterbox((200, 400), (100, 50)), (0, 150, 200, 100));
        // Smaller than the picture: scaled down, aspect kept.
        assert_eq!(letterbox((64, 64), (256, 128)), (0, 16, 64, 32));
        // Degenerate sizes stay inside the window.
        assert_eq!(letterbox((0, 0), (10, 10)), (0, 0, 1, 1));
    }
}
