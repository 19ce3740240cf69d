//! Alias tables: O(1) sampling of a discrete distribution on the GPU (Walker 1977,
//! "An Efficient Method for Generating Discrete Random Variables with General
//! Distributions"; built with Vose 1991's numerically stable method).

use crate::gpu::layout::AliasEntry;

/// Builds the table of `weights` (non-negative; all zero or empty gives a uniform
/// table). `prims[i]` goes into entry i's `prim` field (`NONE` where not needed).
pub fn build(weights: &[f64], prims: &[u32]) -> Vec<AliasEntry> {
    let n = weights.len();
    if n == 0 {
        return Vec::new();
    }
    let total: f64 = weights.iter().filter(|w| w.is_finite() && **w > 0.0).sum();
    let pmf: Vec<f64> = if total > 0.0 {
        weights
            .iter()
            .map(|&w| {
                if w.is_finite() && w > 0.0 {
                    w / total
                } else {
                    0.0
                }
            })
            .collect()
    } else {
        vec![1.0 / n as f64; n]
    };
    // Scaled probabilities: entries below 1 take their remainder from one above 1.
    let mut scaled: Vec<f64> = pmf.iter().map(|p| p * n as f64).collect();
    let mut table: Vec<AliasEntry> = (0..n)
        .map(|i| AliasEntry {
            prob: 1.0,
            alias: i as u32,
            pmf: pmf[i] as f32,
            prim: prims.get(i).copied().unwrap_or(u32::MAX),
        })
        .collect();
    let (mut small, mut large): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| scaled[i] < 1.0);
    while let (Some(s), Some(&l)) = (small.pop(), large.last()) {
        table[s].prob = scaled[s] as f32;
        table[s].alias = l as u32;
        scaled[l] -= 1.0 - scaled[s];
        if scaled[l] < 1.0 {
            large.pop();
            small.push(l);
        }
    }
    // What remains is 1 up to rounding.
    for i in small.into_iter().chain(large) {
        table[i].prob = 1.0;
    }
    table
}

/// Stores in each entry's `prim` the cumulative pmf of the entries before it (f32
/// bits), for sampling by inversion (`alias_sample_cdf` in shaders/sampling/alias.glsl):
/// the emitter table, whose `prim` is otherwise unused.
pub fn set_cdf(table: &mut [AliasEntry]) {
    let mut sum = 0.0f64;
    for e in table.iter_mut() {
        e.prim = (sum as f32).to_bits();
        sum += e.pmf as f64;
    }
}

/// The entry an alias table picks for a uniform `u` in [0, 1), as `alias_sample` in
/// shaders/sampling/alias.glsl does.
pub fn sample(table: &[AliasEntry], u: f32) -> usize {
    let n = table.len();
    let x = u * n as f32;
    let i = (x as usize).min(n - 1);
    let frac = x - i as f32;
    if frac < table[i].prob {
        i
    } else {
        table[i].alias as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sampling_frequencies_follow_the_weights() {
        let w = [1.0, 0.0, 3.0, 6.0, 0.5, 0.0, 2.5];
        let total: f64 = w.iter().sum();
        let table = build(&w, &[]);
        let n = 200_000;
        let mut counts = vec![0usize; w.len()];
        for k in 0..n {
            counts[sample(&table, (k as f32 + 0.5) / n as f32)] += 1;
        }
        for i in 0..w.len() {
            let expected = w[i] / total;
            assert!((table[i].pmf as f64 - expected).abs() < 1e-6);
            // A stratified sweep of u: frequencies are exact up to the table's float
            // rounding.
            assert!(
                (counts[i] as f64 / n as f64 - expected).abs() < 1e-3,
                "entry {i}: {counts:?}"
            );
        }
    }

    #[test]
    fn zero_and_empty_weights_are_uniform_or_empty() {
        assert!(build(&[], &[]).is_empty());
        let t = build(&[0.0, 0.0], &[]);
        assert_eq!(t[0].pmf, 0.5);
        let t = build(&[f64::NAN, 1.0], &[7, 8]);
        assert_eq!((t[0].pmf, t[1].pmf, t[1].prim), (0.0, 1.0, 8));
        assert_eq!(sample(&t, 0.2), 1);
    }
}
