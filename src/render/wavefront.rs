//! The wavefront's GPU state: path states, ray, hit and shadow queues, counters and
//! dispatch arguments — descriptor set 1 (`shaders/queue/wavefront.glsl`). The film
//! is set 3 ([`super::film`]), the photon mappers' set 2.

use std::mem::size_of;

use crate::gpu::layout::{Counters, DispatchArgs, Frame, HitItem, PathState, RayItem, ShadowItem};
use crate::gpu::{
    BindingKind, BindingLayout, Buffer, CommandList, DescriptorSet, Device, Location,
};

use super::error::Result;
use super::groups_for;

/// Bindings of set 1, in order.
pub const WAVEFRONT_BINDINGS: u32 = 14;

/// Words of the queue lengths that follow the frame in its uniform buffer
/// (shaders/queue/wavefront.glsl: `queue_lengths`, three `uvec4`s): the kernels
/// consuming a queue read its length there, once per SIMD group on llvmpipe, where a
/// read of the counters' storage buffer is a loop over the lanes.
pub const QUEUE_LENGTH_WORDS: usize = 12;

/// The kind of each binding of set 1: the frame is a uniform buffer; path states,
/// rays, hits and shadow rays are written as storage buffers (bindings 1-4) and read
/// through texel views of the same buffers (bindings 7-10), see
/// [`BindingKind::Texels`]; likewise the partition of a bounce's rays (written at 11,
/// read as words at 12); the frame's buffer is bound again at 13 as storage, where
/// `queue_args` and `shade_args` write the queue lengths after the frame.
pub fn wavefront_binding_kinds() -> Vec<BindingKind> {
    (0..WAVEFRONT_BINDINGS)
        .map(|b| match b {
            0 => BindingKind::Uniform,
            7..=10 => BindingKind::Texels,
            12 => BindingKind::Words,
            _ => BindingKind::Storage,
        })
        .collect()
}

/// GPU memory one path slot needs, in bytes (path state, two ray queue entries, a
/// hit, a shadow ray, three words of the partition: a queue index in each of its two
/// parts, or in scenes with null surfaces the lists of deferred rays and shadow rays
/// and a deferred shadow ray's draws, deferral.glsl); in scenes whose
/// rays cross null surfaces a second hit adds [`SECOND_HIT_BYTES`] (8% more; the
/// batch size stays that of the other scenes).
pub const BYTES_PER_PATH: u64 = (size_of::<PathState>()
    + 2 * size_of::<RayItem>()
    + size_of::<HitItem>()
    + size_of::<ShadowItem>()
    + 3 * size_of::<u32>()) as u64;

/// The second-nearest hit a path slot keeps in scenes whose rays cross null surfaces.
pub const SECOND_HIT_BYTES: u64 = size_of::<HitItem>() as u64;

/// The sizes of the wavefront's queues for a batch, in bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct QueueBytes {
    pub paths: u64,
    /// Two ray queues (a bounce reads one and fills the other).
    pub rays: u64,
    /// With `second_hits`, each ray's second-nearest hit after the nearest hits.
    pub hits: u64,
    pub shadows: u64,
    /// Three words per path of the partition (or of the deferral lists).
    pub shade_rays: u64,
}

impl QueueBytes {
    /// The queues of a batch of `capacity` paths; `second_hits`: in scenes whose rays
    /// cross null surfaces.
    pub fn new(capacity: u32, second_hits: bool) -> QueueBytes {
        let n = capacity as u64;
        QueueBytes {
            paths: n * size_of::<PathState>() as u64,
            rays: 2 * n * size_of::<RayItem>() as u64,
            hits: n * size_of::<HitItem>() as u64 + second_hits as u64 * n * SECOND_HIT_BYTES,
            shadows: n * size_of::<ShadowItem>() as u64,
            shade_rays: 3 * n * size_of::<u32>() as u64,
        }
    }

    /// Every queue's bytes together.
    pub fn total(&self) -> u64 {
        self.paths + self.rays + self.hits + self.shadows + self.shade_rays
    }
}

pub struct Wavefront {
    pub frame: Buffer,
    pub paths: Buffer,
    pub rays: Buffer,
    pub hits: Buffer,
    pub shadows: Buffer,
    /// Queue indices of a bounce's hits (the first `capacity` words) and misses (the
    /// next) where `intersect` partitions them for `shade`.
    pub shade_rays: Buffer,
    pub counters: Buffer,
    pub dispatch_args: Buffer,
    pub set: DescriptorSet,
    /// Path slots.
    pub capacity: u32,
}

impl Wavefront {
    pub fn new(
        device: &Device,
        layout: &BindingLayout,
        capacity: u32,
        frame: &Frame,
        second_hits: bool,
    ) -> Result<Wavefront> {
        let bytes = QueueBytes::new(capacity, second_hits);
        // The frame, then the queue lengths the kernels read with it.
        let mut frame_bytes = bytemuck::bytes_of(frame).to_vec();
        frame_bytes.extend_from_slice(bytemuck::bytes_of(&[0u32; QUEUE_LENGTH_WORDS]));
        let frame_buf = Buffer::from_slice(device, "frame", &frame_bytes)?;
        let gpu = |label: &str, size: u64| Buffer::new(device, label, size, Location::Gpu);
        let paths = gpu("path states", bytes.paths)?;
        let rays = gpu("ray queues", bytes.rays)?;
        let hits = gpu("hits", bytes.hits)?;
        let shadows = gpu("shadow queue", bytes.shadows)?;
        let shade_rays = gpu("shade partition", bytes.shade_rays)?;
        let counters = Buffer::from_slice(device, "counters", &[Counters::default()])?;
        let dispatch_args =
            Buffer::from_slice(device, "dispatch args", &[DispatchArgs::default()])?;
        let set = DescriptorSet::new(
            layout,
            1,
            &[
                &frame_buf,
                &paths,
                &rays,
                &hits,
                &shadows,
                &counters,
                &dispatch_args,
                &paths,
                &rays,
                &hits,
                &shadows,
                &shade_rays,
                &shade_rays,
                &frame_buf,
            ],
        )?;
        Ok(Wavefront {
            frame: frame_buf,
            paths,
            rays,
            hits,
            shadows,
            shade_rays,
            counters,
            dispatch_args,
            set,
            capacity,
        })
    }

    /// Records emptying the queues for a batch whose first ray queue holds `rays`
    /// rays (written by `generate`, or appended by `photon_emit`: 0): the counters,
    /// the queue lengths after the frame, and the indirect dispatch arguments: the
    /// ray queue's for `first_dispatch` threads (the first indirect dispatch: the
    /// batch's first `intersect`, or `photon_emit`; queue_args writes the later ones),
    /// no shadow rays and no deferred items (deferral.glsl), as queue_args leaves them.
    pub fn reset_queues(&self, cmd: &mut CommandList, rays: u32, first_dispatch: u32) {
        let counters = Counters {
            ray_count: [rays, 0],
            ..Default::default()
        };
        cmd.update(&self.counters, 0, bytemuck::bytes_of(&counters));
        let args = DispatchArgs {
            rays: groups_for(first_dispatch),
            shadows: [0, 1, 1],
            deferred_rays: [0, 1, 1],
            deferred_shadows: [0, 1, 1],
            ..Default::default()
        };
        cmd.update(&self.dispatch_args, 0, bytemuck::bytes_of(&args));
        let mut lengths = [0u32; QUEUE_LENGTH_WORDS];
        lengths[0] = rays;
        cmd.update(
            &self.frame,
            size_of::<Frame>() as u64,
            bytemuck::bytes_of(&lengths),
        );
    }

    /// Byte offset of the ray-queue arguments in the dispatch buffer.
    pub const RAY_ARGS: u64 = 0;
    /// Byte offset of the shadow-queue arguments in the dispatch buffer.
    pub const SHADOW_ARGS: u64 = 12;
    /// Byte offsets of the arguments of a partitioned bounce's hits and misses.
    pub const HIT_ARGS: u64 = 24;
    pub const MISS_ARGS: u64 = 36;
    /// Byte offsets of the arguments of the deferred rays and shadow rays.
    pub const DEFERRED_RAY_ARGS: u64 = 48;
    pub const DEFERRED_SHADOW_ARGS: u64 = 60;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The queue lengths follow the frame in one uniform block (std140, the frame an
    /// array of one) and one storage block (std430): both put them at
    /// `size_of::<Frame>()` only if the frame's size is a multiple of a `uvec4`'s 16
    /// bytes (std140's array stride). And the GLSL declares as many words as the host
    /// writes.
    #[test]
    fn queue_lengths_follow_the_frame() {
        assert_eq!(size_of::<Frame>() % 16, 0);
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders/queue/wavefront.glsl");
        let src = std::fs::read_to_string(path).expect("read wavefront.glsl");
        let uvec4s = QUEUE_LENGTH_WORDS / 4;
        assert!(src.contains(&format!(
            "{{ Frame frames[1]; uvec4 queue_lengths[{uvec4s}]; }}"
        )));
        assert!(src.contains(&format!("uvec4 queue_lengths_out[{uvec4s}]; }}")));
    }

    /// The kernels read the frame at an index that is a push constant, never at
    /// constant offsets: lavapipe 22.3 would otherwise re-inline the frame's values
    /// into first_bounce at every dispatch (11-16 ms each; wavefront.glsl says more).
    /// The index is always 0.
    #[test]
    fn the_frame_is_read_at_a_push_constant_index() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders/queue/wavefront.glsl");
        let src = std::fs::read_to_string(path).expect("read wavefront.glsl");
        assert!(src.contains("\n#define frame frames[push.frame_index]\n"));
        assert_eq!(crate::gpu::layout::Push::default().frame_index, 0);
        // No kernel declares a frame of its own in the uniform block.
        let shaders = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders");
        let mut stack = vec![std::path::PathBuf::from(shaders)];
        while let Some(dir) = stack.pop() {
            for entry in std::fs::read_dir(&dir).expect("read shaders") {
                let p = entry.expect("entry").path();
                if p.is_dir() {
                    stack.push(p);
                } else if p.extension().is_some_and(|e| e == "glsl" || e == "comp") {
                    let text = std::fs::read_to_string(&p).expect("read shader");
                    assert!(
                        !text.contains("uniform FrameBuffer { Frame frame;"),
                        "{} reads the frame at constant offsets",
                        p.display()
                    );
                }
            }
        }
    }
}
