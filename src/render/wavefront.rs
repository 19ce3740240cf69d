//! The wavefront's GPU state: path states, ray, hit and shadow queues, counters and
//! dispatch arguments — descriptor set 1 (`shaders/common/wavefront.glsl`). The film
//! is set 3 ([`super::film`]), the photon mappers' set 2.

use std::mem::size_of;

use crate::gpu::layout::{Counters, DispatchArgs, Frame, HitItem, PathState, RayItem, ShadowItem};
use crate::gpu::{BindingKind, BindingLayout, Buffer, DescriptorSet, Device, Location};

use super::error::Result;

/// Bindings of set 1, in order.
pub const WAVEFRONT_BINDINGS: u32 = 13;

/// The kind of each binding of set 1: the frame is a uniform buffer; path states,
/// rays, hits and shadow rays are written as storage buffers (bindings 1-4) and read
/// through texel views of the same buffers (bindings 7-10), see
/// [`BindingKind::Texels`]; likewise the partition of a bounce's rays (written at 11,
/// read as words at 12).
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
/// hit, a shadow ray, a queue index of the partition).
pub const BYTES_PER_PATH: u64 = (size_of::<PathState>()
    + 2 * size_of::<RayItem>()
    + size_of::<HitItem>()
    + size_of::<ShadowItem>()
    + size_of::<u32>()) as u64;

pub struct Wavefront {
    pub frame: Buffer,
    pub paths: Buffer,
    pub rays: Buffer,
    pub hits: Buffer,
    pub shadows: Buffer,
    /// Queue indices of a bounce's hits (from the front) and misses (from the back)
    /// where `intersect` partitions them for `shade`.
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
    ) -> Result<Wavefront> {
        let n = capacity as u64;
        let frame_buf = Buffer::from_slice(device, "frame", std::slice::from_ref(frame))?;
        let paths = Buffer::new(
            device,
            "path states",
            n * size_of::<PathState>() as u64,
            Location::Gpu,
        )?;
        let rays = Buffer::new(
            device,
            "ray queues",
            2 * n * size_of::<RayItem>() as u64,
            Location::Gpu,
        )?;
        let hits = Buffer::new(
            device,
            "hits",
            n * size_of::<HitItem>() as u64,
            Location::Gpu,
        )?;
        let shadows = Buffer::new(
            device,
            "shadow queue",
            n * size_of::<ShadowItem>() as u64,
            Location::Gpu,
        )?;
        let shade_rays = Buffer::new(
            device,
            "shade partition",
            n * size_of::<u32>() as u64,
            Location::Gpu,
        )?;
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

    /// Byte offset of the ray-queue arguments in the dispatch buffer.
    pub const RAY_ARGS: u64 = 0;
    /// Byte offset of the shadow-queue arguments in the dispatch buffer.
    pub const SHADOW_ARGS: u64 = 12;
    /// Byte offsets of the arguments of a partitioned bounce's hits and misses.
    pub const HIT_ARGS: u64 = 24;
    pub const MISS_ARGS: u64 = 36;
}
