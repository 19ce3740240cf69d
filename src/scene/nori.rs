//! The Nori dialect: `<scene>` (no version) with `camera`, `sampler`, `integrator`,
//! `mesh`, `emitter`.
//!
//! Supported objects (anything else is "not supported yet" or "unknown"):
//! - `camera type="perspective"`: `toWorld`, `fov` (horizontal degrees, 30), `width`
//!   1280, `height` 720, `nearClip` 1e-4, `farClip` 1e4; a nested `rfilter` is ignored.
//!   Nori's camera frame is Mitsuba's.
//! - `sampler type="independent"`: `sampleCount` (1).
//! - `integrator`: any type; its parameters are kept unread in [`IntegratorSpec`].
//! - `mesh type="obj"`: `filename`, `toWorld`, nested `bsdf` (`diffuse` with `albedo`,
//!   0.5) and `emitter type="area"` (`radiance`). Nori does not flip texture v.
//! - top-level `emitter`: `point` (`position`, `power` in W; intensity = power / 4π)
//!   and `distantdisk` with `thetaA` = 180 (a constant environment: `radiance`;
//!   `toWorld` is read and has no effect).

use glam::Vec3;

use super::builder::{self, Builder, UNSUPPORTED_BSDFS, UNSUPPORTED_EMITTERS};
use super::mitsuba::integrator_spec;
use super::properties::Properties;
use super::xml::{Dialect, Document, Element};
use super::{obj, Bsdf, Camera, Emitter, Error, Scene};

/// Loads a Nori scene read by [`super::xml::read`].
pub fn load(doc: &Document) -> Result<Scene, Error> {
    let mut b = Builder::default();
    let mut camera = None;
    let mut spp = None;
    let mut integrator = None;
    for el in &doc.root.children {
        match el.tag.as_str() {
            "camera" => {
                if camera.is_some() {
                    return Err(el.err("more than one <camera>"));
                }
                camera = Some(perspective(el)?);
            }
            "sampler" => {
                if spp.is_some() {
                    return Err(el.err("more than one <sampler>"));
                }
                spp = Some(sampler(el)?);
            }
            "integrator" => {
                if integrator.is_some() {
                    return Err(el.err("more than one <integrator>"));
                }
                integrator = Some(integrator_spec(el, Dialect::Nori)?);
            }
            "mesh" => mesh(el, &mut b)?,
            "emitter" => emitter(el, &mut b)?,
            "test" => return Err(el.err("Nori <test> scenes are not supported yet")),
            "medium" => return Err(el.err("media are not supported yet")),
            t => return Err(el.err(format!("unexpected <{t}> in a Nori <scene>"))),
        }
    }
    let camera = camera.ok_or_else(|| doc.root.err("the scene has no <camera>"))?;
    let integrator = integrator.ok_or_else(|| doc.root.err("the scene has no <integrator>"))?;
    Ok(Scene {
        path: doc.root.file.as_ref().clone(),
        camera,
        spp: spp.unwrap_or(1),
        integrator,
        meshes: b.meshes,
        spheres: b.spheres,
        bsdfs: b.bsdfs,
        emitters: b.emitters,
    })
}

fn perspective(el: &Element) -> Result<Camera, Error> {
    el.check_attrs(&["type"])?;
    if el.require("type")? != "perspective" {
        return Err(builder::unsupported(el, "camera", &[]));
    }
    let (props, nested) = Properties::read(el, Dialect::Nori, false)?;
    for n in nested {
        if n.tag != "rfilter" {
            return Err(n.err(format!("unexpected <{}> in <camera>", n.tag)));
        }
        Properties::read(n, Dialect::Nori, false)?; // accepted and ignored
    }
    let fov = props.float("fov", 30.0)?;
    if !(fov > 0.0 && fov < 180.0) {
        return Err(props.error("fov", format!("fov must be in (0, 180) degrees, found {fov}")));
    }
    let camera = Camera {
        to_world: props.transform("toWorld")?,
        fov_x_deg: fov,
        near_clip: props.float("nearClip", 1e-4)?,
        far_clip: props.float("farClip", 1e4)?,
        width: props.positive("width", 1280)?,
        height: props.positive("height", 720)?,
    };
    if !(camera.near_clip > 0.0 && camera.far_clip > camera.near_clip) {
        return Err(props.object_error("need 0 < nearClip < farClip"));
    }
    props.finish()?;
    Ok(camera)
}

fn sampler(el: &Element) -> Result<u32, Error> {
    el.check_attrs(&["type"])?;
    let t = el.require("type")?;
    if t != "independent" {
        return Err(el.err(format!("unknown sampler type '{t}'")));
    }
    let (props, nested) = Properties::read(el, Dialect::Nori, false)?;
    if let Some(n) = nested.first() {
        return Err(n.err(format!("unexpected <{}> in <sampler>", n.tag)));
    }
    let spp = props.positive("sampleCount", 1)?;
    props.finish()?;
    Ok(spp)
}

fn mesh(el: &Element, b: &mut Builder) -> Result<(), Error> {
    el.check_attrs(&["type"])?;
    if el.require("type")? != "obj" {
        return Err(builder::unsupported(el, "mesh", &[]));
    }
    let (props, nested) = Properties::read(el, Dialect::Nori, false)?;
    let mut bsdf = None;
    let mut radiance = None;
    for n in nested {
        match n.tag.as_str() {
            "bsdf" if bsdf.is_none() => bsdf = Some(nori_bsdf(n, b)?),
            "emitter" if radiance.is_none() => {
                n.check_attrs(&["type"])?;
                let et = n.require("type")?;
                if et != "area" {
                    return Err(n.err(format!(
                        "a mesh can only carry an area emitter, not '{et}'"
                    )));
                }
                let (p, nn) = Properties::read(n, Dialect::Nori, true)?;
                if let Some(x) = nn.first() {
                    return Err(x.err(format!("unexpected <{}> in an emitter", x.tag)));
                }
                radiance = Some(
                    p.color_opt("radiance")?
                        .ok_or_else(|| p.object_error("area emitter needs a 'radiance'"))?,
                );
                p.finish()?;
            }
            "bsdf" | "emitter" => return Err(n.err(format!("a mesh can have only one <{}>", n.tag))),
            "medium" => return Err(n.err("media are not supported yet")),
            t => return Err(n.err(format!("unexpected <{t}> in <mesh>"))),
        }
    }
    let path = builder::mesh_path(el, &props, "filename")?;
    let to_world = props.transform("toWorld")?;
    props.finish()?;
    let m = obj::load(&path, false)?;
    let bsdf = match bsdf {
        Some(i) => i,
        None => b.default_bsdf(),
    };
    let emitter = radiance.map(|r| b.add_emitter(Emitter::Area { radiance: r }));
    b.add_mesh(el, m, to_world, false, false, bsdf, emitter)
}

fn nori_bsdf(el: &Element, b: &mut Builder) -> Result<u32, Error> {
    el.check_attrs(&["type"])?;
    if el.require("type")? != "diffuse" {
        return Err(builder::unsupported(el, "bsdf", UNSUPPORTED_BSDFS));
    }
    let (props, nested) = Properties::read(el, Dialect::Nori, false)?;
    if let Some(n) = nested.first() {
        return Err(n.err(format!("unexpected <{}> in <bsdf>", n.tag)));
    }
    let reflectance = props.color("albedo", Vec3::splat(0.5))?;
    props.finish()?;
    Ok(b.add_bsdf(Bsdf::Diffuse { reflectance }))
}

fn emitter(el: &Element, b: &mut Builder) -> Result<(), Error> {
    el.check_attrs(&["type"])?;
    let t = el.require("type")?;
    let (props, nested) = Properties::read(el, Dialect::Nori, true)?;
    if let Some(n) = nested.first() {
        return Err(n.err(format!("unexpected <{}> in <emitter>", n.tag)));
    }
    let e = match t {
        "point" => Emitter::Point {
            position: props.point("position", Vec3::ZERO)?,
            intensity: props
                .color_opt("power")?
                .ok_or_else(|| props.object_error("point emitter needs a 'power'"))?
                / (4.0 * std::f32::consts::PI),
        },
        "distantdisk" => {
            let theta = props.float("thetaA", 180.0)?;
            if theta != 180.0 {
                return Err(props.error(
                    "thetaA",
                    format!("distantdisk with thetaA = {theta} is not supported yet (only 180, a constant environment)"),
                ));
            }
            props.transform("toWorld")?;
            Emitter::Constant {
                radiance: props
                    .color_opt("radiance")?
                    .ok_or_else(|| props.object_error("distantdisk needs a 'radiance'"))?,
            }
        }
        "area" => return Err(el.err("an area emitter must be nested in a <mesh>")),
        _ => return Err(builder::unsupported(el, "emitter", UNSUPPORTED_EMITTERS)),
    };
    props.finish()?;
    b.add_emitter(e);
    Ok(())
}
