//! Command recording and submission, with optional per-kernel GPU timestamps.

use std::collections::BTreeMap;

use ash::vk;

use super::buffer::Buffer;
use super::device::Device;
use super::error::{Error, Result, VkContext};
use super::kernel::{DescriptorSet, Kernel};

/// Most timestamps one command list records.
const MAX_TIMESTAMPS: u32 = 4096;

/// GPU time per kernel name, summed over dispatches.
#[derive(Debug, Clone, Default)]
pub struct KernelTimes {
    /// Seconds and dispatch count by kernel name.
    pub by_kernel: BTreeMap<String, (f64, u32)>,
}

impl KernelTimes {
    pub fn add(&mut self, other: &KernelTimes) {
        for (k, (s, n)) in &other.by_kernel {
            let e = self.by_kernel.entry(k.clone()).or_default();
            e.0 += s;
            e.1 += n;
        }
    }

    pub fn total_seconds(&self) -> f64 {
        self.by_kernel.values().map(|v| v.0).sum()
    }
}

/// A primary command buffer recorded on the host and run on the device's queue.
pub struct CommandList {
    device: Device,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    queries: Option<vk::QueryPool>,
    labels: Vec<String>,
    recording: bool,
    /// Where each submission's kernel intervals go with timestamps on (`KERNEL_TRACE_VAR`).
    trace: Option<std::path::PathBuf>,
}

/// With timestamps on (`--profile`), the file to which every submission appends a line
/// per kernel dispatch, `label start_ns end_ns`, in the device's timestamp clock: on
/// lavapipe CLOCK_MONOTONIC, which `perf record -k CLOCK_MONOTONIC` shares, so that
/// tools/kernel_perf.py can attribute a profile's samples to the kernels.
pub const KERNEL_TRACE_VAR: &str = "WAVETRACE_KERNEL_TRACE";

impl CommandList {
    /// A command list in the recording state.
    pub fn new(device: &Device) -> Result<CommandList> {
        Self::create(device, false)
    }

    /// A command list that records a GPU timestamp after every dispatch, where the
    /// device supports timestamps.
    pub fn with_timestamps(device: &Device) -> Result<CommandList> {
        Self::create(device, device.info().timestamp_period_ns.is_some())
    }

    fn create(device: &Device, timestamps: bool) -> Result<CommandList> {
        let raw = device.raw();
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(device.inner.command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: valid pool of this device.
        let cmd =
            unsafe { raw.allocate_command_buffers(&alloc) }.vk("vkAllocateCommandBuffers")?[0];
        // SAFETY: valid create info.
        let fence = unsafe { raw.create_fence(&vk::FenceCreateInfo::default(), None) };
        let mut list = CommandList {
            device: device.clone(),
            cmd,
            fence: vk::Fence::null(),
            queries: None,
            labels: Vec::new(),
            recording: false,
            trace: None,
        };
        list.fence = fence.vk("vkCreateFence")?;
        if timestamps {
            let info = vk::QueryPoolCreateInfo::default()
                .query_type(vk::QueryType::TIMESTAMP)
                .query_count(MAX_TIMESTAMPS);
            // SAFETY: valid create info.
            list.queries =
                Some(unsafe { raw.create_query_pool(&info, None) }.vk("vkCreateQueryPool")?);
            list.trace = std::env::var_os(KERNEL_TRACE_VAR).map(std::path::PathBuf::from);
        }
        list.begin()?;
        Ok(list)
    }

    fn begin(&mut self) -> Result<()> {
        let raw = self.device.raw();
        let info = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the command buffer is not in use (waited on, or fresh).
        unsafe { raw.begin_command_buffer(self.cmd, &info) }.vk("vkBeginCommandBuffer")?;
        self.recording = true;
        self.labels.clear();
        if let Some(q) = self.queries {
            // SAFETY: recording; query range within the pool.
            unsafe {
                raw.cmd_reset_query_pool(self.cmd, q, 0, MAX_TIMESTAMPS);
                raw.cmd_write_timestamp(self.cmd, vk::PipelineStageFlags::TOP_OF_PIPE, q, 0);
            }
        }
        Ok(())
    }

    fn bind(&mut self, kernel: &Kernel, sets: &[&DescriptorSet], push: &[u8]) {
        // SAFETY: recording; kernel and sets belong to this device.
        unsafe { kernel.record_bind(self.cmd, sets, push) };
    }

    fn stamp(&mut self, label: &str) {
        if let Some(q) = self.queries {
            let index = self.labels.len() as u32 + 1;
            if index < MAX_TIMESTAMPS {
                // SAFETY: recording; index within the pool.
                unsafe {
                    self.device.raw().cmd_write_timestamp(
                        self.cmd,
                        vk::PipelineStageFlags::BOTTOM_OF_PIPE,
                        q,
                        index,
                    )
                };
                self.labels.push(label.to_string());
            }
        }
    }

    /// Dispatches `groups` workgroups of `kernel`.
    pub fn dispatch(
        &mut self,
        kernel: &Kernel,
        sets: &[&DescriptorSet],
        push: &[u8],
        groups: [u32; 3],
    ) {
        self.bind(kernel, sets, push);
        // SAFETY: recording, pipeline bound.
        unsafe {
            self.device
                .raw()
                .cmd_dispatch(self.cmd, groups[0], groups[1], groups[2])
        };
        self.stamp(kernel.name());
    }

    /// Dispatches `kernel` with the workgroup counts stored in `args` at `offset`
    /// (a `VkDispatchIndirectCommand`: three u32).
    pub fn dispatch_indirect(
        &mut self,
        kernel: &Kernel,
        sets: &[&DescriptorSet],
        push: &[u8],
        args: &Buffer,
        offset: u64,
    ) {
        self.bind(kernel, sets, push);
        // SAFETY: recording, pipeline bound, args is an indirect buffer.
        unsafe {
            self.device
                .raw()
                .cmd_dispatch_indirect(self.cmd, args.raw, offset)
        };
        self.stamp(kernel.name());
    }

    /// Makes every earlier write visible to every later read, including indirect
    /// argument fetches and transfers.
    pub fn barrier(&mut self) {
        let access = vk::AccessFlags::SHADER_READ
            | vk::AccessFlags::SHADER_WRITE
            | vk::AccessFlags::UNIFORM_READ
            | vk::AccessFlags::INDIRECT_COMMAND_READ
            | vk::AccessFlags::TRANSFER_READ
            | vk::AccessFlags::TRANSFER_WRITE;
        let barrier = [vk::MemoryBarrier::default()
            .src_access_mask(access)
            .dst_access_mask(access)];
        let stages = vk::PipelineStageFlags::COMPUTE_SHADER
            | vk::PipelineStageFlags::DRAW_INDIRECT
            | vk::PipelineStageFlags::TRANSFER;
        // SAFETY: recording.
        unsafe {
            self.device.raw().cmd_pipeline_barrier(
                self.cmd,
                stages,
                stages,
                vk::DependencyFlags::empty(),
                &barrier,
                &[],
                &[],
            )
        };
    }

    /// Fills `size` bytes at `offset` (multiples of 4) with a repeated u32.
    pub fn fill(&mut self, buffer: &Buffer, offset: u64, size: u64, value: u32) {
        // SAFETY: recording; range within the buffer (checked by validation).
        unsafe {
            self.device
                .raw()
                .cmd_fill_buffer(self.cmd, buffer.raw, offset, size, value)
        };
    }

    /// Writes at most 64 KiB of bytes (a multiple of 4) into `buffer` at `offset`.
    pub fn update(&mut self, buffer: &Buffer, offset: u64, bytes: &[u8]) {
        // SAFETY: recording; vkCmdUpdateBuffer takes at most 65536 bytes.
        unsafe {
            self.device
                .raw()
                .cmd_update_buffer(self.cmd, buffer.raw, offset, bytes)
        };
    }

    pub fn copy(
        &mut self,
        src: &Buffer,
        src_offset: u64,
        dst: &Buffer,
        dst_offset: u64,
        size: u64,
    ) {
        let region = [vk::BufferCopy::default()
            .src_offset(src_offset)
            .dst_offset(dst_offset)
            .size(size)];
        // SAFETY: recording; regions within both buffers.
        unsafe {
            self.device
                .raw()
                .cmd_copy_buffer(self.cmd, src.raw, dst.raw, &region)
        };
    }

    /// Submits what was recorded, waits for it, and starts recording again.
    /// Returns GPU time per kernel where timestamps were recorded.
    pub fn submit_and_wait(&mut self) -> Result<()> {
        self.submit_and_wait_timed().map(|_| ())
    }

    /// As [`Self::submit_and_wait`], returning GPU time per kernel.
    pub fn submit_and_wait_timed(&mut self) -> Result<KernelTimes> {
        let raw = self.device.raw();
        // SAFETY: recording.
        unsafe { raw.end_command_buffer(self.cmd) }.vk("vkEndCommandBuffer")?;
        self.recording = false;
        let cmds = [self.cmd];
        let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
        // SAFETY: command buffer ended; fence unsignaled.
        unsafe {
            raw.queue_submit(self.device.inner.queue, &submit, self.fence)
                .vk("vkQueueSubmit")?;
            raw.wait_for_fences(&[self.fence], true, u64::MAX)
                .vk("vkWaitForFences")?;
            raw.reset_fences(&[self.fence]).vk("vkResetFences")?;
        }
        let times = self.read_times()?;
        // SAFETY: the fence says the buffer is done.
        unsafe { raw.reset_command_buffer(self.cmd, vk::CommandBufferResetFlags::empty()) }
            .vk("vkResetCommandBuffer")?;
        self.begin()?;
        Ok(times)
    }

    fn read_times(&self) -> Result<KernelTimes> {
        let mut times = KernelTimes::default();
        let (Some(q), Some(period)) = (self.queries, self.device.info().timestamp_period_ns) else {
            return Ok(times);
        };
        if self.labels.is_empty() {
            return Ok(times);
        }
        let mut ticks = vec![0u64; self.labels.len() + 1];
        // SAFETY: the submission finished, so every written query is available.
        unsafe {
            self.device.raw().get_query_pool_results(
                q,
                0,
                &mut ticks,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .vk("vkGetQueryPoolResults")?;
        let mut trace = String::new();
        for (i, label) in self.labels.iter().enumerate() {
            if self.trace.is_some() {
                let ns = |t: u64| (t as f64 * period) as u64;
                trace += &format!("{label} {} {}\n", ns(ticks[i]), ns(ticks[i + 1]));
            }
            let dt = ticks[i + 1].saturating_sub(ticks[i]) as f64 * period * 1e-9;
            let e = times.by_kernel.entry(label.clone()).or_default();
            e.0 += dt;
            e.1 += 1;
        }
        if let Some(path) = &self.trace {
            use std::io::Write;
            std::fs::OpenOptions::new()
                .create(true)
                .append(true)
                .open(path)
                .and_then(|mut f| f.write_all(trace.as_bytes()))
                .map_err(|e| Error::KernelTrace {
                    path: path.display().to_string(),
                    why: e.to_string(),
                })?;
        }
        Ok(times)
    }
}

impl Drop for CommandList {
    fn drop(&mut self) {
        let raw = self.device.raw();
        // SAFETY: nothing in flight (every submit waits); objects belong to this device.
        unsafe {
            if self.recording {
                let _ = raw.end_command_buffer(self.cmd);
            }
            raw.free_command_buffers(self.device.inner.command_pool, &[self.cmd]);
            raw.destroy_fence(self.fence, None);
            if let Some(q) = self.queries {
                raw.destroy_query_pool(q, None);
            }
        }
    }
}
