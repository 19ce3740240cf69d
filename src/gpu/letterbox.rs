//! The window's pixels from the picture's: the `letterbox` kernel
//! (`shaders/kernels/letterbox.comp`) puts the picture in the largest rectangle of its
//! aspect ratio centred in the window, scaled with bilinear filtering (one window
//! pixel per picture pixel where the sizes agree), and grey bars around it, in the
//! byte order of the window's format, for the swapchain ([`super::Swapchain`]) to copy
//! into the window's image as they are.
//!
//! A compute kernel rather than `vkCmdBlitImage` and `vkCmdClearColorImage`: those run
//! on llvmpipe's graphics pipeline, whose fragment shaders llvmpipe at 512 bits
//! (Mesa 26) crashes compiling, so the viewer could not run on the driver a machine
//! calibrated for.

use ash::vk;

use super::buffer::Buffer;
use super::device::Device;
use super::error::Result;
use super::kernel::{BindingLayout, DescriptorSet, Kernel};
use super::layout::LetterboxPush;
use super::shaders;
use crate::image::png::srgb_oetf;

/// Grey of the bars around a letterboxed picture (linear value).
const BAR_GREY: f32 = 0.05;

/// Workgroup size of `letterbox` in x and y.
const TILE: u32 = 8;

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

/// How a window's format stores a pixel in 4 bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WindowFormat {
    /// The bytes are B, G, R, A (else R, G, B, A).
    pub bgra: bool,
    /// The display decodes the values as sRGB codes (else shows them as they are).
    pub srgb: bool,
}

impl WindowFormat {
    /// The window formats the picture's 8-bit pixels can be copied into, in the order
    /// they are preferred.
    pub const SUPPORTED: [(vk::Format, WindowFormat); 6] = [
        (vk::Format::B8G8R8A8_UNORM, WindowFormat::new(true, false)),
        (vk::Format::R8G8B8A8_UNORM, WindowFormat::new(false, false)),
        (
            vk::Format::A8B8G8R8_UNORM_PACK32,
            WindowFormat::new(false, false),
        ),
        (vk::Format::B8G8R8A8_SRGB, WindowFormat::new(true, true)),
        (vk::Format::R8G8B8A8_SRGB, WindowFormat::new(false, true)),
        (
            vk::Format::A8B8G8R8_SRGB_PACK32,
            WindowFormat::new(false, true),
        ),
    ];

    const fn new(bgra: bool, srgb: bool) -> WindowFormat {
        WindowFormat { bgra, srgb }
    }

    /// The bars' pixel: the same grey code in every colour byte, opaque.
    pub fn bar_pixel(self) -> u32 {
        let v = if self.srgb {
            srgb_oetf(BAR_GREY)
        } else {
            BAR_GREY
        };
        let code = (v * 255.0).round() as u32;
        code | (code << 8) | (code << 16) | (255 << 24)
    }
}

/// What `letterbox` needs to draw a window of `window` pixels in `format` from a
/// picture of `picture` pixels.
pub fn push(window: (u32, u32), picture: (u32, u32), format: WindowFormat) -> LetterboxPush {
    let (x, y, w, h) = letterbox(window, picture);
    let (pw, ph) = (picture.0.max(1), picture.1.max(1));
    LetterboxPush {
        window_width: window.0,
        window_height: window.1,
        x: x as u32,
        y: y as u32,
        width: w,
        height: h,
        picture_width: pw,
        picture_height: ph,
        step_x: pw as f32 / w as f32,
        step_y: ph as f32 / h as f32,
        bar: format.bar_pixel(),
        bgra: format.bgra as u32,
    }
}

/// The workgroups of a dispatch of `letterbox` with `push`.
pub fn groups(push: &LetterboxPush) -> [u32; 3] {
    [
        push.window_width.div_ceil(TILE),
        push.window_height.div_ceil(TILE),
        1,
    ]
}

/// The `letterbox` kernel.
pub struct Letterbox {
    layout: BindingLayout,
    pub kernel: Kernel,
}

impl Letterbox {
    pub fn new(device: &Device) -> Result<Letterbox> {
        let layout = BindingLayout::new(device, &[2], std::mem::size_of::<LetterboxPush>() as u32)?;
        let kernel = Kernel::new(device, "letterbox", shaders::LETTERBOX, &layout, &[])?;
        Ok(Letterbox { layout, kernel })
    }

    /// The set that has it read `picture` (4 bytes a pixel, R in the lowest, top row
    /// first) and write `window` (4 bytes a pixel in the window's order, top row first).
    pub fn bind(&self, picture: &Buffer, window: &Buffer) -> Result<DescriptorSet> {
        DescriptorSet::new(&self.layout, 0, &[picture, window])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn bars_are_the_same_grey_in_either_encoding() {
        // 0.05 as a value shown as it is: code 13; as sRGB: 0.2478, code 63.
        let layout = |format| {
            WindowFormat::SUPPORTED
                .iter()
                .find(|(f, _)| *f == format)
                .map(|(_, w)| *w)
        };
        assert_eq!(
            layout(vk::Format::B8G8R8A8_UNORM),
            Some(WindowFormat::new(true, false))
        );
        assert_eq!(WindowFormat::new(true, false).bar_pixel(), 0xff0d_0d0d);
        assert_eq!(
            layout(vk::Format::R8G8B8A8_SRGB),
            Some(WindowFormat::new(false, true))
        );
        assert_eq!(WindowFormat::new(false, true).bar_pixel(), 0xff3f_3f3f);
        assert!(layout(vk::Format::A2B10G10R10_UNORM_PACK32).is_none());
    }

    #[test]
    fn one_window_pixel_per_picture_pixel_where_the_sizes_agree() {
        let p = push((48, 32), (48, 32), WindowFormat::new(true, false));
        assert_eq!((p.x, p.y, p.width, p.height), (0, 0, 48, 32));
        assert_eq!((p.step_x, p.step_y), (1.0, 1.0));
        assert_eq!(groups(&p), [6, 4, 1]);
    }
}
