//! Participating media, as the scene describes them.
//!
//! Mitsuba 3's `homogeneous` and `heterogeneous` media, bound to shapes through
//! `interior`/`exterior` and to the sensor (a camera inside fog):
//!
//! - `homogeneous`: `sigma_t` (color, default 1) and `albedo` (color in [0, 1], default
//!   0.75, or a `gridvolume`: constant extinction, albedo varying in space), or
//!   instead `sigma_a` and `sigma_s` (sigma_t = sigma_a + sigma_s, albedo = sigma_s /
//!   sigma_t); `scale` (default 1) multiplies the extinction; `sample_emitters`
//!   (default true): next-event estimation at scattering points (false: as Mitsuba's
//!   volpath, none there, and emitters that the phase-sampled ray finds count in full).
//! - `heterogeneous`: `sigma_t` a nested `<volume type="gridvolume">` (a Mitsuba `.vol`
//!   file, 1 or 3 float32 channels; `to_world` places its unit cube, or its own bounding
//!   box with `use_grid_bbox`; trilinear interpolation between voxel centres, as
//!   Mitsuba 3's `gridvolume`; or an OpenVDB `.vdb` file, whose scalar grid `grid`
//!   (default: the first named `density`, else the first scalar grid) is placed by
//!   the file's own transform and then `to_world`, see `scene::vdb`) or a constant; `albedo` a constant color, or a
//!   `gridvolume` of any resolution and `to_world` (looked up in its own grid, as in
//!   Mitsuba); `scale`;
//!   a constant `sigma_t` (value or `constvolume`) fills only the unit cube under the
//!   constvolume's `to_world` ([0, 1]³ by default), as in Mitsuba, where a
//!   heterogeneous medium ends at its sigma_t volume's bounding box;
//!   `majorant_resolution_factor` (wavetrace default 8: a coarse grid of maxima, one
//!   cell per 8³ voxels, lets delta tracking take long steps through thin regions; 0:
//!   one majorant for the whole grid, as Mitsuba's default). Procedural `cloud` and
//!   `perlin` volumes are baked to a grid at load (`scene::procedural`).
//! - A nested `<phase type="isotropic"/>` (default) or `<phase type="hg">` (`g` in
//!   (-1, 1), Mitsuba's default 0.8).
//!
//! ```xml
//! <shape type="cube">
//!     <bsdf type="null"/>
//!     <medium type="homogeneous" name="interior">
//!         <rgb name="sigma_t" value="1"/><rgb name="albedo" value="0.9"/>
//!         <phase type="hg"><float name="g" value="0.7"/></phase>
//!     </medium>
//! </shape>
//! ```

use std::path::Path;

use glam::{Mat4, Vec3};

pub mod heterogeneous;
pub mod homogeneous;
pub mod phase;
pub mod record;
pub mod volume;

use super::plugin::{self, Family, Param, PluginDoc};
use super::properties::Properties;
use super::xml::{Dialect, Element};
use super::Error;
use volume::Volume;

/// Every medium, phase function and volume type: the supported ones with the
/// parameters they read, then Mitsuba 3's not supported yet.
pub const REGISTRY: &[PluginDoc] = &[
    homogeneous::MITSUBA,
    heterogeneous::MITSUBA,
    phase::ISOTROPIC,
    phase::HG,
    phase::not_yet("rayleigh"),
    phase::not_yet("sggx"),
    phase::not_yet("tabphase"),
    phase::not_yet("blendphase"),
    volume::CONSTVOLUME,
    volume::GRIDVOLUME,
    volume::CLOUD,
    volume::PERLIN,
    homogeneous::NORI,
    heterogeneous::NORI,
];

/// The parameters every medium reads besides its extinction.
const ALBEDO: Param = Param::new(
    "albedo",
    "rgb|volume",
    "0.75",
    "single-scattering albedo, in [0, 1]: a color or a volume (a gridvolume of any resolution and placement)",
);
const SIGMA_A: Param = Param::new(
    "sigma_a",
    "rgb",
    "",
    "absorption (with sigma_s, instead of sigma_t and albedo)",
);
const SIGMA_S: Param = Param::new("sigma_s", "rgb", "", "scattering (with sigma_a)");
const SCALE: Param = Param::new("scale", "float", "1", "factor on the extinction");
const SAMPLE_EMITTERS: Param = Param::new(
    "sample_emitters",
    "boolean",
    "true",
    "next-event estimation at scattering points",
);
/// Mitsuba's hint that the extinction varies by channel (its volpath then weighs each
/// free flight by the ratio of the channels' transmittances to the sampled one's;
/// with `false` it skips that ratio, exact for a gray extinction). wavetrace always
/// weighs, so the hint changes no image where it is true to the medium.
const HAS_SPECTRAL_EXTINCTION: Param = Param::new(
    "has_spectral_extinction",
    "boolean",
    "true",
    "Mitsuba's hint that sigma_t varies by channel (accepted; images are the same for a gray sigma_t)",
);
/// Nori's box a medium fills.
const BOUNDS_MIN: Param = Param::new(
    "bounds_min",
    "point",
    "",
    "the box's low corner (Nori; required)",
);
const BOUNDS_MAX: Param = Param::new(
    "bounds_max",
    "point",
    "",
    "the box's high corner (Nori; required)",
);

/// A medium.
#[derive(Debug, Clone, PartialEq)]
pub struct Medium {
    /// For messages: the id, or the type.
    pub name: String,
    pub kind: MediumKind,
    /// Single-scattering albedo sigma_s / sigma_t, each channel in [0, 1].
    pub albedo: Vec3,
    /// A grid of albedos (1 or 3 channels, values in [0, 1]) replacing `albedo`, with
    /// its own resolution and `to_world` (any medium kind; clamped outside its box).
    pub albedo_grid: Option<Grid>,
    /// Henyey-Greenstein asymmetry, 0 for the isotropic phase function.
    pub g: f32,
    pub sample_emitters: bool,
}

#[derive(Debug, Clone, PartialEq)]
pub enum MediumKind {
    /// Constant extinction per unit length (scale applied).
    Homogeneous { sigma_t: Vec3 },
    /// Extinction = scale x the grid's density.
    Grid {
        grid: Grid,
        scale: Vec3,
        /// Voxels per majorant cell along each axis; 0 for a single majorant.
        majorant_factor: u32,
    },
}

/// A voxel grid on the unit cube that `to_world` places in the scene. Values at voxel
/// centres; voxel (x, y, z) channel c is `data[((z * res[1] + y) * res[0] + x) *
/// channels + c]` (Mitsuba's `.vol` order).
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    pub res: [u32; 3],
    pub channels: u32,
    pub data: Vec<f32>,
    pub to_world: Mat4,
}

impl Grid {
    /// Largest value of channel `c`.
    pub fn max(&self, c: u32) -> f32 {
        self.data
            .iter()
            .skip(c as usize)
            .step_by(self.channels as usize)
            .fold(0.0f32, |m, &v| m.max(v))
    }
}

/// The most values a grid may hold: one 128 MiB GPU buffer of f32s (lavapipe's
/// largest storage-buffer binding).
pub const MAX_GRID_VALUES: u64 = 1 << 25;

/// Reads a Mitsuba `.vol` grid (version 3: "VOL", 3, int32 encoding (1 = float32),
/// int32 xres, yres, zres, channels, 6 float32 bounding box, float32 data). Returns the
/// grid with `to_world` mapping the unit cube onto the file's bounding box.
pub fn read_vol(path: &Path) -> Result<Grid, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let bad = |what: &str| format!("{}: not a Mitsuba .vol grid: {what}", path.display());
    if bytes.len() < 3 || &bytes[0..3] != b"VOL" {
        return Err(bad("missing the 'VOL' header"));
    }
    if bytes.len() < 48 {
        return Err(bad(&format!(
            "truncated: {} bytes, shorter than the 48-byte header",
            bytes.len()
        )));
    }
    if bytes[3] != 3 {
        return Err(bad(&format!(
            "version {} (only version 3 is read)",
            bytes[3]
        )));
    }
    let int = |i: usize| i32::from_le_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    let float = |i: usize| f32::from_le_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    let encoding = int(4);
    if encoding != 1 {
        return Err(bad(&format!(
            "encoding {encoding} (only 1 = float32 is supported, as in Mitsuba 3)"
        )));
    }
    let (xr, yr, zr, ch) = (int(8), int(12), int(16), int(20));
    if xr <= 0 || yr <= 0 || zr <= 0 || !(ch == 1 || ch == 3) {
        return Err(bad(&format!(
            "resolution {xr} x {yr} x {zr} with {ch} channels (need positive sizes and 1 or 3 channels)"
        )));
    }
    // Four sizes up to 2^31 each: the product can pass 2^64.
    let count = [yr, zr, ch]
        .iter()
        .try_fold(xr as u64, |n, &k| n.checked_mul(k as u64))
        .filter(|&n| n <= MAX_GRID_VALUES)
        .ok_or_else(|| {
            bad(&format!(
                "{xr} x {yr} x {zr} x {ch} values is more than wavetrace accepts ({MAX_GRID_VALUES}: one 128 MiB GPU buffer)"
            ))
        })?;
    let need = 48 + 4 * count as usize;
    if bytes.len() < need {
        return Err(bad(&format!(
            "{} bytes, but {xr} x {yr} x {zr} x {ch} float32 values need {need}",
            bytes.len()
        )));
    }
    let lo = Vec3::new(float(24), float(28), float(32));
    let hi = Vec3::new(float(36), float(40), float(44));
    let mut data = Vec::with_capacity(count as usize);
    for i in 0..count as usize {
        let v = float(48 + 4 * i);
        if !v.is_finite() || v < 0.0 {
            return Err(bad(&format!(
                "value {v} at index {i} (need finite values >= 0)"
            )));
        }
        data.push(v);
    }
    let ext = hi - lo;
    let to_world = if lo.is_finite() && hi.is_finite() && ext.min_element() > 0.0 {
        Mat4::from_translation(lo) * Mat4::from_scale(ext)
    } else {
        Mat4::IDENTITY
    };
    Ok(Grid {
        res: [xr as u32, yr as u32, zr as u32],
        channels: ch as u32,
        data,
        to_world,
    })
}

fn check_color(props: &Properties, key: &str, c: Vec3, max: Option<f32>) -> Result<Vec3, Error> {
    let ok = c.is_finite() && c.min_element() >= 0.0 && max.is_none_or(|m| c.max_element() <= m);
    if !ok {
        let range = match max {
            Some(m) => format!("in [0, {m}]"),
            None => "finite and >= 0".into(),
        };
        return Err(props.error(key, format!("{key} must be {range}, found {c}")));
    }
    Ok(c)
}

impl Medium {
    /// A Mitsuba `<medium>` element.
    pub fn from_mitsuba(el: &Element) -> Result<Medium, Error> {
        Ok(Medium::read(el, Dialect::Mitsuba, |_| Ok(()))?.0)
    }

    /// A `<medium>` element of either dialect; `extra` reads the parameters a dialect
    /// adds (Nori's bounds) before unknown ones are refused.
    pub fn read<T>(
        el: &Element,
        dialect: Dialect,
        extra: impl FnOnce(&Properties) -> Result<T, Error>,
    ) -> Result<(Medium, T), Error> {
        el.check_attrs(&["type", "id", "name"])?;
        let t = el.require("type")?;
        if plugin::find(REGISTRY, Family::Medium, dialect, t).is_none() {
            return Err(plugin::unsupported(el, Family::Medium, dialect, REGISTRY));
        }
        let (props, nested) = Properties::read(el, dialect, false)?;
        let (g, volumes) = nested_objects(&props, nested)?;
        let mut c = Coefficients::from_volumes(&props, volumes)?;
        c.check_albedo_grid()?;
        c.read_sigma_a_and_s(&props)?;
        let albedo = check_color(
            &props,
            "albedo",
            c.albedo.unwrap_or(Vec3::splat(0.75)),
            Some(1.0),
        )?;
        let scale = props.float("scale", 1.0)?;
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(props.error(
                "scale",
                format!("scale must be finite and >= 0, found {scale}"),
            ));
        }
        let sample_emitters = props.boolean("sample_emitters", true)?;
        if dialect == Dialect::Mitsuba {
            props.boolean("has_spectral_extinction", true)?;
        }
        let kind = if t == "homogeneous" {
            homogeneous::kind(&props, c.sigma_t, c.grid.is_some(), scale)?
        } else {
            heterogeneous::kind(&props, dialect, c.sigma_t, c.grid, c.const_to_world, scale)?
        };
        let more = extra(&props)?;
        props.finish()?;
        let medium = Medium {
            name: el.attr("id").unwrap_or(t).to_string(),
            kind,
            albedo,
            albedo_grid: c.albedo_grid.map(|(a, _)| a),
            g: g.unwrap_or(0.0),
            sample_emitters,
        };
        Ok((medium, more))
    }
}

/// A medium's nested `<phase>` (its asymmetry) and `<volume>`s (by parameter name).
type Nested<'a> = (Option<f32>, Vec<(&'a str, Volume, &'a Element)>);

fn nested_objects<'a>(props: &Properties, nested: Vec<&'a Element>) -> Result<Nested<'a>, Error> {
    let mut g = None;
    let mut volumes: Vec<(&str, Volume, &Element)> = Vec::new();
    for n in nested {
        match n.tag.as_str() {
            "phase" if g.is_none() => g = Some(phase::read(n)?),
            "phase" => return Err(n.err("a medium has one <phase>")),
            "volume" => {
                let name = n.require("name")?;
                if !matches!(name, "sigma_t" | "albedo") {
                    return Err(n.err(format!(
                        "a <volume> of a medium is its 'sigma_t' or 'albedo', not '{name}'"
                    )));
                }
                if props.has(name) || volumes.iter().any(|v| v.0 == name) {
                    return Err(n.err(format!("'{name}' of the medium is given twice")));
                }
                volumes.push((name, volume::read(n)?, n));
            }
            "ref" => return Err(n.err("references inside a <medium> are not supported yet")),
            tag => return Err(n.err(format!("unexpected <{tag}> in a <medium>"))),
        }
    }
    Ok((g, volumes))
}

/// A medium's coefficients as given, values or volumes, before its type reads them.
struct Coefficients<'a> {
    sigma_t: Option<Vec3>,
    albedo: Option<Vec3>,
    grid: Option<Grid>,
    albedo_grid: Option<(Grid, &'a Element)>,
    /// Where a constant sigma_t lives in a Mitsuba heterogeneous medium: the unit
    /// cube under the constvolume's to_world (identity for a plain value).
    const_to_world: Mat4,
}

impl<'a> Coefficients<'a> {
    fn from_volumes(
        props: &Properties,
        volumes: Vec<(&str, Volume, &'a Element)>,
    ) -> Result<Coefficients<'a>, Error> {
        let mut c = Coefficients {
            sigma_t: props.color_opt("sigma_t")?,
            albedo: props.color_opt("albedo")?,
            grid: None,
            albedo_grid: None,
            const_to_world: Mat4::IDENTITY,
        };
        for (name, v, n) in volumes {
            match (name, v) {
                ("sigma_t", Volume::Constant(col, m)) => {
                    c.sigma_t = Some(col);
                    c.const_to_world = m;
                }
                (_, Volume::Constant(col, _)) => c.albedo = Some(col),
                ("sigma_t", Volume::Grid(gr)) => c.grid = Some(gr),
                (_, Volume::Grid(gr)) => c.albedo_grid = Some((gr, n)),
            }
        }
        Ok(c)
    }

    /// An albedo grid's values lie in [0, 1]. Its resolution and placement are its own
    /// (Mitsuba looks each volume up in its own grid), in a homogeneous medium too.
    fn check_albedo_grid(&self) -> Result<(), Error> {
        if let Some((a, n)) = &self.albedo_grid {
            if a.data.iter().any(|&v| v > 1.0) {
                return Err(n.err("albedo grid values must lie in [0, 1]"));
            }
        }
        Ok(())
    }

    /// `sigma_a` and `sigma_s` instead of `sigma_t` and `albedo`.
    fn read_sigma_a_and_s(&mut self, props: &Properties) -> Result<(), Error> {
        let (sa, ss) = (props.color_opt("sigma_a")?, props.color_opt("sigma_s")?);
        if sa.is_some() || ss.is_some() {
            if self.sigma_t.is_some()
                || self.albedo.is_some()
                || self.grid.is_some()
                || self.albedo_grid.is_some()
            {
                return Err(props.object_error(
                    "give either sigma_a and sigma_s, or sigma_t and albedo, not both",
                ));
            }
            let sa = check_color(props, "sigma_a", sa.unwrap_or(Vec3::ZERO), None)?;
            let ss = check_color(props, "sigma_s", ss.unwrap_or(Vec3::ZERO), None)?;
            let st = sa + ss;
            self.sigma_t = Some(st);
            self.albedo = Some(Vec3::select(st.cmpgt(Vec3::ZERO), ss / st, Vec3::ZERO));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::testutil::{error_at, load, mitsuba};

    /// A .vol file's bytes.
    pub fn vol_bytes(res: [i32; 3], channels: i32, bbox: [f32; 6], data: &[f32]) -> Vec<u8> {
        let mut b = b"VOL\x03".to_vec();
        for i in [1, res[0], res[1], res[2], channels] {
            b.extend_from_slice(&i.to_le_bytes());
        }
        for f in bbox.iter().chain(data) {
            b.extend_from_slice(&f.to_le_bytes());
        }
        b
    }

    #[test]
    fn homogeneous_parameters() {
        let s = load(
            &[(
                "s.xml",
                &mitsuba(
                    r#"<medium type="homogeneous" id="fog">
    <rgb name="sigma_t" value="1, 2, 3"/><float name="albedo" value="0.5"/>
    <float name="scale" value="2"/><phase type="hg"><float name="g" value="-0.7"/></phase>
</medium>
<shape type="cube"><bsdf type="null"/><ref id="fog" name="interior"/></shape>"#,
                ),
            )],
            &[],
        )
        .unwrap();
        assert_eq!(s.media.len(), 1);
        let m = &s.media[0];
        assert_eq!(
            m.kind,
            MediumKind::Homogeneous {
                sigma_t: Vec3::new(2.0, 4.0, 6.0)
            }
        );
        assert_eq!((m.albedo, m.g), (Vec3::splat(0.5), -0.7));
        assert_eq!(
            (s.meshes[0].interior, s.meshes[0].exterior),
            (Some(0), None)
        );
        assert!(s.meshes[0].null_bsdf);

        let s = load(
            &[(
                "s.xml",
                &mitsuba(
                    r#"<shape type="sphere"><medium type="homogeneous" name="exterior">
    <rgb name="sigma_a" value="1"/><rgb name="sigma_s" value="3"/></medium></shape>"#,
                ),
            )],
            &[],
        )
        .unwrap();
        let m = &s.media[0];
        assert_eq!(
            m.kind,
            MediumKind::Homogeneous {
                sigma_t: Vec3::splat(4.0)
            }
        );
        assert_eq!((m.albedo, m.g), (Vec3::splat(0.75), 0.0));
        assert_eq!(
            (s.quadrics[0].interior, s.quadrics[0].exterior),
            (None, Some(0))
        );
        // Without a BSDF a medium's shape is diffuse, as in Mitsuba 3.9.
        assert!(!s.quadrics[0].null_bsdf);
    }

    #[test]
    fn constant_heterogeneous_medium_fills_its_volume_box() {
        // Mitsuba bounds a heterogeneous medium by its sigma_t volume's box: a plain
        // value fills [0, 1]³, a constvolume the unit cube under its to_world.
        let s = load(
            &[(
                "s.xml",
                &mitsuba(
                    r#"<medium type="heterogeneous" id="a"><rgb name="sigma_t" value="0.5, 0.4, 0.3"/><float name="scale" value="5"/></medium>
<medium type="heterogeneous" id="b"><volume type="constvolume" name="sigma_t"><rgb name="value" value="2"/>
    <transform name="to_world"><translate x="-0.5" y="-0.5" z="-0.5"/></transform></volume></medium>"#,
                ),
            )],
            &[],
        )
        .unwrap();
        let MediumKind::Grid { grid, scale, .. } = &s.media[0].kind else {
            panic!("{:?}", s.media[0].kind)
        };
        assert_eq!((grid.res, grid.channels), ([1, 1, 1], 3));
        assert_eq!(grid.data, vec![0.5, 0.4, 0.3]);
        assert_eq!((*scale, grid.to_world), (Vec3::splat(5.0), Mat4::IDENTITY));
        let MediumKind::Grid { grid, scale, .. } = &s.media[1].kind else {
            panic!("{:?}", s.media[1].kind)
        };
        assert_eq!((grid.data[0], *scale), (2.0, Vec3::ONE));
        assert_eq!(
            grid.to_world.transform_point3(Vec3::ZERO),
            Vec3::splat(-0.5)
        );
    }

    #[test]
    fn sensor_medium_and_errors() {
        let xml = r#"<scene version="3.0.0">
<medium type="homogeneous" id="fog"/>
<sensor type="perspective"><ref id="fog"/></sensor>
</scene>"#;
        let s = load(&[("s.xml", xml)], &[]).unwrap();
        assert_eq!(s.camera_medium, Some(0));
        let bad = |body: &str, line: u32, want: &str| {
            let text = error_at(load(&[("s.xml", &mitsuba(body))], &[]), "s.xml", line);
            assert!(text.contains(want), "{text}");
        };
        bad(
            "<medium type=\"homogeneous\"><float name=\"albedo\" value=\"1.5\"/></medium>",
            3,
            "albedo must be in [0, 1]",
        );
        bad(
            "<medium type=\"homogeneous\"><phase type=\"hg\"><float name=\"g\" value=\"1\"/></phase></medium>",
            3,
            "g must lie in (-1, 1)",
        );
        bad("<medium type=\"fancy\"/>", 3, "unknown medium type 'fancy'");
        bad(
            "<medium type=\"homogeneous\"><float name=\"sigma_t\" value=\"-1\"/></medium>",
            3,
            "sigma_t must be finite and >= 0",
        );
        bad(
            "<medium type=\"homogeneous\"><float name=\"density\" value=\"1\"/></medium>",
            3,
            "'density'",
        );
        bad(
            "<shape type=\"cube\"><medium type=\"homogeneous\" name=\"inside\"/></shape>",
            3,
            "interior",
        );
        bad(
            "<medium type=\"heterogeneous\"><volume name=\"sigma_t\" type=\"gridvolume\"><string name=\"filename\" value=\"missing.vol\"/></volume></medium>",
            3,
            "missing.vol",
        );
    }

    #[test]
    fn vol_files() {
        let data: Vec<f32> = (0..24).map(|i| i as f32).collect();
        let dir = crate::scene::testutil::temp_dir("vol");
        let p = dir.join("g.vol");
        std::fs::write(
            &p,
            vol_bytes([2, 3, 4], 1, [0.0, 0.0, 0.0, 2.0, 1.0, 1.0], &data),
        )
        .unwrap();
        let g = read_vol(&p).unwrap();
        assert_eq!((g.res, g.channels, g.max(0)), ([2, 3, 4], 1, 23.0));
        assert_eq!(
            g.to_world.transform_point3(Vec3::ONE),
            Vec3::new(2.0, 1.0, 1.0)
        );
        for (bytes, want) in [
            (b"VOX\x03".to_vec(), "VOL"),
            (vol_bytes([2, 3, 4], 1, [0.0; 6], &data[..10]), "need"),
            (vol_bytes([2, 3, 4], 2, [0.0; 6], &data), "channels"),
            (
                vol_bytes([2, 1, 1], 1, [0.0; 6], &[1.0, f32::NAN]),
                "finite",
            ),
        ] {
            std::fs::write(&p, bytes).unwrap();
            let e = read_vol(&p).unwrap_err();
            assert!(e.contains(want), "{e}");
        }
        // A scale that overflows the grid's extinction is refused.
        std::fs::write(&p, vol_bytes([2, 3, 4], 1, [0.0; 6], &data)).unwrap();
        let xml = mitsuba(
            r#"<medium type="heterogeneous"><volume type="gridvolume" name="sigma_t"><string name="filename" value="g.vol"/></volume><float name="scale" value="1e38"/></medium>"#,
        );
        std::fs::write(dir.join("s.xml"), xml).unwrap();
        let e = crate::scene::load(&dir.join("s.xml"), &[])
            .unwrap_err()
            .to_string();
        assert!(e.contains("overflows"), "{e}");
        // A wrong file never panics, at any truncation.
        let good = vol_bytes([2, 3, 4], 1, [0.0, 0.0, 0.0, 1.0, 1.0, 1.0], &data);
        for n in 0..good.len() {
            std::fs::write(&p, &good[..n]).unwrap();
            let e = read_vol(&p).unwrap_err();
            let want = match n {
                0..3 => "'VOL' header",
                3..48 => "truncated",
                _ => "need",
            };
            assert!(e.contains(want), "{n} bytes: {e}");
        }
    }

    /// An albedo grid keeps its own resolution and placement: in a homogeneous medium
    /// (Mitsuba's constant extinction, albedo varying in space) and beside a density
    /// grid of another resolution; its GPU header maps world points into its own unit
    /// cube (scenes/media/albedo_*.xml, rendered against Mitsuba by
    /// tests/media_vs_mitsuba.rs).
    #[test]
    fn albedo_grids_of_their_own() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/media");
        let s = crate::scene::load(&dir.join("albedo_homogeneous.xml"), &[]).unwrap();
        let m = &s.media[0];
        assert!(
            matches!(m.kind, MediumKind::Homogeneous { .. }),
            "{:?}",
            m.kind
        );
        assert!(m.sample_emitters);
        let a = m.albedo_grid.as_ref().expect("an albedo grid");
        assert_eq!((a.res, a.channels), ([7, 5, 3], 3));
        let (mut words, mut packed, mut maj) = (Vec::new(), Vec::new(), Vec::new());
        let rec = record::record(m, &mut words, &mut packed, &mut maj);
        assert_eq!((rec.albedo_data, rec.albedo), (0, [1.0; 3]));
        assert_eq!(words.len(), record::ALBEDO_GRID_HEADER + 7 * 5 * 3 * 3);

        let defines = [("sample_emitters".to_string(), "false".to_string())];
        let s = crate::scene::load(&dir.join("albedo_homogeneous.xml"), &defines).unwrap();
        assert!(!s.media[0].sample_emitters);

        let s = crate::scene::load(&dir.join("albedo_heterogeneous.xml"), &[]).unwrap();
        let m = &s.media[0];
        let MediumKind::Grid { grid, .. } = &m.kind else {
            panic!("{:?}", m.kind)
        };
        let a = m.albedo_grid.as_ref().expect("an albedo grid");
        assert_eq!((grid.res, a.res, a.channels), ([32, 32, 32], [9, 4, 6], 1));
        assert!(!grid.to_world.abs_diff_eq(a.to_world, 1e-3));
        let h = record::albedo_grid_header(a);
        let local = Vec3::new(0.2, 0.7, 0.4);
        let p = a.to_world.transform_point3(local);
        let back = Vec3::from_array(
            [0, 1, 2]
                .map(|r| h[4 * r] * p.x + h[4 * r + 1] * p.y + h[4 * r + 2] * p.z + h[4 * r + 3]),
        );
        assert!((back - local).length() < 1e-5, "{back} != {local}");
        let tail: Vec<u32> = h[12..].iter().map(|v| v.to_bits()).collect();
        assert_eq!(tail, [9, 4, 6, 1]);
    }

    /// A `.vdb` gridvolume in both dialects: the grid `grid` (default: density), placed
    /// by the file's transform and then `to_world`; clear errors, with the line, for a
    /// grid the file lacks (listing those it has), `grid` on a .vol file and
    /// `use_grid_bbox` false on a .vdb.
    #[test]
    fn vdb_gridvolumes() {
        let vdb = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/media/smoke_grids.vdb");
        let volume = |file: &Path, extra: &str| {
            format!(
                r#"<medium type="heterogeneous"><volume type="gridvolume" name="sigma_t"><string name="filename" value="{}"/>{extra}</volume></medium>"#,
                file.display()
            )
        };
        let grid_of = |s: &crate::scene::Scene| match &s.media[0].kind {
            MediumKind::Grid { grid, .. } => grid.clone(),
            k => panic!("not a grid: {k:?}"),
        };
        let direct = |name| crate::scene::vdb::read_vdb(&vdb, name).unwrap();
        let m = |body: String| load(&[("s.xml", &mitsuba(&body))], &[]);

        let s = m(volume(&vdb, "")).unwrap();
        assert_eq!(grid_of(&s), direct(None));
        let s = m(volume(
            &vdb,
            r#"<string name="grid" value="temperature"/><transform name="to_world"><translate x="5"/></transform><boolean name="use_grid_bbox" value="true"/>"#,
        ))
        .unwrap();
        let mut want = direct(Some("temperature"));
        want.to_world = Mat4::from_translation(Vec3::new(5.0, 0.0, 0.0)) * want.to_world;
        assert_eq!(grid_of(&s), want);

        let nori = format!(
            r#"<scene>
  <integrator type="vol_path_mis"/>
  <camera type="perspective"/>
  <medium type="heterogeneous">
    <volume type="gridvolume" name="sigma_t"><string name="filename" value="{}"/><string name="grid" value="tiles"/></volume>
    <point name="bounds_min" value="0, 0, 0"/><point name="bounds_max" value="1, 1, 1"/>
  </medium>
</scene>"#,
            vdb.display()
        );
        let s = load(&[("n.xml", &nori)], &[]).unwrap();
        assert_eq!(grid_of(&s), direct(Some("tiles")));

        let e = error_at(
            m(volume(&vdb, r#"<string name="grid" value="smoke"/>"#)),
            "s.xml",
            3,
        );
        assert!(
            e.contains("no grid named 'smoke'") && e.contains("'temperature' (float), 'density'"),
            "{e}"
        );
        let e = error_at(
            m(volume(
                &vdb,
                r#"<boolean name="use_grid_bbox" value="false"/>"#,
            )),
            "s.xml",
            3,
        );
        assert!(e.contains("its own transform"), "{e}");
        let vol = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/media/smoke.vol");
        let e = error_at(
            m(volume(&vol, r#"<string name="grid" value="density"/>"#)),
            "s.xml",
            3,
        );
        assert!(e.contains("picks a grid of a .vdb file"), "{e}");
    }
}
