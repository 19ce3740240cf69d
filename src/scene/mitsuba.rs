//! The Mitsuba 3 dialect: `<scene version="3.x.y">` with `sensor`, `integrator`,
//! `shape`, `bsdf`, `emitter`, `ref`/`id` (forward references allowed, as in Mitsuba).
//!
//! Supported objects (anything else is "not supported yet" or "unknown"):
//! - `sensor type="perspective"`: `fov` + `fov_axis` (x, y, diagonal, smaller, larger;
//!   default x) or `focal_length` (35 mm film, default "50mm"), `near_clip` (0.01),
//!   `far_clip` (10000), `to_world`, `focus_distance` (read, unused); nested
//!   `film type="hdrfilm"` (`width` 768, `height` 576; `pixel_format`,
//!   `component_format`, `banner`, `sample_border`, `rfilter` accepted and ignored) and
//!   `sampler` (independent, stratified, multijitter, orthogonal, ldsampler:
//!   `sample_count` 4; `seed`, `jitter`, `strength` ignored).
//! - `integrator`: any type; its parameters are kept unread in [`IntegratorSpec`].
//! - shapes `obj` (`filename`, `face_normals`, `flip_tex_coords` = true), `ply`
//!   (`filename`, `face_normals`), `rectangle`, `cube`, `disk` (a 256-gon), `sphere`
//!   (`center`, `radius`); all with `to_world` and `flip_normals`.
//! - `bsdf type="diffuse"` (`reflectance`, 0.5); `twosided` around one BSDF is unwrapped.
//! - `emitter`: `area` (`radiance`, nested in or referenced by a shape), `point`
//!   (`position` or `to_world`, `intensity` 1), `constant` (`radiance` 1).
//!
//! An area emitter referenced by several shapes gives each its own [`Emitter::Area`].

use std::collections::{HashMap, HashSet};

use glam::Vec3;

use super::builder::{self, Builder, UNSUPPORTED_BSDFS, UNSUPPORTED_EMITTERS, UNSUPPORTED_MEDIA};
use super::mesh;
use super::properties::Properties;
use super::xml::{Dialect, Document, Element};
use super::{obj, ply, Bsdf, Camera, Emitter, Error, IntegratorSpec, Scene};

const SENSORS: &[&str] = &[
    "thinlens",
    "orthographic",
    "radiancemeter",
    "irradiancemeter",
    "distant",
    "batch",
];
const SHAPES: &[&str] = &[
    "serialized",
    "cylinder",
    "shapegroup",
    "instance",
    "bsplinecurve",
    "linearcurve",
    "sdfgrid",
    "ellipsoids",
    "ellipsoidsmesh",
];
const FILMS: &[&str] = &["specfilm"];
const SAMPLERS: &[&str] = &[
    "independent",
    "stratified",
    "multijitter",
    "orthogonal",
    "ldsampler",
];
const RFILTERS: &[&str] = &["box", "tent", "gaussian", "mitchell", "catmullrom", "lanczos"];

/// Default `<film>` size.
const FILM_WIDTH: u32 = 768;
const FILM_HEIGHT: u32 = 576;

/// Loads a Mitsuba 3 scene read by [`super::xml::read`].
pub fn load(doc: &Document) -> Result<Scene, Error> {
    let mut ids = HashMap::new();
    collect_ids(&doc.root, &mut ids)?;
    let mut l = Loader {
        b: Builder::default(),
        ids,
        bsdf_ids: HashMap::new(),
        area_ids: HashMap::new(),
        building: HashSet::new(),
    };
    let mut camera: Option<(Camera, u32)> = None;
    let mut integrator: Option<IntegratorSpec> = None;
    for el in &doc.root.children {
        match el.tag.as_str() {
            "sensor" => {
                if camera.is_some() {
                    return Err(el.err("more than one <sensor>; wavetrace renders one"));
                }
                camera = Some(sensor(el)?);
            }
            "integrator" => {
                if integrator.is_some() {
                    return Err(el.err("more than one <integrator>"));
                }
                integrator = Some(integrator_spec(el, Dialect::Mitsuba)?);
            }
            "shape" => l.shape(el)?,
            "bsdf" => {
                l.bsdf(el)?;
            }
            "emitter" => l.top_emitter(el)?,
            _ => return Err(l.unexpected(el, "<scene>")),
        }
    }
    let (camera, spp) = camera.ok_or_else(|| doc.root.err("the scene has no <sensor>"))?;
    let integrator = integrator.unwrap_or_else(|| IntegratorSpec {
        name: "path".into(),
        ..Default::default()
    });
    Ok(Scene {
        path: doc.root.file.as_ref().clone(),
        camera,
        spp,
        integrator,
        meshes: l.b.meshes,
        spheres: l.b.spheres,
        bsdfs: l.b.bsdfs,
        emitters: l.b.emitters,
    })
}

/// Every element with an `id`, anywhere in the tree; duplicates are an error.
fn collect_ids<'a>(el: &'a Element, ids: &mut HashMap<String, &'a Element>) -> Result<(), Error> {
    for c in &el.children {
        if c.tag != "ref" {
            if let Some(id) = c.attr("id") {
                if let Some(prev) = ids.insert(id.to_string(), c) {
                    return Err(c.err(format!(
                        "duplicate id '{id}' (first used at {}:{})",
                        prev.file.display(),
                        prev.line
                    )));
                }
            }
        }
        collect_ids(c, ids)?;
    }
    Ok(())
}

/// The parameters of an `<integrator>`, kept unread.
pub fn integrator_spec(el: &Element, dialect: Dialect) -> Result<IntegratorSpec, Error> {
    el.check_attrs(&["type", "id", "name"])?;
    let name = el.require("type")?.to_string();
    let (props, nested) = Properties::read(el, dialect, false)?;
    if let Some(n) = nested.first() {
        return Err(n.err(format!(
            "<{}> inside an <integrator> is not supported yet",
            n.tag
        )));
    }
    Ok(IntegratorSpec {
        name,
        params: props.into_params()?,
        line: Some(el.line),
    })
}

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

fn sensor(el: &Element) -> Result<(Camera, u32), Error> {
    el.check_attrs(&["type", "id", "name"])?;
    if el.require("type")? != "perspective" {
        return Err(builder::unsupported(el, "sensor", SENSORS));
    }
    let (props, nested) = Properties::read(el, Dialect::Mitsuba, false)?;
    let mut size = None;
    let mut spp = None;
    for n in nested {
        match n.tag.as_str() {
            "film" if size.is_none() => size = Some(film(n)?),
            "sampler" if spp.is_none() => spp = Some(sampler(n)?),
            "film" | "sampler" => return Err(n.err(format!("more than one <{}> in <sensor>", n.tag))),
            "medium" | "ref" => return Err(n.err("media are not supported yet")),
            _ => return Err(n.err(format!("unexpected <{}> in <sensor>", n.tag))),
        }
    }
    let (width, height) = size.unwrap_or((FILM_WIDTH, FILM_HEIGHT));
    let fov_x_deg = if props.has("fov") {
        if props.has("focal_length") {
            return Err(props.error(
                "focal_length",
                "give either 'fov' or 'focal_length', not both",
            ));
        }
        let fov = props.float("fov", 0.0)? as f64;
        if !(fov > 0.0 && fov < 180.0) {
            return Err(props.error("fov", format!("fov must be in (0, 180) degrees, found {fov}")));
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
            return Err(props.error("fov_axis", "fov_axis applies to 'fov', not to 'focal_length'"));
        }
        fov_x(fov, "diagonal", width, height).unwrap_or(fov)
    };
    let near_clip = props.float("near_clip", 0.01)?;
    let far_clip = props.float("far_clip", 10000.0)?;
    if !(near_clip > 0.0 && far_clip > near_clip) {
        return Err(props.object_error(format!(
            "need 0 < near_clip < far_clip, found near_clip = {near_clip}, far_clip = {far_clip}"
        )));
    }
    let to_world = props.transform("to_world")?;
    props.ignore(&["focus_distance"]);
    props.finish()?;
    Ok((
        Camera {
            to_world,
            fov_x_deg: fov_x_deg as f32,
            near_clip,
            far_clip,
            width,
            height,
        },
        spp.unwrap_or(4),
    ))
}

fn film(el: &Element) -> Result<(u32, u32), Error> {
    el.check_attrs(&["type", "id", "name"])?;
    if el.require("type")? != "hdrfilm" {
        return Err(builder::unsupported(el, "film", FILMS));
    }
    let (props, nested) = Properties::read(el, Dialect::Mitsuba, false)?;
    for n in nested {
        match n.tag.as_str() {
            "rfilter" => {
                n.check_attrs(&["type", "id", "name"])?;
                let t = n.require("type")?;
                if !RFILTERS.contains(&t) {
                    return Err(n.err(format!("unknown rfilter type '{t}'")));
                }
                // Accepted and ignored, parameters included.
                Properties::read(n, Dialect::Mitsuba, false)?;
            }
            _ => return Err(n.err(format!("unexpected <{}> in <film>", n.tag))),
        }
    }
    let size = (
        props.positive("width", FILM_WIDTH)?,
        props.positive("height", FILM_HEIGHT)?,
    );
    props.ignore(&["pixel_format", "component_format", "banner", "sample_border", "file_format"]);
    props.finish()?;
    Ok(size)
}

fn sampler(el: &Element) -> Result<u32, Error> {
    el.check_attrs(&["type", "id", "name"])?;
    let t = el.require("type")?;
    if !SAMPLERS.contains(&t) {
        return Err(el.err(format!("unknown sampler type '{t}'")));
    }
    let (props, nested) = Properties::read(el, Dialect::Mitsuba, false)?;
    if let Some(n) = nested.first() {
        return Err(n.err(format!("unexpected <{}> in <sampler>", n.tag)));
    }
    let spp = props.positive("sample_count", 4)?;
    props.ignore(&["seed", "jitter", "strength"]);
    props.finish()?;
    Ok(spp)
}

struct Loader<'a> {
    b: Builder,
    ids: HashMap<String, &'a Element>,
    /// BSDFs with an id, built once.
    bsdf_ids: HashMap<String, u32>,
    /// Radiance of area emitters with an id.
    area_ids: HashMap<String, Vec3>,
    /// Ids being built (reference cycle guard).
    building: HashSet<String>,
}

impl<'a> Loader<'a> {
    fn unexpected(&self, el: &Element, parent: &str) -> Error {
        match el.tag.as_str() {
            "medium" => builder::unsupported(el, "medium", UNSUPPORTED_MEDIA),
            "texture" => el.err("textures are not supported yet"),
            "film" | "sampler" | "rfilter" => {
                el.err(format!("<{}> must be nested in a <sensor>", el.tag))
            }
            "phase" | "volume" | "spectrum" => el.err(format!("<{}> is not supported yet", el.tag)),
            "boolean" | "integer" | "float" | "string" | "point" | "vector" | "rgb"
            | "transform" => el.err(format!("<{}> has no meaning in {parent}", el.tag)),
            t => el.err(format!("unexpected <{t}> in {parent}")),
        }
    }

    /// The element a `<ref id=...>` names.
    fn deref(&self, r: &Element) -> Result<&'a Element, Error> {
        r.check_attrs(&["id", "name"])?;
        let id = r.require("id")?;
        self.ids
            .get(id)
            .copied()
            .ok_or_else(|| r.err(format!("reference to unknown id '{id}'")))
    }

    fn bsdf(&mut self, el: &'a Element) -> Result<u32, Error> {
        let id = el.attr("id").map(str::to_string);
        if let Some(id) = &id {
            if let Some(&i) = self.bsdf_ids.get(id) {
                return Ok(i);
            }
            if !self.building.insert(id.clone()) {
                return Err(el.err(format!("reference cycle through id '{id}'")));
            }
        }
        let index = self.build_bsdf(el)?;
        if let Some(id) = id {
            self.building.remove(&id);
            self.bsdf_ids.insert(id, index);
        }
        Ok(index)
    }

    fn build_bsdf(&mut self, el: &'a Element) -> Result<u32, Error> {
        el.check_attrs(&["type", "id", "name"])?;
        let t = el.require("type")?;
        let (props, nested) = Properties::read(el, Dialect::Mitsuba, false)?;
        match t {
            "diffuse" => {
                if let Some(n) = nested.first() {
                    return Err(match n.tag.as_str() {
                        "texture" => n.err("textures are not supported yet"),
                        _ => n.err(format!("unexpected <{}> in a diffuse <bsdf>", n.tag)),
                    });
                }
                let reflectance = props.color("reflectance", Vec3::splat(0.5))?;
                props.finish()?;
                Ok(self.b.add_bsdf(Bsdf::Diffuse { reflectance }))
            }
            "twosided" => {
                // Unwrapped for now: the inner BSDF is used as is.
                props.finish()?;
                let inner: Vec<&'a Element> = el
                    .children
                    .iter()
                    .filter(|c| c.tag == "bsdf" || c.tag == "ref")
                    .collect();
                if inner.len() != 1 || nested.len() != 1 {
                    return Err(el.err(
                        "twosided needs exactly one nested <bsdf> (two different sides are not supported yet)",
                    ));
                }
                let inner = if inner[0].tag == "ref" {
                    let target = self.deref(inner[0])?;
                    if target.tag != "bsdf" {
                        return Err(inner[0].err(format!(
                            "'{}' is a <{}>, not a <bsdf>",
                            inner[0].attr("id").unwrap_or(""),
                            target.tag
                        )));
                    }
                    target
                } else {
                    inner[0]
                };
                self.bsdf(inner)
            }
            _ => Err(builder::unsupported(el, "bsdf", UNSUPPORTED_BSDFS)),
        }
    }

    /// Radiance of an `<emitter type="area">`.
    fn area(&mut self, el: &'a Element) -> Result<Vec3, Error> {
        if let Some(id) = el.attr("id") {
            if let Some(&r) = self.area_ids.get(id) {
                return Ok(r);
            }
        }
        el.check_attrs(&["type", "id", "name"])?;
        let (props, nested) = Properties::read(el, Dialect::Mitsuba, true)?;
        if let Some(n) = nested.first() {
            return Err(n.err(format!("<{}> inside an area emitter is not supported yet", n.tag)));
        }
        let radiance = props
            .color_opt("radiance")?
            .ok_or_else(|| props.object_error("area emitter needs a 'radiance'"))?;
        props.finish()?;
        if let Some(id) = el.attr("id") {
            self.area_ids.insert(id.to_string(), radiance);
        }
        Ok(radiance)
    }

    fn top_emitter(&mut self, el: &'a Element) -> Result<(), Error> {
        el.check_attrs(&["type", "id", "name"])?;
        let t = el.require("type")?;
        if t == "area" {
            if el.attr("id").is_none() {
                return Err(el.err(
                    "an area emitter must be nested in a <shape> or referenced by one (give it an id)",
                ));
            }
            self.area(el)?;
            return Ok(());
        }
        let (props, nested) = Properties::read(el, Dialect::Mitsuba, true)?;
        if !matches!(t, "point" | "constant") {
            return Err(builder::unsupported(el, "emitter", UNSUPPORTED_EMITTERS));
        }
        if let Some(n) = nested.first() {
            return Err(match n.tag.as_str() {
                "medium" | "ref" => n.err("media are not supported yet"),
                "texture" => n.err("textures are not supported yet"),
                tag => n.err(format!("unexpected <{tag}> in an emitter")),
            });
        }
        let emitter = if t == "point" {
            let position = match (props.point_opt("position")?, props.transform_opt("to_world")?) {
                (Some(_), Some(_)) => {
                    return Err(props.error(
                        "position",
                        "give either 'position' or 'to_world', not both",
                    ))
                }
                (Some(p), None) => p,
                (None, Some(m)) => m.w_axis.truncate(),
                (None, None) => Vec3::ZERO,
            };
            Emitter::Point {
                position,
                intensity: props.color("intensity", Vec3::ONE)?,
            }
        } else {
            Emitter::Constant {
                radiance: props.color("radiance", Vec3::ONE)?,
            }
        };
        props.finish()?;
        self.b.add_emitter(emitter);
        Ok(())
    }

    fn shape(&mut self, el: &'a Element) -> Result<(), Error> {
        el.check_attrs(&["type", "id", "name"])?;
        let t = el.require("type")?;
        let (props, nested) = Properties::read(el, Dialect::Mitsuba, false)?;
        let mut bsdf = None;
        let mut radiance = None;
        for n in nested {
            let (target, via_ref) = if n.tag == "ref" {
                (self.deref(n)?, true)
            } else {
                (n, false)
            };
            match target.tag.as_str() {
                "bsdf" => {
                    if bsdf.is_some() {
                        return Err(n.err("a shape can have only one bsdf"));
                    }
                    bsdf = Some(self.bsdf(target)?);
                }
                "emitter" => {
                    if radiance.is_some() {
                        return Err(n.err("a shape can carry only one emitter"));
                    }
                    target.check_attrs(&["type", "id", "name"])?;
                    let et = target.require("type")?;
                    if et != "area" {
                        return Err(if via_ref || UNSUPPORTED_EMITTERS.contains(&et) || et == "point" || et == "constant" {
                            n.err(format!("a shape can only carry an area emitter, not '{et}'"))
                        } else {
                            builder::unsupported(target, "emitter", UNSUPPORTED_EMITTERS)
                        });
                    }
                    radiance = Some(self.area(target)?);
                }
                _ => return Err(self.unexpected(n, "<shape>")),
            }
        }
        let bsdf = match bsdf {
            Some(b) => b,
            None => self.b.default_bsdf(),
        };
        let to_world = props.transform("to_world")?;
        let flip_normals = props.boolean("flip_normals", false)?;
        let (m, face_normals) = match t {
            "obj" => {
                let path = builder::mesh_path(el, &props, "filename")?;
                let face_normals = props.boolean("face_normals", false)?;
                let flip_tex = props.boolean("flip_tex_coords", true)?;
                (obj::load(&path, flip_tex)?, face_normals)
            }
            "ply" => {
                let path = builder::mesh_path(el, &props, "filename")?;
                let face_normals = props.boolean("face_normals", false)?;
                (ply::load(&path)?, face_normals)
            }
            "rectangle" => (mesh::rectangle(), false),
            "cube" => (mesh::cube(), false),
            "disk" => (mesh::disk(mesh::DISK_SEGMENTS), false),
            "sphere" => {
                let center = props.point("center", Vec3::ZERO)?;
                let radius = props.float("radius", 1.0)?;
                props.finish()?;
                let emitter = radiance.map(|r| self.b.add_emitter(Emitter::Area { radiance: r }));
                return self
                    .b
                    .add_sphere(&props, center, radius, to_world, flip_normals, bsdf, emitter);
            }
            _ => return Err(builder::unsupported(el, "shape", SHAPES)),
        };
        props.finish()?;
        let emitter = radiance.map(|r| self.b.add_emitter(Emitter::Area { radiance: r }));
        self.b
            .add_mesh(el, m, to_world, face_normals, flip_normals, bsdf, emitter)
    }
}
