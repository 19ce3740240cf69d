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
}
