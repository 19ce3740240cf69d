//! Helpers of the media tests (media_*.rs): rendering with statistics, the finiteness
//! check every stress render makes, and Mitsuba `.vol` grids written on the fly.

use wavetrace::gpu::Device;
use wavetrace::image::Image;
use wavetrace::render::{RenderOptions, RenderStats, Renderer};
use wavetrace::scene::Scene;

/// Renders `scene` at `spp` with `seed` (and `integrator` in place of the scene's):
/// the image and the render's statistics.
pub fn render_stats(
    device: &Device,
    scene: &Scene,
    integrator: Option<&str>,
    spp: u32,
    seed: u32,
) -> (Image, RenderStats) {
    let options = RenderOptions {
        integrator: integrator.map(str::to_string),
        seed,
        ..Default::default()
    };
    let mut r = Renderer::new(device, scene, &options).unwrap_or_else(|e| panic!("setup: {e}"));
    r.render(spp, &mut |_, _| {}).expect("render")
}

/// Every pixel finite and no sample dropped as NaN or infinite.
pub fn assert_finite(name: &str, img: &Image, stats: &RenderStats) {
    assert_eq!(stats.discarded, 0, "{name}: NaN or infinite samples");
    assert!(
        img.rgb.iter().all(|v| v.is_finite() && *v >= 0.0),
        "{name}: bad pixel"
    );
}

/// A Mitsuba .vol file's bytes (float32, bounding box the unit cube).
pub fn vol_bytes(res: [i32; 3], data: &[f32]) -> Vec<u8> {
    let mut b = b"VOL\x03".to_vec();
    for i in [1, res[0], res[1], res[2], 1] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    for f in [0f32, 0.0, 0.0, 1.0, 1.0, 1.0].iter().chain(data) {
        b.extend_from_slice(&f.to_le_bytes());
    }
    b
}
