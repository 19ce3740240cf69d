//! The samplers of shaders/sampler/ on the GPU (test kernel shaders/tests/sampler.comp,
//! specialized to each kind as the renderer's kernels are): uniformity of every
//! dimension and of pairs of dimensions (chi-square), the stratification each kind
//! promises (exact counts per stratum, (0,2)-nets), no correlation between dimensions,
//! and sample indices past the pattern's count (later passes).

mod common;

use bytemuck::{Pod, Zeroable};
use common::stats::{assert_fit, chi2};
use wavetrace::gpu::{
    shaders, BindingLayout, Buffer, CommandList, DescriptorSet, Device, Kernel, Location,
};
use wavetrace::render::sampler::{flags, kind_id};
use wavetrace::scene::sampler::{Randomization, Sampler, SamplerKind};

/// The kernel's push constants: a `Sampler` (sampler.glsl) and the block to evaluate.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Push {
    kind: u32,
    count: u32,
    res_x: u32,
    res_y: u32,
    flags: u32,
    seed: u32,
    width: u32,
    height: u32,
    pixel_base: u32,
    sample_base: u32,
    dim_base: u32,
    samples: u32,
    dims: u32,
    total: u32,
    mode: u32,
    pad: u32,
}

/// Film of the tests' pixel keys (zsobol reads positions from them).
const WIDTH: u32 = 16;
const HEIGHT: u32 = 16;

struct Probe {
    device: Device,
    layout: BindingLayout,
    sampler: Sampler,
    push: Push,
    kernel: Kernel,
}

impl Probe {
    /// `sampler` drawing patterns of `spp` samples (as it rounds them).
    fn new(device: &Device, sampler: Sampler, spp: u32) -> Probe {
        let layout = BindingLayout::new(device, &[1], std::mem::size_of::<Push>() as u32).unwrap();
        let kernel = Kernel::new(
            device,
            "sampler",
            shaders::TESTS_SAMPLER,
            &layout,
            &[kind_id(&sampler)],
        )
        .unwrap();
        let c = sampler.sample_count(spp, WIDTH, HEIGHT).unwrap();
        let push = Push {
            kind: kind_id(&sampler),
            count: c.count,
            res_x: c.res[0],
            res_y: c.res[1],
            flags: flags(&sampler),
            seed: 7,
            width: WIDTH,
            height: HEIGHT,
            ..Zeroable::zeroed()
        };
        Probe {
            device: device.clone(),
            layout,
            sampler,
            push,
            kernel,
        }
    }

    fn count(&self) -> u32 {
        self.push.count
    }

    /// Dimensions dims of samples of pixels, 2-D (`two_d`) or 1-D draws; indexed
    /// [pixel][sample][dim].
    fn eval(
        &self,
        pixels: std::ops::Range<u32>,
        samples: std::ops::Range<u32>,
        dims: std::ops::Range<u32>,
        two_d: bool,
    ) -> Vec<[f32; 2]> {
        let n_s = samples.len() as u32;
        let n_d = dims.len() as u32;
        let total = pixels.len() as u32 * n_s * n_d;
        let push = Push {
            pixel_base: pixels.start,
            sample_base: samples.start,
            dim_base: dims.start,
            samples: n_s,
            dims: n_d,
            total,
            mode: if two_d { 0 } else { 1 },
            ..self.push
        };
        let d = &self.device;
        let out = Buffer::new(d, "out", total as u64 * 8, Location::Gpu).unwrap();
        let set = DescriptorSet::new(&self.layout, 0, &[&out]).unwrap();
        let mut cmd = CommandList::new(d).unwrap();
        cmd.dispatch(
            &self.kernel,
            &[&set],
            bytemuck::bytes_of(&push),
            [total.div_ceil(64), 1, 1],
        );
        cmd.barrier();
        cmd.submit_and_wait().unwrap();
        let mut v: Vec<[f32; 2]> = out.read(d).unwrap();
        v.truncate(total as usize);
        for p in &v {
            assert!(
                (0.0..1.0).contains(&p[0]) && (0.0..1.0).contains(&p[1]),
                "{:?}: {p:?} outside [0, 1)",
                self.sampler.kind
            );
        }
        v
    }
}

fn every_kind() -> Vec<Sampler> {
    let mut v: Vec<Sampler> = SamplerKind::NAMES
        .iter()
        .map(|n| Sampler::new(SamplerKind::from_name(n).unwrap()))
        .collect();
    v.push(Sampler {
        strength: 3,
        ..Sampler::new(SamplerKind::Orthogonal)
    });
    v.push(Sampler {
        jitter: false,
        ..Sampler::new(SamplerKind::Multijitter)
    });
    for r in [Randomization::Owen, Randomization::PermuteDigits] {
        v.push(Sampler {
            randomization: r,
            ..Sampler::new(SamplerKind::ZSobol)
        });
    }
    v
}

/// Dimensions of `every_dimension_and_pair_is_uniform`.
const DIMS: u32 = 6;
/// Dimensions of `distant_dimensions_are_uncorrelated`: the first against each other.
const DISTANT: [u32; 5] = [2, 8, 14, 50, 1000];

/// Chi-square tests in this file, for the Šidák level, counted from the loops that run
/// them: per sampler kind, `every_dimension_and_pair_is_uniform` tests each dimension's
/// two coordinates and its 2-D grid (3 per dimension), one cross pair and the 1-D draws;
/// `distant_dimensions_are_uncorrelated` one grid per distant dimension.
fn tests() -> usize {
    every_kind().len() * (3 * DIMS as usize + 2 + (DISTANT.len() - 1))
}
/// Family-wise false-alarm rate of the chi-square tests of this file.
const ALPHA: f64 = 0.01;

/// Counts of values in `cells` equal bins of [0, 1).
fn histogram(values: impl Iterator<Item = f32>, cells: usize) -> Vec<f64> {
    let mut h = vec![0.0; cells];
    for v in values {
        h[((v * cells as f32) as usize).min(cells - 1)] += 1.0;
    }
    h
}

/// Counts of points in a cells x cells grid.
fn histogram_2d(points: impl Iterator<Item = (f32, f32)>, cells: usize) -> Vec<f64> {
    let mut h = vec![0.0; cells * cells];
    for (x, y) in points {
        let i = ((x * cells as f32) as usize).min(cells - 1);
        let j = ((y * cells as f32) as usize).min(cells - 1);
        h[j * cells + i] += 1.0;
    }
    h
}

#[test]
fn every_dimension_and_pair_is_uniform() {
    // 64 pixels x 16 samples x 6 dimensions; chi-square on 16 bins per dimension and on
    // an 8 x 8 grid for the two coordinates of a 2-D dimension and for coordinates of
    // different dimensions (first of dimension 1 against the second of dimension 4).
    // Each kind's values pooled over pixels: stratified kinds fit better than chance,
    // which a goodness-of-fit test accepts; a biased or clumped one fails.
    let device = common::device();
    for s in every_kind() {
        let p = Probe::new(&device, s, 16);
        let (px, ns, nd) = (64u32, p.count(), DIMS);
        let v = p.eval(0..px, 0..ns, 0..nd, true);
        let at = |pix: u32, smp: u32, d: u32| v[((pix * ns + smp) * nd + d) as usize];
        let n = (px * ns) as f64;
        for d in 0..nd {
            for c in 0..2 {
                let h = histogram((0..px * ns).map(|k| at(k / ns, k % ns, d)[c]), 16);
                assert_fit(
                    &format!("{:?} dim {d}.{c}", s),
                    &h,
                    &[n / 16.0; 16],
                    ALPHA,
                    tests(),
                );
            }
            let h = histogram_2d(
                (0..px * ns).map(|k| {
                    let u = at(k / ns, k % ns, d);
                    (u[0], u[1])
                }),
                8,
            );
            assert_fit(
                &format!("{:?} dim {d} 2-D", s),
                &h,
                &[n / 64.0; 64],
                ALPHA,
                tests(),
            );
        }
        let h = histogram_2d(
            (0..px * ns).map(|k| (at(k / ns, k % ns, 1)[0], at(k / ns, k % ns, 4)[1])),
            8,
        );
        assert_fit(
            &format!("{:?} dims 1 x 4", s),
            &h,
            &[n / 64.0; 64],
            ALPHA,
            tests(),
        );
        // 1-D draws are uniform too.
        let w = p.eval(0..px, 0..ns, 0..2, false);
        let h = histogram(w.iter().map(|u| u[0]), 16);
        let n1 = w.len() as f64;
        assert_fit(
            &format!("{:?} 1-D", s),
            &h,
            &[n1 / 16.0; 16],
            ALPHA,
            tests(),
        );
    }
}

/// Checks that each pixel's `count` values of `stratum(value)` hit every stratum in
/// `0..strata` exactly `count / strata` times.
fn assert_strata(name: &str, values: &[u32], strata: u32) {
    let mut h = vec![0u32; strata as usize];
    for &v in values {
        h[v as usize] += 1;
    }
    let want = values.len() as u32 / strata;
    assert!(
        h.iter().all(|&c| c == want),
        "{name}: strata counts {h:?}, want {want} each"
    );
}

fn stratum(u: f32, n: u32) -> u32 {
    ((u * n as f32) as u32).min(n - 1)
}

/// Checks one pixel's 2-D and 1-D draws of one dimension (name, 2-D, 1-D, count).
type StrataCheck = dyn Fn(&str, &[[f32; 2]], &[[f32; 2]], u32);

#[test]
fn stratified_kinds_fill_every_stratum_exactly() {
    let device = common::device();
    // Per pixel, per dimension, for the first and for a later pass (samples 2N..3N).
    let check = |s: Sampler, spp: u32, f: &StrataCheck| {
        let p = Probe::new(&device, s, spp);
        let n = p.count();
        for pass in [0, 2] {
            let samples = pass * n..(pass + 1) * n;
            let two = p.eval(0..8, samples.clone(), 0..5, true);
            let one = p.eval(0..8, samples, 0..5, false);
            for pix in 0..8u32 {
                for d in 0..5u32 {
                    let pick = |v: &[[f32; 2]]| -> Vec<[f32; 2]> {
                        (0..n)
                            .map(|i| v[((pix * n + i) * 5 + d) as usize])
                            .collect()
                    };
                    let name = format!("{:?} pixel {pix} dim {d} pass {pass}", s.kind);
                    f(&name, &pick(&two), &pick(&one), n);
                }
            }
        }
    };
    // stratified, 49 = 7 x 7: a 2-D dimension has one point per cell, a 1-D one per
    // 1/49.
    check(
        Sampler::new(SamplerKind::Stratified),
        49,
        &|name, two, one, n| {
            assert_strata(
                name,
                &two.iter()
                    .map(|u| stratum(u[1], 7) * 7 + stratum(u[0], 7))
                    .collect::<Vec<_>>(),
                n,
            );
            assert_strata(
                name,
                &one.iter().map(|u| stratum(u[0], n)).collect::<Vec<_>>(),
                n,
            );
        },
    );
    // multijitter, 30 = 6 columns x 5 rows: one point per cell, and both projections
    // of a 2-D dimension in 30 strata (the "multi" of multi-jittered).
    check(
        Sampler::new(SamplerKind::Multijitter),
        30,
        &|name, two, one, n| {
            assert_strata(
                name,
                &two.iter()
                    .map(|u| stratum(u[1], 5) * 6 + stratum(u[0], 6))
                    .collect::<Vec<_>>(),
                n,
            );
            assert_strata(
                name,
                &two.iter().map(|u| stratum(u[0], n)).collect::<Vec<_>>(),
                n,
            );
            assert_strata(
                name,
                &two.iter().map(|u| stratum(u[1], n)).collect::<Vec<_>>(),
                n,
            );
            assert_strata(
                name,
                &one.iter().map(|u| stratum(u[0], n)).collect::<Vec<_>>(),
                n,
            );
        },
    );
    // orthogonal (strength 2), 25 = 5^2: each coordinate in 25 strata, the two of a 2-D
    // dimension on the 5 x 5 grid.
    check(
        Sampler::new(SamplerKind::Orthogonal),
        25,
        &|name, two, one, n| {
            assert_strata(
                name,
                &two.iter()
                    .map(|u| stratum(u[1], 5) * 5 + stratum(u[0], 5))
                    .collect::<Vec<_>>(),
                n,
            );
            assert_strata(
                name,
                &two.iter().map(|u| stratum(u[0], n)).collect::<Vec<_>>(),
                n,
            );
            assert_strata(
                name,
                &two.iter().map(|u| stratum(u[1], n)).collect::<Vec<_>>(),
                n,
            );
            assert_strata(
                name,
                &one.iter().map(|u| stratum(u[0], n)).collect::<Vec<_>>(),
                n,
            );
        },
    );
}

#[test]
fn orthogonal_columns_are_pairwise_stratified() {
    // Strength 2 (Bose): any two distinct columns of the array are stratified on the
    // s x s grid. Dimension d's coordinates are columns 2d and 2d + 1; with s = 7 the
    // columns 0..7 (dimensions 0..3) are distinct (columns repeat mod s).
    let device = common::device();
    let p = Probe::new(&device, Sampler::new(SamplerKind::Orthogonal), 49);
    let n = p.count();
    let v = p.eval(0..4, 0..n, 0..4, true);
    for pix in 0..4u32 {
        let col = |i: u32, c: u32| v[((pix * n + i) * 4 + c / 2) as usize][(c % 2) as usize];
        for a in 0..8u32 {
            for b in a + 1..8 {
                let cells: Vec<u32> = (0..n)
                    .map(|i| stratum(col(i, a), 7) * 7 + stratum(col(i, b), 7))
                    .collect();
                assert_strata(
                    &format!("orthogonal pixel {pix} columns {a}, {b}"),
                    &cells,
                    n,
                );
            }
        }
    }
}

/// Checks that `points` (2^m of them) form a (0, m, 2)-net in base 2: every elementary
/// interval [i / 2^a, (i + 1) / 2^a) x [j / 2^b, (j + 1) / 2^b) with a + b = m holds
/// exactly one point.
fn assert_02_net(name: &str, points: &[[f32; 2]]) {
    let m = points.len().trailing_zeros();
    assert_eq!(1 << m, points.len());
    for a in 0..=m {
        let b = m - a;
        let cells: Vec<u32> = points
            .iter()
            .map(|u| (stratum(u[0], 1 << a) << b) | stratum(u[1], 1 << b))
            .collect();
        assert_strata(
            &format!("{name}, intervals 2^-{a} x 2^-{b}"),
            &cells,
            1 << m,
        );
    }
}

#[test]
fn ldsampler_and_zsobol_pixels_are_02_nets() {
    // ldsampler: every 2-D dimension of a pixel is the first 4^k points of the
    // (0,2)-sequence, digitally shifted: a (0, 2k, 2)-net. zsobol: a pixel's samples
    // are an aligned block of 2^m Sobol' indices, Owen-scrambled: a (0, m, 2)-net for
    // any m (here 64 and 32 samples), for every randomization.
    let device = common::device();
    let mut cases = vec![(Sampler::new(SamplerKind::LdSampler), 64)];
    for r in [
        Randomization::FastOwen,
        Randomization::Owen,
        Randomization::PermuteDigits,
        Randomization::None,
    ] {
        for spp in [64, 32] {
            cases.push((
                Sampler {
                    randomization: r,
                    ..Sampler::new(SamplerKind::ZSobol)
                },
                spp,
            ));
        }
    }
    for (s, spp) in cases {
        let p = Probe::new(&device, s, spp);
        let n = p.count();
        for pass in [0, 1] {
            let v = p.eval(0..6, pass * n..(pass + 1) * n, 0..5, true);
            for pix in 0..6u32 {
                for d in 0..5u32 {
                    let pts: Vec<[f32; 2]> = (0..n)
                        .map(|i| v[((pix * n + i) * 5 + d) as usize])
                        .collect();
                    assert_02_net(
                        &format!(
                            "{:?} {:?} {n} spp pixel {pix} dim {d} pass {pass}",
                            s.kind, s.randomization
                        ),
                        &pts,
                    );
                }
            }
        }
    }
}

/// Pearson's correlation of two equally long series.
fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma) * (x - ma);
        sbb += (y - mb) * (y - mb);
    }
    sab / (saa * sbb).sqrt()
}

#[test]
fn distant_dimensions_are_uncorrelated() {
    // Dimensions 2 and 2 + 6k (the same slot of bounces k apart) and a far one, over
    // 64 pixels x count samples: |r| below 4.5 / sqrt(n) (about 4.5 standard errors of
    // a zero correlation, so a false alarm over the ~60 checks here is below 1e-3),
    // and no 2-D dependence (chi-square on a grid of the pair).
    let device = common::device();
    for s in every_kind() {
        let p = Probe::new(&device, s, 16);
        let n = p.count();
        let dims = DISTANT;
        let series: Vec<Vec<[f32; 2]>> = dims
            .iter()
            .map(|&d| p.eval(0..64, 0..n, d..d + 1, true))
            .collect();
        let len = series[0].len();
        let limit = 4.5 / (len as f64).sqrt();
        for k in 1..dims.len() {
            for c in 0..2 {
                let a: Vec<f64> = series[0].iter().map(|u| u[c] as f64).collect();
                let b: Vec<f64> = series[k].iter().map(|u| u[c] as f64).collect();
                let r = correlation(&a, &b);
                assert!(
                    r.abs() < limit,
                    "{:?}: dims {} and {} coordinate {c}: correlation {r:.4} (limit {limit:.4})",
                    s,
                    dims[0],
                    dims[k]
                );
            }
            // 8 x 8 cells: a multiple of the 16 strata, so that the discrete values of
            // unjittered patterns fill the cells evenly.
            let h = histogram_2d(
                series[0].iter().zip(&series[k]).map(|(a, b)| (a[0], b[0])),
                8,
            );
            let e = vec![len as f64 / 64.0; 64];
            let r = chi2(&h, &e);
            assert!(
                r.p_value > common::stats::sidak(ALPHA, tests()),
                "{:?}: dims {} and {} dependent: X² = {:.1}, p = {:.2e}",
                s,
                dims[0],
                dims[k],
                r.statistic,
                r.p_value
            );
        }
    }
}

#[test]
fn samples_are_a_function_of_pixel_sample_and_dimension() {
    // The same (pixel, sample, dimension) gives the same numbers whatever block it is
    // evaluated in (a batch, a sample range, a resumed render).
    let device = common::device();
    for s in every_kind() {
        let p = Probe::new(&device, s, 16);
        let n = p.count();
        let whole = p.eval(0..8, 0..3 * n, 0..4, true);
        let part = p.eval(5..7, n + 3..2 * n + 5, 2..4, true);
        for (k, u) in part.iter().enumerate() {
            let k = k as u32;
            let (d, rest) = (2 + k % 2, k / 2);
            let (smp, pix) = (n + 3 + rest % (n + 2), 5 + rest / (n + 2));
            let w = whole[((pix * 3 * n + smp) * 4 + d) as usize];
            assert_eq!(*u, w, "{:?}: pixel {pix} sample {smp} dim {d}", s.kind);
        }
        // Later passes are new patterns, not repeats.
        let first = p.eval(0..1, 0..n, 0..1, true);
        let second = p.eval(0..1, n..2 * n, 0..1, true);
        assert_ne!(first, second, "{:?}: pass 1 repeats pass 0", s.kind);
    }
}

/// Worst two-sided p-value (Bonferroni over 8 x 8 blocks and channels) that the mean of
/// `img - reference` over a block is zero, with a floor of 0.2% of the block's value
/// on the standard error: stratified samplers make the noise so small that the
/// difference between the renderers in smooth, directly seen regions, about 6e-5 of
/// the value whatever the sampler (it is there at 1024 spp with `independent` too:
/// float rounding of films and environment lookups), would otherwise fail the test.
/// A 5% bias still stands out (checked below).
fn block_agreement(
    img: &wavetrace::image::Image,
    reference: &wavetrace::image::Image,
) -> (f64, String) {
    use wavetrace::image::metrics::student_t_two_sided_p;
    let (w, h) = (img.width as usize, img.height as usize);
    let (mut worst, mut at) = (1.0f64, String::new());
    let tests = (w / 8) * (h / 8) * 3;
    for by in 0..h / 8 {
        for bx in 0..w / 8 {
            for c in 0..3 {
                let (mut d, mut r) = (Vec::with_capacity(64), 0.0);
                for y in by * 8..by * 8 + 8 {
                    for x in bx * 8..bx * 8 + 8 {
                        let k = 3 * (y * w + x) + c;
                        d.push((img.rgb[k] - reference.rgb[k]) as f64);
                        r += reference.rgb[k] as f64 / 64.0;
                    }
                }
                let m = d.iter().sum::<f64>() / 64.0;
                let var = d.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / 63.0;
                let floor = 2e-3 * r.abs();
                let t = m / (var / 64.0 + floor * floor).sqrt().max(1e-30);
                let p = (student_t_two_sided_p(t, 63.0) * tests as f64).min(1.0);
                if p < worst {
                    (worst, at) = (
                        p,
                        format!(
                            "block ({bx}, {by}) channel {c}: mean difference {m:.3e}, t = {t:.2}"
                        ),
                    );
                }
            }
        }
    }
    (worst, at)
}

/// The environment-map scene (path tracing, 64 x 64) with every sampler against
/// Mitsuba's 4096-spp reference (made with `independent`): a sampler changes the noise,
/// never the expectation. 16 samples (orthogonal: 25) keep this a few seconds; the
/// family-wise level is 1% per image.
#[test]
fn images_with_every_sampler_match_mitsuba() {
    use wavetrace::image::Image;
    use wavetrace::render::{RenderOptions, Renderer};
    let device = common::device();
    let scene = common::load(&common::repo("scenes/envmap/envmap.xml"));
    let reference = Image::read_exr(common::repo("scenes/refs/envmap.exr")).unwrap();
    for name in SamplerKind::NAMES {
        let options = RenderOptions {
            sampler: Some(name.to_string()),
            ..Default::default()
        };
        let mut r = Renderer::new(&device, &scene, &options).unwrap();
        let (img, stats) = r.render(16, &mut |_, _| {}).unwrap();
        assert_eq!(stats.discarded, 0, "{name}: NaN or infinite samples");
        let (p, at) = block_agreement(&img, &reference);
        println!("envmap, {name}: worst Bonferroni p {p:.3e} at {at}");
        assert!(
            p > 0.01,
            "{name} disagrees with Mitsuba: p = {p:.3e} at {at}"
        );
        let mut biased = img.clone();
        biased.rgb.iter_mut().for_each(|v| *v *= 0.95);
        let (p, at) = block_agreement(&biased, &reference);
        assert!(
            p < 0.01,
            "{name}: the test cannot see a 5% bias (p = {p:.3e} at {at})"
        );
    }
}

/// A split render equals the whole with a stratified sampler too: samples 0..16 of a
/// 16-sample multijittered pattern, rendered as 0..5 and 5..16, average to the same
/// image (float rounding aside).
#[test]
fn split_renders_equal_the_whole_with_multijitter() {
    use wavetrace::render::{RenderOptions, Renderer};
    let device = common::device();
    let mut scene = common::load(&common::repo("scenes/envmap/envmap.xml"));
    scene.camera.width = 24;
    scene.camera.height = 16;
    let options = RenderOptions {
        sampler: Some("multijitter".into()),
        max_batch_paths: Some(1000),
        ..Default::default()
    };
    let mut r = Renderer::new(&device, &scene, &options).unwrap();
    let whole = r.render(16, &mut |_, _| {}).unwrap().0;
    let a = r.render_range(0, 5, &mut |_, _| {}).unwrap().0;
    let b = r.render_range(5, 11, &mut |_, _| {}).unwrap().0;
    for i in 0..whole.rgb.len() {
        let combined = (5.0 * a.rgb[i] + 11.0 * b.rgb[i]) / 16.0;
        assert!(
            (combined - whole.rgb[i]).abs() <= 1e-5 * (1.0 + whole.rgb[i].abs()),
            "pixel value {i}: {combined} vs {}",
            whole.rgb[i]
        );
    }
}
