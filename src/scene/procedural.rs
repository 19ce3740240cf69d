//! Procedural density volumes, baked to a grid on the host: a cloud built from
//! Worley-noise fBm and a Perlin-noise fBm density. Both are wavetrace's own volume
//! types (Mitsuba 3 has none), used as a heterogeneous medium's `sigma_t`:
//!
//! ```xml
//! <medium type="heterogeneous">
//!     <volume type="cloud" name="sigma_t">
//!         <integer name="resolution" value="64"/>
//!         <float name="threshold" value="0.45"/>
//!         <transform name="to_world"><scale value="2"/><translate x="-1" y="-1" z="-1"/></transform>
//!     </volume>
//!     <float name="scale" value="8"/>
//! </medium>
//! ```
//!
//! `cloud` (Schneider and Vos 2015, "The Real-time Volumetric Cloudscapes of Horizon
//! Zero Dawn", SIGGRAPH course, in spirit): a base shape from inverted Worley noise
//! (1 - F1, the distance to the nearest feature point; Worley 1996, "A Cellular
//! Texture Basis Function") summed over octaves (fBm), kept where it exceeds
//! `threshold` and remapped to [0, 1], minus higher-frequency Worley detail
//! (`detail_strength` x its fBm), faded to 0 towards the bounds over a margin `fade`
//! (fraction of the unit cube), times `density`. Parameters: `resolution` (64),
//! `seed` (1), `frequency` (3, base cells per unit), `octaves` (3), `threshold`
//! (0.5), `detail_frequency` (12), `detail_strength` (0.3), `fade` (0.1), `density`
//! (1), `to_world` (the unit cube's placement).
//!
//! `perlin`: fBm of Perlin's improved noise (Perlin 2002), `density` x max(0, fbm +
//! `offset`). Parameters: `resolution` (64), `seed` (1), `frequency` (4), `octaves`
//! (4), `lacunarity` (2), `gain` (0.5), `offset` (0), `fade` (0), `density` (1),
//! `to_world`.
//!
//! Each noise field is normalized to [0, 1] over the grid before use, so thresholds
//! mean the same whatever the noise library's output range.

use glam::Vec3;
use noise::{core::worley::ReturnType, Fbm, MultiFractal, NoiseFn, Perlin, Worley};

use super::medium::Grid;
use super::properties::Properties;
use super::Error;

/// Largest `resolution` accepted (256³ floats = 64 MiB). Fuzz builds
/// (`tools/fuzz.sh`) lower it to 32: baking costs resolution³, and a fuzzer should
/// explore scenes rather than bake large grids.
const MAX_RESOLUTION: i64 = if cfg!(fuzzing) { 32 } else { 256 };

/// Reads the parameters of a `cloud` or `perlin` volume and bakes its grid.
pub fn bake(kind: &str, props: &Properties) -> Result<Grid, Error> {
    let res = props.integer("resolution", 64)?;
    if !(2..=MAX_RESOLUTION).contains(&res) {
        return Err(props.error(
            "resolution",
            format!("resolution must be in [2, {MAX_RESOLUTION}], found {res}"),
        ));
    }
    let seed = props.integer("seed", 1)?;
    let seed = u32::try_from(seed)
        .map_err(|_| props.error("seed", format!("seed must be in [0, 2^32), found {seed}")))?;
    let positive = |key: &str, default: f32| -> Result<f32, Error> {
        let v = props.float(key, default)?;
        if !(v.is_finite() && v > 0.0) {
            return Err(props.error(key, format!("{key} must be positive, found {v}")));
        }
        Ok(v)
    };
    let unit = |key: &str, default: f32| -> Result<f32, Error> {
        let v = props.float(key, default)?;
        if !(0.0..=1.0).contains(&v) {
            return Err(props.error(key, format!("{key} must be in [0, 1], found {v}")));
        }
        Ok(v)
    };
    let octaves = |default: i64| -> Result<usize, Error> {
        let o = props.integer("octaves", default)?;
        if !(1..=8).contains(&o) {
            return Err(props.error("octaves", format!("octaves must be in [1, 8], found {o}")));
        }
        Ok(o as usize)
    };
    let n = res as usize;
    let data = match kind {
        "cloud" => {
            let p = CloudParams {
                seed,
                frequency: positive("frequency", 3.0)?,
                octaves: octaves(3)?,
                threshold: props.float("threshold", 0.5)?,
                detail_frequency: positive("detail_frequency", 12.0)?,
                detail_strength: props.float("detail_strength", 0.3)?,
                fade: unit("fade", 0.1)?,
                density: positive("density", 1.0)?,
            };
            if !(0.0..1.0).contains(&p.threshold) {
                return Err(props.error("threshold", "threshold must be in [0, 1)"));
            }
            if !(p.detail_strength.is_finite() && p.detail_strength >= 0.0) {
                return Err(props.error("detail_strength", "detail_strength must be >= 0"));
            }
            cloud(n, &p)
        }
        _ => {
            let frequency = positive("frequency", 4.0)? as f64;
            let fbm = Fbm::<Perlin>::new(seed)
                .set_octaves(octaves(4)?)
                .set_frequency(frequency)
                .set_lacunarity(positive("lacunarity", 2.0)? as f64)
                .set_persistence(positive("gain", 0.5)? as f64);
            let offset = props.float("offset", 0.0)?;
            let fade = unit("fade", 0.0)?;
            let density = positive("density", 1.0)?;
            let field = normalized(sample(n, |p| fbm.get(p)));
            field
                .iter()
                .enumerate()
                .map(|(i, &v)| density * (v + offset).max(0.0) * fade_at(n, i, fade))
                .collect()
        }
    };
    Ok(Grid {
        res: [res as u32; 3],
        channels: 1,
        data,
        to_world: props.transform("to_world")?,
    })
}

struct CloudParams {
    seed: u32,
    frequency: f32,
    octaves: usize,
    threshold: f32,
    detail_frequency: f32,
    detail_strength: f32,
    fade: f32,
    density: f32,
}

/// fBm of inverted Worley F1 noise at base frequency `f`: sum over octaves of
/// 0.5^k (1 - F1(2^k f p)).
fn worley_fbm(n: usize, seed: u32, f: f64, octaves: usize) -> Vec<f32> {
    let layers: Vec<Worley> = (0..octaves)
        .map(|k| {
            Worley::new(seed.wrapping_add(k as u32))
                .set_return_type(ReturnType::Distance)
                .set_frequency(f * (1u32 << k) as f64)
        })
        .collect();
    sample(n, |p| {
        layers
            .iter()
            .enumerate()
            .map(|(k, w)| -0.5f64.powi(k as i32) * w.get(p))
            .sum()
    })
}

fn cloud(n: usize, p: &CloudParams) -> Vec<f32> {
    let base = normalized(worley_fbm(n, p.seed, p.frequency as f64, p.octaves));
    let detail = normalized(worley_fbm(
        n,
        p.seed.wrapping_add(1000),
        p.detail_frequency as f64,
        2,
    ));
    base.iter()
        .zip(&detail)
        .enumerate()
        .map(|(i, (&b, &d))| {
            let shape = ((b - p.threshold) / (1.0 - p.threshold)).max(0.0);
            let v = (shape - p.detail_strength * d).max(0.0);
            p.density * v * fade_at(n, i, p.fade)
        })
        .collect()
}

/// `f` at every voxel centre of an n³ grid on the unit cube (x fastest).
fn sample(n: usize, f: impl Fn([f64; 3]) -> f64) -> Vec<f32> {
    let mut out = Vec::with_capacity(n * n * n);
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let c = |i: usize| (i as f64 + 0.5) / n as f64;
                out.push(f([c(x), c(y), c(z)]) as f32);
            }
        }
    }
    out
}

/// Remaps values linearly onto [0, 1] (a constant field becomes 0).
fn normalized(v: Vec<f32>) -> Vec<f32> {
    let (lo, hi) = v
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    let span = hi - lo;
    if !(span > 0.0 && span.is_finite()) {
        return vec![0.0; v.len()];
    }
    v.into_iter().map(|x| (x - lo) / span).collect()
}

/// Smooth fade from 0 at the cube's faces to 1 at distance `margin` inside.
fn fade_at(n: usize, i: usize, margin: f32) -> f32 {
    if margin <= 0.0 {
        return 1.0;
    }
    let (x, y, z) = (i % n, (i / n) % n, i / (n * n));
    let c = |k: usize| (k as f32 + 0.5) / n as f32;
    let d = Vec3::new(c(x), c(y), c(z));
    let edge = d.min(Vec3::ONE - d).min_element();
    let t = (edge / margin).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use crate::scene::medium::MediumKind;
    use crate::scene::testutil::{error_at, load, mitsuba};

    fn grid_of(body: &str) -> crate::scene::medium::Grid {
        let s = load(&[("s.xml", &mitsuba(body))], &[]).unwrap();
        match &s.media[0].kind {
            MediumKind::Grid { grid, .. } => grid.clone(),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn clouds_are_deterministic_sparse_and_fade_at_the_bounds() {
        let body = r#"<medium type="heterogeneous"><volume type="cloud" name="sigma_t">
            <integer name="resolution" value="24"/><float name="fade" value="0.2"/></volume></medium>"#;
        let a = grid_of(body);
        let b = grid_of(body);
        assert_eq!(a, b, "same parameters, same grid");
        assert_eq!((a.res, a.channels), ([24; 3], 1));
        let n = 24usize;
        let empty = a.data.iter().filter(|&&v| v == 0.0).count() as f64 / a.data.len() as f64;
        let max = a.data.iter().fold(0.0f32, |m, &v| m.max(v));
        assert!(empty > 0.2 && empty < 0.98, "empty fraction {empty}");
        assert!(max > 0.1 && max <= 1.0, "max {max}");
        // The outermost voxels are faded to (almost) nothing.
        for z in 0..n {
            for y in 0..n {
                assert!(a.data[(z * n + y) * n] < 0.05);
            }
        }
        let other = grid_of(&body.replace(
            "<float name=\"fade\"",
            "<integer name=\"seed\" value=\"7\"/><float name=\"fade\"",
        ));
        assert_ne!(other.data, a.data, "another seed, another cloud");
    }

    #[test]
    fn perlin_density_and_errors() {
        let g = grid_of(
            r#"<medium type="heterogeneous"><volume type="perlin" name="sigma_t">
            <integer name="resolution" value="16"/><float name="offset" value="-0.5"/>
            <float name="density" value="3"/></volume></medium>"#,
        );
        assert!(g.data.iter().all(|v| (0.0..=1.5 + 1e-5).contains(v)));
        assert!(g.data.contains(&0.0) && g.data.iter().any(|&v| v > 0.5));
        let text = error_at(
            load(
                &[(
                    "s.xml",
                    &mitsuba(
                        r#"<medium type="heterogeneous"><volume type="cloud" name="sigma_t"><integer name="resolution" value="100000"/></volume></medium>"#,
                    ),
                )],
                &[],
            ),
            "s.xml",
            3,
        );
        assert!(text.contains("resolution must be in [2, 256]"), "{text}");
    }
}
