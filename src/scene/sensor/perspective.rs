//! `perspective`: the pinhole camera of both dialects ([`Camera`]).
//!
//! Mitsuba 3: `fov` + `fov_axis` (x, y, diagonal, smaller, larger; default x) or
//! `focal_length` (35 mm film, default "50mm"), `near_clip` (0.01), `far_clip` (10000),
//! `to_world`, `focus_distance` (read, unused); a nested `<film>`, `<sampler>` and
//! `<medium>` (or a `<ref>` to one) the camera sits in.
//!
//! Nori: `toWorld`, `fov` (horizontal degrees, 30), `width` 1280, `height` 720,
//! `nearClip` 1e-4, `farClip` 1e4; a nested `<rfilter>`. Nori's camera looks down +z
//! like Mitsuba's but puts image column 0 at camera -x. `lookat` is orthonormal, as in
//! Nori since its commit 981dfb2 (2015-08-18); before that Nori left its `left` and
//! `up` axes unnormalised, of length sin θ (θ between `up` and the view direction),
//! which narrows tan(fov / 2) by that factor: the 2015 course references (veach_mi,
//! odyssey, sphere) are 1-4.4% zoomed in against these files
//! (`tests/nori_scenes_vs_2015_references.rs`).
//!
//! ```xml
//! <sensor type="perspective"><float name="fov" value="40"/>
//!     <transform name="to_world"><lookat origin="0,1,5" target="0,1,0" up="0,1,0"/></transform>
//!     <film type="hdrfilm"><integer name="width" value="256"/><integer name="height" value="256"/></film>
//! </sensor>
//! ```

use super::{SensorParts, FILM_HEIGHT, FILM_WIDTH};
use crate::scene::film::Filter;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::sampler::Sampler;
use crate::scene::xml::{Dialect, Element};
use crate::scene::{Camera, Error, Film, Projection};

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Sensor,
    Dialect::Mitsuba,
    "perspective",
    "A pinhole camera looking down +z of to_world; nests a <film>, a <sampler> and the <medium> it sits in.",
    &[
        Param::new("fov", "float", "", "field of view (degrees, in (0, 180)) along fov_axis; or give focal_length"),
        Param::new("fov_axis", "string", "x", "x, y, diagonal, smaller or larger"),
        Param::new("focal_length", "string", "50mm", "focal length on 35 mm film, instead of fov"),
        Param::new("near_clip", "float", "0.01", "near clip distance"),
        Param::new("far_clip", "float", "10000", "far clip distance"),
        Param::new("to_world", "transform", "identity", "camera to world"),
        Param::new("focus_distance", "float", "", "read and ignored (a pinhole)"),
    ],
);

pub const NORI: PluginDoc = PluginDoc::new(
    Family::Sensor,
    Dialect::Nori,
    "perspective",
    "A pinhole camera (image column 0 at camera -x); nests an <rfilter>.",
    &[
        Param::new("toWorld", "transform", "identity", "camera to world"),
        Param::new("fov", "float", "30", "horizontal field of view (degrees)"),
        Param::new("width", "integer", "1280", "image width"),
        Param::new("height", "integer", "720", "image height"),
        Param::new("nearClip", "float", "1e-4", "near clip distance"),
        Param::new("farClip", "float", "1e4", "far clip distance"),
    ],
);

/// The horizontal field of view in degrees for `fov` measured along `axis` of a
/// `width` x `height` image (Mitsuba's `fov_axis`).
pub fn fov_x(fov_deg: f64, axis: &str, width: u32, height: u32) -> Option<f64> {
    let aspect = width as f64 / height as f64;
    let axis = match axis {
        "smaller" => {
            if aspect > 1.0 {
                "y"
            } else {
                "x"
            }
        }
        "larger" => {
            if aspect > 1.0 {
                "x"
            } else {
                "y"
            }
        }
        a => a,
    };
    let t = (fov_deg.to_radians() * 0.5).tan();
    let tx = match axis {
        "x" => t,
        "y" => t * aspect,
        "diagonal" => t / (1.0 + 1.0 / (aspect * aspect)).sqrt(),
        _ => return None,
    };
    Some((2.0 * tx.atan()).to_degrees())
}

/// The horizontal field of view in degrees that `fov` + `fov_axis` or `focal_length`
/// give a `width` x `height` image (Mitsuba's `parse_fov`; default "50mm").
pub fn parse_fov(props: &Properties, width: u32, height: u32) -> Result<f64, Error> {
    Ok(if props.has("fov") {
        if props.has("focal_length") {
            return Err(props.error(
                "focal_length",
                "give either 'fov' or 'focal_length', not both",
            ));
        }
        let fov = props.float("fov", 0.0)? as f64;
        if !(fov > 0.0 && fov < 180.0) {
            return Err(props.error(
                "fov",
                format!("fov must be in (0, 180) degrees, found {fov}"),
            ));
        }
        let axis = props.string("fov_axis", "x")?.to_ascii_lowercase();
        fov_x(fov, &axis, width, height).ok_or_else(|| {
            props.error(
                "fov_axis",
                format!("fov_axis must be x, y, diagonal, smaller or larger, found '{axis}'"),
            )
        })?
    } else {
        let s = props.string("focal_length", "50mm")?;
        let f = s
            .trim()
            .strip_suffix("mm")
            .unwrap_or(s.trim())
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|f| *f > 0.0 && f.is_finite())
            .ok_or_else(|| {
                props.error(
                    "focal_length",
                    format!("could not parse focal_length \"{s}\" (expected e.g. \"50mm\")"),
                )
            })?;
        // 35 mm film: the 36 x 24 mm frame's diagonal sees the fov.
        let diag = (36.0f64 * 36.0 + 24.0 * 24.0).sqrt();
        let fov = (2.0 * (diag / (2.0 * f)).atan()).to_degrees();
        if props.has("fov_axis") {
            return Err(props.error(
                "fov_axis",
                "fov_axis applies to 'fov', not to 'focal_length'",
            ));
        }
        fov_x(fov, "diagonal", width, height).unwrap_or(fov)
    })
}

/// A Mitsuba `<sensor type="perspective">` (its type already checked).
pub fn mitsuba(el: &Element) -> Result<SensorParts<'_>, Error> {
    projective(el, "perspective")
}

/// A Mitsuba `perspective`, `thinlens` or `orthographic` sensor (`kind`): what they
/// share (film, sampler, medium, clip planes, to_world) and what each adds.
pub(super) fn projective<'a>(el: &'a Element, kind: &str) -> Result<SensorParts<'a>, Error> {
    projective_sized(el, kind, None)
}

/// [`projective`], its film's size (width, height) then set to `size_override`, as a
/// `batch` sensor sets its children's (Mitsuba's `film()->set_size`, then
/// `parameters_changed`): the horizontal fov stays what `fov_axis` gave against the
/// sensor's own film (its nested `<film>`, or the default 768 x 576); the vertical one
/// follows the new aspect ratio.
pub(super) fn projective_sized<'a>(
    el: &'a Element,
    kind: &str,
    size_override: Option<(u32, u32)>,
) -> Result<SensorParts<'a>, Error> {
    let (props, nested) = Properties::read(el, Dialect::Mitsuba, false)?;
    let mut size = None;
    let mut spp = None;
    let mut medium = None;
    for n in nested {
        match n.tag.as_str() {
            "film" if size.is_none() => size = Some(super::film(n)?),
            "sampler" if spp.is_none() => spp = Some(super::sampler(n)?),
            "film" | "sampler" => {
                return Err(n.err(format!("more than one <{}> in <sensor>", n.tag)))
            }
            "medium" | "ref" if medium.is_none() => medium = Some(n),
            "medium" | "ref" => return Err(n.err("a sensor sits in one medium")),
            _ => return Err(n.err(format!("unexpected <{}> in <sensor>", n.tag))),
        }
    }
    let (mut width, mut height, film) = size.unwrap_or((FILM_WIDTH, FILM_HEIGHT, Film::default()));
    let fov_x_deg = if matches!(
        kind,
        "orthographic" | "radiancemeter" | "distant" | "irradiancemeter"
    ) {
        90.0
    } else {
        parse_fov(&props, width, height)?
    };
    // Mitsuba resolves the fov against the sensor's own film when it is built; a batch
    // then sets the film's size, which changes the aspect ratio alone.
    // A radiancemeter checks its own film's size (1 x 1) before a batch resizes it.
    let own_size = (width, height);
    if let Some((w, h)) = size_override {
        (width, height) = (w, h);
    }
    // A radiance meter has no clip planes (Mitsuba's radiancemeter is no projective
    // camera): its ray is unbounded.
    let (near_clip, far_clip) = if matches!(kind, "radiancemeter" | "distant" | "irradiancemeter") {
        (0.01, f32::MAX)
    } else {
        (
            props.float("near_clip", 0.01)?,
            props.float("far_clip", 10000.0)?,
        )
    };
    if !(near_clip > 0.0 && far_clip > near_clip) {
        return Err(props.object_error(format!(
            "need 0 < near_clip < far_clip, found near_clip = {near_clip}, far_clip = {far_clip}"
        )));
    }
    let to_world = if kind == "radiancemeter" {
        super::radiancemeter::to_world(&props, own_size.0, own_size.1)?
    } else if kind == "distant" {
        super::distant::to_world(&props, width, height)?
    } else if kind == "irradiancemeter" {
        super::irradiancemeter::to_world(&props)?
    } else {
        props.transform("to_world")?
    };
    let projection = match kind {
        "radiancemeter" => Projection::RadianceMeter,
        "distant" => Projection::Distant {
            target: props.point_opt("target")?,
        },
        "thinlens" => super::thinlens::lens(&props, to_world, far_clip)?,
        "orthographic" => Projection::Orthographic,
        _ => {
            props.ignore(&["focus_distance"]);
            Projection::Perspective
        }
    };
    props.finish()?;
    Ok((
        Camera {
            to_world,
            fov_x_deg: fov_x_deg as f32,
            near_clip,
            far_clip,
            width,
            height,
            projection,
            batch: Vec::new(),
        },
        spp.unwrap_or((Sampler::default(), 4)),
        film,
        medium,
    ))
}

/// A Nori `<camera type="perspective">` (its type already checked) and its film
/// (Nori's reconstruction filter sits in the camera).
pub fn nori(el: &Element) -> Result<(Camera, Film), Error> {
    let (props, nested) = Properties::read(el, Dialect::Nori, false)?;
    let mut filter = None;
    for n in nested {
        match n.tag.as_str() {
            "rfilter" if filter.is_none() => filter = Some(Filter::from_nori(n)?),
            "rfilter" => return Err(n.err("the camera has more than one reconstruction filter")),
            _ => return Err(n.err(format!("unexpected <{}> in <camera>", n.tag))),
        }
    }
    let fov = props.float("fov", 30.0)?;
    if !(fov > 0.0 && fov < 180.0) {
        return Err(props.error(
            "fov",
            format!("fov must be in (0, 180) degrees, found {fov}"),
        ));
    }
    let camera = Camera {
        // Nori maps image column 0 to camera -x (its sample-to-camera transform scales
        // x by +1/2 where Mitsuba's scales by -1/2): mirror x into our Mitsuba frame.
        // Scenes converted from Mitsuba therefore carry <scale value="-1,1,1"/>.
        to_world: props.transform("toWorld")?
            * glam::Mat4::from_scale(glam::Vec3::new(-1.0, 1.0, 1.0)),
        fov_x_deg: fov,
        near_clip: props.float("nearClip", 1e-4)?,
        far_clip: props.float("farClip", 1e4)?,
        width: props.positive("width", 1280)?,
        height: props.positive("height", 720)?,
        projection: Projection::Perspective,
        batch: Vec::new(),
    };
    if !(camera.near_clip > 0.0 && camera.far_clip > camera.near_clip) {
        return Err(props.object_error("need 0 < nearClip < farClip"));
    }
    props.finish()?;
    Ok((camera, Film::nori(filter.unwrap_or(Filter::DEFAULT))))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fov_axis_conversions() {
        let deg = |x: f64| x.to_radians();
        // y: tan(fx/2) = tan(fy/2) * aspect.
        let fx = fov_x(40.0, "y", 200, 100).unwrap();
        assert!((deg(fx / 2.0).tan() - 2.0 * deg(20.0).tan()).abs() < 1e-12);
        // smaller/larger pick y/x for a wide image, x/y for a tall one.
        assert_eq!(fov_x(40.0, "smaller", 200, 100), fov_x(40.0, "y", 200, 100));
        assert_eq!(fov_x(40.0, "larger", 200, 100), Some(40.0));
        assert_eq!(fov_x(40.0, "smaller", 100, 200), Some(40.0));
        assert_eq!(fov_x(40.0, "larger", 100, 200), fov_x(40.0, "y", 100, 200));
        // diagonal: tan(fx/2) = tan(fd/2) * w / sqrt(w^2 + h^2).
        let fx = fov_x(60.0, "diagonal", 300, 400).unwrap();
        assert!((deg(fx / 2.0).tan() - deg(30.0).tan() * 300.0 / 500.0).abs() < 1e-12);
        assert_eq!(fov_x(60.0, "z", 1, 1), None);
    }
}
