//! The viewer's `letterbox` kernel (src/gpu/letterbox.rs) on the device, against the
//! same drawing done here on the CPU: bars where the picture is not, one window pixel
//! per picture pixel where the sizes agree, bilinear filtering with clamped edges where
//! they do not (as vkCmdBlitImage's linear filter), and the window format's byte order.

mod common;

use wavetrace::gpu::layout::LetterboxPush;
use wavetrace::gpu::letterbox::{self, WindowFormat};

/// A picture of distinct pixels (R, G, B varying with x and y, opaque).
fn picture(w: u32, h: u32) -> Vec<u32> {
    (0..h)
        .flat_map(|y| {
            (0..w).map(move |x| {
                let r = (x * 255 / w.max(2).saturating_sub(1).max(1)).min(255);
                let g = (y * 255 / h.max(2).saturating_sub(1).max(1)).min(255);
                let b = (x * 37 + y * 91) % 256;
                r | (g << 8) | (b << 16) | (255 << 24)
            })
        })
        .collect()
}

fn channels(p: u32) -> [f32; 4] {
    [0, 8, 16, 24].map(|s| ((p >> s) & 255) as f32)
}

/// The window `push` describes, drawn here: f64 bilinear on the codes, rounded.
fn expected(push: &LetterboxPush, pic: &[u32]) -> Vec<u32> {
    let (pw, ph) = (push.picture_width as usize, push.picture_height as usize);
    let texel = |x: usize, y: usize| channels(pic[y.min(ph - 1) * pw + x.min(pw - 1)]);
    let mut out = Vec::new();
    for wy in 0..push.window_height {
        for wx in 0..push.window_width {
            let inside = wx >= push.x
                && wy >= push.y
                && wx < push.x + push.width
                && wy < push.y + push.height;
            if !inside {
                out.push(push.bar);
                continue;
            }
            let cx = ((f64::from(wx - push.x) + 0.5) * f64::from(push.step_x) - 0.5).max(0.0);
            let cy = ((f64::from(wy - push.y) + 0.5) * f64::from(push.step_y) - 0.5).max(0.0);
            let (x0, y0) = (
                (cx.floor() as usize).min(pw - 1),
                (cy.floor() as usize).min(ph - 1),
            );
            let (fx, fy) = (
                (cx - x0 as f64).clamp(0.0, 1.0),
                (cy - y0 as f64).clamp(0.0, 1.0),
            );
            let (a, b, c, d) = (
                texel(x0, y0),
                texel(x0 + 1, y0),
                texel(x0, y0 + 1),
                texel(x0 + 1, y0 + 1),
            );
            let mut v = [0u32; 4];
            for i in 0..4 {
                let top = f64::from(a[i]) * (1.0 - fx) + f64::from(b[i]) * fx;
                let bottom = f64::from(c[i]) * (1.0 - fx) + f64::from(d[i]) * fx;
                v[i] = (top * (1.0 - fy) + bottom * fy).round() as u32;
            }
            if push.bgra != 0 {
                v.swap(0, 2);
            }
            out.push(v[0] | (v[1] << 8) | (v[2] << 16) | (v[3] << 24));
        }
    }
    out
}

/// Pixels of `got` off `want` by more than one code in a channel (float rounding of
/// the filter's weights), as (index, got, want), at most 5.
fn off(got: &[u32], want: &[u32]) -> Vec<(usize, u32, u32)> {
    assert_eq!(got.len(), want.len());
    got.iter()
        .zip(want)
        .enumerate()
        .filter(|(_, (g, w))| {
            channels(**g)
                .iter()
                .zip(channels(**w))
                .any(|(a, b)| (a - b).abs() > 1.0)
        })
        .map(|(i, (g, w))| (i, *g, *w))
        .take(5)
        .collect()
}

#[test]
fn the_same_size_copies_every_pixel_in_the_window_order() {
    let pic = picture(13, 7);
    for format in WindowFormat::SUPPORTED.map(|(_, f)| f) {
        let push = letterbox::push((13, 7), (13, 7), format);
        let got = common::letterbox_window(&push, &pic);
        assert_eq!(got, expected(&push, &pic), "{format:?}");
        if format.bgra {
            assert_eq!(
                got[1],
                (pic[1] & 0xff00ff00) | ((pic[1] & 255) << 16) | ((pic[1] >> 16) & 255)
            );
        } else {
            assert_eq!(got, pic);
        }
    }
}

#[test]
fn a_larger_window_scales_the_picture_between_bars() {
    let pic = picture(12, 8);
    let format = WindowFormat::SUPPORTED[0].1;
    // Wider than the picture's aspect: bars left and right, scaled 2.5x.
    let push = letterbox::push((50, 20), (12, 8), format);
    assert_eq!((push.x, push.y, push.width, push.height), (10, 0, 30, 20));
    let got = common::letterbox_window(&push, &pic);
    let want = expected(&push, &pic);
    assert_eq!(off(&got, &want), vec![]);
    assert_eq!(got[0], format.bar_pixel());
    assert_eq!(got[49], format.bar_pixel());
    assert_ne!(got[25], format.bar_pixel());
}

#[test]
fn a_smaller_window_shrinks_the_picture_between_bars() {
    let pic = picture(40, 30);
    let format = WindowFormat::SUPPORTED[4].1;
    // Taller than the picture's aspect: bars above and below.
    let push = letterbox::push((16, 20), (40, 30), format);
    assert_eq!((push.x, push.y, push.width, push.height), (0, 4, 16, 12));
    let got = common::letterbox_window(&push, &pic);
    assert_eq!(off(&got, &expected(&push, &pic)), vec![]);
    assert!(got[..16 * 4].iter().all(|p| *p == format.bar_pixel()));
    assert!(got[16 * 16..].iter().all(|p| *p == format.bar_pixel()));
}
