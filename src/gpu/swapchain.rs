//! Showing pictures in a window: the swapchain of the surface a device was opened
//! for ([`Device::with_surface`]) and a picture of fixed size (the film's), scaled to
//! fit the window and letterboxed.
//!
//! A frame is one submission: the `letterbox` kernel (`shaders/kernels/letterbox.comp`)
//! draws the window's pixels from the picture's 8-bit pixels (a buffer a compute
//! kernel wrote), the picture in the largest rectangle of its aspect ratio centred in
//! the window and grey bars around it; they are copied into the window's image, which
//! is presented. The pixels never come back to the host. Nothing of the driver's
//! graphics pipeline is used (no blit, no clear): llvmpipe at 512 bits (Mesa 26)
//! crashes compiling the shader of its blit.

use ash::vk;

use super::buffer::{Buffer, Location};
use super::device::Device;
use super::error::{Error, Result, VkContext};
use super::kernel::DescriptorSet;
use super::letterbox::{self, Letterbox, WindowFormat};

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
    /// How `format` stores a pixel (one of [`WindowFormat::SUPPORTED`]).
    window_format: WindowFormat,
    present_mode: vk::PresentModeKHR,
    extent: vk::Extent2D,
    picture_size: (u32, u32),
    letterbox: Letterbox,
    /// The window's pixels (its extent, 4 bytes each, in its format's byte order), with
    /// the set that binds the picture's pixels of the last frame (that buffer's
    /// handle) and them; made again when either changes.
    window: Option<(Buffer, DescriptorSet, vk::Buffer)>,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    acquired: vk::Semaphore,
    /// One per swapchain image: its frame is drawn and copied into it.
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
        let letterbox = Letterbox::new(device)?;
        let mut chain = Swapchain {
            device: device.clone(),
            loader,
            raw: vk::SwapchainKHR::null(),
            images: Vec::new(),
            format: vk::Format::UNDEFINED,
            window_format: WindowFormat::SUPPORTED[0].1,
            present_mode: vk::PresentModeKHR::FIFO,
            extent: vk::Extent2D::default(),
            picture_size: picture,
            letterbox,
            window: None,
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
        let (chosen, window_format) = WindowFormat::SUPPORTED
            .iter()
            .find_map(|(p, layout)| {
                formats
                    .iter()
                    .find(|f| f.format == *p)
                    .map(|f| (*f, *layout))
            })
            .ok_or_else(|| {
                let offered: Vec<String> =
                    formats.iter().map(|f| format!("{:?}", f.format)).collect();
                Error::NoPresentation(format!(
                    "the window offers no 8-bit RGBA or BGRA pixel format (it offers: {})",
                    if offered.is_empty() {
                        "none".to_string()
                    } else {
                        offered.join(", ")
                    }
                ))
            })?;
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
        self.format = chosen.format;
        self.window_format = window_format;
        self.present_mode = present_mode;
        self.extent = extent;
        for _ in 0..self.images.len() {
            // SAFETY: valid create info; destroyed with the chain.
            let s = unsafe { raw_dev.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
                .vk("vkCreateSemaphore")?;
            self.drawn.push(s);
        }
        Ok(())
    }

    /// Shows `pixels` (the picture's size, 4 bytes a pixel: R, G, B, A, top row
    /// first) in the window, letterboxed.
    pub fn present(&mut self, pixels: &Buffer) -> Result<Presented> {
        if self.raw == vk::SwapchainKHR::null() {
            return Ok(Presented::Stale);
        }
        self.prepare_window(pixels)?;
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
        self.record(image)?;
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

    /// Makes the window's pixels and their set where the window's size or the
    /// picture's buffer changed since the last frame (nothing of either is in flight:
    /// every frame is waited for).
    fn prepare_window(&mut self, pixels: &Buffer) -> Result<()> {
        let bytes = u64::from(self.extent.width) * u64::from(self.extent.height) * 4;
        let current = self
            .window
            .as_ref()
            .is_some_and(|(w, _, p)| w.size() == bytes.max(16) && *p == pixels.raw);
        if !current {
            self.window = None;
            let window = Buffer::new(&self.device, "window pixels", bytes, Location::Gpu)?;
            let set = self.letterbox.bind(pixels, &window)?;
            self.window = Some((window, set, pixels.raw));
        }
        Ok(())
    }

    /// Records the frame: `letterbox` draws the window's pixels, which are copied into
    /// the window's `image`, ready to present.
    fn record(&self, image: vk::Image) -> Result<()> {
        let raw = self.device.raw();
        let cmd = self.cmd;
        let Some((window, set, _)) = &self.window else {
            return Err(Error::NoPresentation(
                "the window's pixels were not made".into(),
            ));
        };
        let push = letterbox::push(
            (self.extent.width, self.extent.height),
            self.picture_size,
            self.window_format,
        );
        let layers = vk::ImageSubresourceLayers::default()
            .aspect_mask(vk::ImageAspectFlags::COLOR)
            .layer_count(1);
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
            // The picture's pixels were written by a compute kernel in an earlier
            // submission; the window's were read by the last frame's copy.
            let written = [vk::MemoryBarrier::default()
                .src_access_mask(vk::AccessFlags::SHADER_WRITE | vk::AccessFlags::TRANSFER_WRITE)
                .dst_access_mask(vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE)];
            raw.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::COMPUTE_SHADER | vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::DependencyFlags::empty(),
                &written,
                &[],
                &[],
            );
            self.letterbox
                .kernel
                .record_bind(cmd, &[set], bytemuck::bytes_of(&push));
            let [gx, gy, gz] = letterbox::groups(&push);
            raw.cmd_dispatch(cmd, gx, gy, gz);
            // The window's pixels before the copy; the image's layout after the
            // acquisition (the submission waits for it at the transfer stage).
            let drawn = [vk::MemoryBarrier::default()
                .src_access_mask(vk::AccessFlags::SHADER_WRITE)
                .dst_access_mask(vk::AccessFlags::TRANSFER_READ)];
            let images = [transition(
                image,
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                vk::AccessFlags::empty(),
                vk::AccessFlags::TRANSFER_WRITE,
            )];
            raw.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::COMPUTE_SHADER | vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::TRANSFER,
                vk::DependencyFlags::empty(),
                &drawn,
                &[],
                &images,
            );
            let copy = [vk::BufferImageCopy::default()
                .image_subresource(layers)
                .image_extent(vk::Extent3D {
                    width: self.extent.width,
                    height: self.extent.height,
                    depth: 1,
                })];
            raw.cmd_copy_buffer_to_image(
                cmd,
                window.raw,
                image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &copy,
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
        self.window = None;
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
