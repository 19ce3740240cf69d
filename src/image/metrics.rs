//! Error metrics between a render and a reference, and a noise-aware comparison for
//! image tests.

use super::Image;

/// ε of [`rel_mse`]: keeps dark reference pixels from dominating.
pub const REL_MSE_EPSILON: f64 = 1e-2;

fn check_sizes(a: &Image, b: &Image) {
    assert!(
        a.width == b.width && a.height == b.height,
        "images differ in size: {}x{} vs {}x{}",
        a.width,
        a.height,
        b.width,
        b.height
    );
}

/// Mean squared error over every pixel and channel.
pub fn mse(img: &Image, reference: &Image) -> f64 {
    check_sizes(img, reference);
    let n = img.rgb.len().max(1) as f64;
    img.rgb
        .iter()
        .zip(&reference.rgb)
        .map(|(&a, &b)| (a as f64 - b as f64).powi(2))
        .sum::<f64>()
        / n
}

pub fn rmse(img: &Image, reference: &Image) -> f64 {
    mse(img, reference).sqrt()
}

/// Relative MSE: mean of (a - b)² / (b² + ε) over pixels and channels (Rousselle et
/// al. 2011), ε = [`REL_MSE_EPSILON`].
pub fn rel_mse(img: &Image, reference: &Image) -> f64 {
    check_sizes(img, reference);
    let n = img.rgb.len().max(1) as f64;
    img.rgb
        .iter()
        .zip(&reference.rgb)
        .map(|(&a, &b)| {
            let (a, b) = (a as f64, b as f64);
            (a - b).powi(2) / (b * b + REL_MSE_EPSILON)
        })
        .sum::<f64>()
        / n
}

/// Mean of each channel.
pub fn mean(img: &Image) -> [f64; 3] {
    let mut m = [0.0; 3];
    for px in img.rgb.chunks_exact(3) {
        for c in 0..3 {
            m[c] += px[c] as f64;
        }
    }
    let n = (img.rgb.len() / 3).max(1) as f64;
    m.map(|v| v / n)
}

/// The result of [`compare_blocks`].
#[derive(Debug, Clone, Copy)]
pub struct BlockComparison {
    /// Largest |z| over blocks and channels.
    pub max_abs_z: f64,
    /// Mean of z² over blocks and channels: about 1 when the difference is noise.
    pub mean_z2: f64,
    /// Largest |mean difference| of a block relative to the reference block mean.
    pub max_rel_diff: f64,
    pub blocks: usize,
}

/// Compares a noisy render with a reference that is far less noisy, in `block` x
/// `block` pixel blocks: per block and channel, z = (mean(render) - mean(reference)) /
/// (standard error of the render block's mean, from the variance of its pixels, each
/// pixel being an average of independent samples). A correct render gives z ~ N(0, 1)
/// per block; a missing factor or a bias shows up as large |z| across many blocks.
/// Blocks whose pixels are all equal (no noise) compare with a small absolute floor
/// `sigma_floor` instead.
pub fn compare_blocks(
    img: &Image,
    reference: &Image,
    block: u32,
    sigma_floor: f64,
) -> BlockComparison {
    check_sizes(img, reference);
    let (bw, bh) = (img.width / block, img.height / block);
    let mut out = BlockComparison {
        max_abs_z: 0.0,
        mean_z2: 0.0,
        max_rel_diff: 0.0,
        blocks: (bw * bh) as usize,
    };
    let mut count = 0usize;
    for by in 0..bh {
        for bx in 0..bw {
            for c in 0..3 {
                let (mut sa, mut sa2, mut sb) = (0.0f64, 0.0f64, 0.0f64);
                for y in by * block..(by + 1) * block {
                    for x in bx * block..(bx + 1) * block {
                        let a = img.pixel(x, y)[c] as f64;
                        sa += a;
                        sa2 += a * a;
                        sb += reference.pixel(x, y)[c] as f64;
                    }
                }
                let n = (block * block) as f64;
                let (ma, mb) = (sa / n, sb / n);
                let var = ((sa2 / n - ma * ma) * n / (n - 1.0).max(1.0)).max(0.0);
                let se = (var / n).sqrt().max(sigma_floor);
                let z = (ma - mb) / se;
                out.max_abs_z = out.max_abs_z.max(z.abs());
                out.mean_z2 += z * z;
                out.max_rel_diff = out.max_rel_diff.max((ma - mb).abs() / mb.abs().max(1e-3));
                count += 1;
            }
        }
    }
    out.mean_z2 /= count.max(1) as f64;
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn img(values: &[f32]) -> Image {
        Image {
            width: (values.len() / 3) as u32,
            height: 1,
            rgb: values.to_vec(),
        }
    }

    #[test]
    fn metrics_on_known_inputs() {
        let a = img(&[1.0, 2.0, 3.0, 0.0, 0.0, 0.0]);
        let b = img(&[1.0, 2.0, 1.0, 0.0, 0.0, 1.0]);
        assert!((mse(&a, &b) - 5.0 / 6.0).abs() < 1e-12);
        assert!((rmse(&a, &b) - (5.0f64 / 6.0).sqrt()).abs() < 1e-12);
        let expected = (4.0 / (1.0 + 0.01) + 1.0 / (1.0 + 0.01)) / 6.0;
        assert!((rel_mse(&a, &b) - expected).abs() < 1e-12);
        assert_eq!(mean(&a), [0.5, 1.0, 1.5]);
    }

    #[test]
    fn block_comparison_accepts_noise_and_rejects_bias() {
        // A deterministic noisy image around 1 and the exact reference.
        let (w, h) = (64u32, 64u32);
        let mut noisy = Image::new(w, h);
        let mut state = 12345u32;
        for v in noisy.rgb.iter_mut() {
            state = state.wrapping_mul(1664525).wrapping_add(1013904223);
            *v = 1.0 + ((state >> 8) as f32 / 16777216.0 - 0.5);
        }
        let mut reference = Image::new(w, h);
        reference.rgb.iter_mut().for_each(|v| *v = 1.0);
        let ok = compare_blocks(&noisy, &reference, 8, 1e-6);
        assert!(ok.max_abs_z < 5.0 && ok.mean_z2 < 2.0, "{ok:?}");
        // Pixel noise sd 0.29, so a block mean's standard error is 0.036: a 20% bias
        // is 5.5 standard errors per block.
        reference.rgb.iter_mut().for_each(|v| *v = 1.2);
        let bad = compare_blocks(&noisy, &reference, 8, 1e-6);
        assert!(bad.max_abs_z > 5.0 && bad.mean_z2 > 4.0, "{bad:?}");
    }
}
