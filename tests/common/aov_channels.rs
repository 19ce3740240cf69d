//! AOV channels against Mitsuba's at pixel centres (tests/aov.rs, tests/batch_sensor.rs):
//! at 1 spp of the unjittered stratified sampler every camera ray goes through its
//! pixel's centre in both renderers (wavetrace's within 1/65536 of a pixel: its film
//! positions are kept in 1/32768 cells), so the AOVs agree up to float rounding.

use std::path::Path;

use wavetrace::image::exr;

/// The channel `name` of `channels`.
pub fn channel<'a>(channels: &'a [exr::Channel], name: &str) -> &'a [f32] {
    &channels
        .iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no channel {name}"))
        .values
}

/// Reads our EXR and Mitsuba's, asserts the same channel names and that every channel
/// but the radiance (`R`, `G`, `B` and the nested integrator's, `radiance.*`) agrees
/// within 1e-4 of the scene's scale (the centre offset moves a point by ~2e-5 units
/// and tilts a sphere's normal by as much); returns our channels.
pub fn assert_match_mitsuba(ours: &Path, reference: &Path, radiance: &str) -> Vec<exr::Channel> {
    let (w, h, ours) = exr::read_channels(ours).expect("ours");
    let (rw, rh, theirs) = exr::read_channels(reference).expect("reference");
    assert_eq!((w, h), (rw, rh));
    let mut names: Vec<&str> = ours.iter().map(|c| c.name.as_str()).collect();
    let mut ref_names: Vec<&str> = theirs.iter().map(|c| c.name.as_str()).collect();
    names.sort();
    ref_names.sort();
    assert_eq!(names, ref_names, "channel names as Mitsuba's");
    for c in &theirs {
        if ["R", "G", "B"].contains(&c.name.as_str()) || c.name.starts_with(&format!("{radiance}."))
        {
            continue; // radiance: noise at 1 spp
        }
        let a = channel(&ours, &c.name);
        for (i, (x, y)) in a.iter().zip(&c.values).enumerate() {
            assert!(
                (x - y).abs() <= 1e-4 * (1.0 + y.abs()),
                "{} pixel {i} ({}, {}): {x} against Mitsuba's {y}",
                c.name,
                i % w as usize,
                i / w as usize
            );
        }
    }
    ours
}
