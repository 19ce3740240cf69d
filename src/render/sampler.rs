//! The scene's sampler as the kernels see it: its kind as a specialization constant of
//! `generate` and `shade` (the other kinds' code compiles away) and its parameters in
//! the [`Frame`] (shaders/sampler/sampler.glsl reads them).

use crate::gpu::layout::{
    Frame, SAMPLER_INDEPENDENT, SAMPLER_JITTER, SAMPLER_LDSAMPLER, SAMPLER_MULTIJITTER,
    SAMPLER_ORTHOGONAL, SAMPLER_ORTHOGONAL_BUSH, SAMPLER_SCRAMBLE_FAST_OWEN, SAMPLER_SCRAMBLE_NONE,
    SAMPLER_SCRAMBLE_OWEN, SAMPLER_SCRAMBLE_SHIFT, SAMPLER_SCRAMBLE_XOR, SAMPLER_STRATIFIED,
    SAMPLER_STRENGTH_SHIFT, SAMPLER_ZSOBOL,
};
use crate::scene::sampler::{Randomization, SampleCount, Sampler, SamplerKind};

/// The `SAMPLER_*` id of a sampler: its type, and for `orthogonal` the construction
/// its strength takes (a kind of its own, so that the kernels compile only one).
pub fn kind_id(sampler: &Sampler) -> u32 {
    match sampler.kind {
        SamplerKind::Independent => SAMPLER_INDEPENDENT,
        SamplerKind::Stratified => SAMPLER_STRATIFIED,
        SamplerKind::Multijitter => SAMPLER_MULTIJITTER,
        SamplerKind::Orthogonal if sampler.strength == 2 => SAMPLER_ORTHOGONAL,
        SamplerKind::Orthogonal => SAMPLER_ORTHOGONAL_BUSH,
        SamplerKind::LdSampler => SAMPLER_LDSAMPLER,
        SamplerKind::ZSobol => SAMPLER_ZSOBOL,
    }
}

/// `Frame::sampler_flags` of a sampler.
pub fn flags(sampler: &Sampler) -> u32 {
    let scramble = match sampler.randomization {
        Randomization::None => SAMPLER_SCRAMBLE_NONE,
        Randomization::PermuteDigits => SAMPLER_SCRAMBLE_XOR,
        Randomization::FastOwen => SAMPLER_SCRAMBLE_FAST_OWEN,
        Randomization::Owen => SAMPLER_SCRAMBLE_OWEN,
    };
    (sampler.jitter as u32 * SAMPLER_JITTER)
        | (sampler.strength.min(255) << SAMPLER_STRENGTH_SHIFT)
        | (scramble << SAMPLER_SCRAMBLE_SHIFT)
}

/// Writes the sampler fields of `frame`: `sampler` drawing `count` samples a pass, with
/// the render's seed `seed` (added to the sampler's own, as Mitsuba does), over pixel
/// keys of a `key_size` grid ([`super::film::FilmGeometry::key_size`]).
pub fn set_frame(
    frame: &mut Frame,
    sampler: &Sampler,
    count: &SampleCount,
    seed: u32,
    key_size: (u32, u32),
) {
    frame.sampler_kind = kind_id(sampler);
    frame.sample_count = count.count;
    frame.sampler_res_x = count.res[0];
    frame.sampler_res_y = count.res[1];
    frame.sampler_flags = flags(sampler);
    frame.seed = seed.wrapping_add(sampler.seed);
    (frame.sampler_width, frame.sampler_height) = key_size;
    frame.emitter_strata = emitter_strata(sampler, count, frame.emitter_count);
}

/// Into how many strata one pass of `sampler` (`count`) divides the first coordinate of
/// a 2-D dimension, when the emitter choice should hand whole strata to each of
/// `emitters` emitters; 0 when it should not (independent sampler, one emitter, fewer
/// strata than emitters).
///
/// The emitter is chosen by the first coordinate of the emitter sample, which is then
/// reused. Choosing by the weights' cdf cuts strata at arbitrary places, so the number of
/// a pixel's samples that go to each emitter varies from pixel to pixel although the
/// sampler stratifies: on Veach's plates (four lights of nearly equal power, `direct`,
/// 64 spp) that made the MSE away from the lights 1.31x Mitsuba's with `stratified`
/// (whose uniform choice gives each light two of the eight columns) and 1.08x with
/// `multijitter`; with whole strata, 1.00x and 1.02x (30 seeds, standard error 0.04).
/// Each emitter gets one stratum plus its power's share of the rest, rounded
/// (shaders/emitter/emitter.glsl: emitter_choose).
pub fn emitter_strata(sampler: &Sampler, count: &SampleCount, emitters: u32) -> u32 {
    let strata = match sampler.kind {
        SamplerKind::Independent => 0,
        // A side x side grid: the first coordinate falls in one of `side` columns.
        SamplerKind::Stratified => count.res[0],
        // Multi-jittered (n-rooks), orthogonal-array (Latin hypercube) and (0, 2)-
        // sequence points stratify each coordinate into `count` intervals.
        _ => count.count,
    };
    if emitters > 1 && strata >= emitters {
        strata
    } else {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strata(kind: SamplerKind, spp: u32, emitters: u32) -> u32 {
        let s = Sampler::new(kind);
        emitter_strata(&s, &s.sample_count(spp, 16, 16).unwrap(), emitters)
    }

    #[test]
    fn emitter_strata_follow_the_first_coordinate_of_each_pattern() {
        // 64 stratified samples: an 8 x 8 grid, eight columns.
        assert_eq!(strata(SamplerKind::Stratified, 64, 4), 8);
        // Multi-jittered points are n-rooks: 64 intervals.
        assert_eq!(strata(SamplerKind::Multijitter, 64, 4), 64);
        assert_eq!(strata(SamplerKind::LdSampler, 64, 4), 64);
        assert_eq!(strata(SamplerKind::ZSobol, 64, 4), 64);
        // No strata to keep: the weights' cdf.
        assert_eq!(strata(SamplerKind::Independent, 64, 4), 0);
        assert_eq!(strata(SamplerKind::Stratified, 64, 1), 0);
        // Fewer strata than emitters could not give each one.
        assert_eq!(strata(SamplerKind::Stratified, 16, 5), 0);
        assert_eq!(strata(SamplerKind::Stratified, 16, 4), 4);
    }
}
