//! The picture the window shows: the film's running mean, tone mapped on the GPU by
//! `tonemap` (`shaders/kernels/tonemap.comp`) into 8-bit sRGB pixels that the
//! swapchain copies into the window. The pixels come back to the host only for a
//! screenshot.

use std::path::Path;

use crate::gpu::layout::TonemapPush;
use crate::gpu::{
    shaders, BindingLayout, Buffer, CommandList, DescriptorSet, Device, Kernel, Location,
};
use crate::render::Renderer;

use super::error::Result;

/// Workgroup size of `tonemap` in x and y.
const TILE: u32 = 8;

/// The tonemap kernel and the pixels it writes.
pub struct Picture {
    device: Device,
    kernel: Kernel,
    set: DescriptorSet,
    /// 4 bytes a pixel (R, G, B, 255), top row first: what the window shows.
    pub pixels: Buffer,
    pub width: u32,
    pub height: u32,
    luminance: bool,
}

impl Picture {
    /// The picture of `renderer`'s film (its crop window); `luminance`: show grey, as
    /// the PNG of a luminance film is.
    pub fn new(device: &Device, renderer: &Renderer, luminance: bool) -> Result<Picture> {
        let crop = renderer.film_geometry().crop;
        let (width, height) = (crop.width, crop.height);
        let layout = BindingLayout::new(device, &[2], std::mem::size_of::<TonemapPush>() as u32)?;
        let kernel = Kernel::new(device, "tonemap", shaders::TONEMAP, &layout, &[])?;
        let pixels = Buffer::new(
            device,
            "window pixels",
            u64::from(width) * u64::from(height) * 4,
            Location::Gpu,
        )?;
        let set = DescriptorSet::new(&layout, 0, &[renderer.film_sums_buffer(), &pixels])?;
        Ok(Picture {
            device: device.clone(),
            kernel,
            set,
            pixels,
            width,
            height,
            luminance,
        })
    }

    /// Tone maps the film as it stands with `exposure` stops into the pixels.
    pub fn develop(&self, exposure: f32) -> Result<()> {
        let push = TonemapPush {
            width: self.width,
            height: self.height,
            scale: exposure.exp2(),
            luminance: self.luminance as u32,
        };
        let mut cmd = CommandList::new(&self.device)?;
        cmd.dispatch(
            &self.kernel,
            &[&self.set],
            bytemuck::bytes_of(&push),
            [self.width.div_ceil(TILE), self.height.div_ceil(TILE), 1],
        );
        cmd.barrier();
        cmd.submit_and_wait()?;
        Ok(())
    }

    /// The pixels as 8-bit sRGB RGB, 3 bytes a pixel, top row first.
    pub fn read_rgb8(&self) -> Result<Vec<u8>> {
        let words: Vec<u32> = self.pixels.read(&self.device)?;
        let n = (self.width * self.height) as usize;
        Ok(words[..n]
            .iter()
            .flat_map(|w| {
                let b = w.to_le_bytes();
                [b[0], b[1], b[2]]
            })
            .collect())
    }

    /// Writes what the window shows as an 8-bit sRGB PNG.
    pub fn write_png(&self, path: &Path) -> Result<()> {
        let rgb = self.read_rgb8()?;
        crate::image::png::write_rgb8(path, self.width, self.height, &rgb)?;
        Ok(())
    }
}
