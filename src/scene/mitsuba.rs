//! The Mitsuba 3 dialect's tree walker: `<scene version="3.x.y">` with `sensor`,
//! `integrator`, `shape`, `bsdf`, `emitter`, `medium`, `texture` and `ref`/`id`
//! (forward references allowed, as in Mitsuba), and `path value="DIR"` (a folder file
//! names are also searched in, see [`super::xml::SearchPath`]).
//!
//! This file resolves references and ids, nesting and what may sit where; each
//! object's type and parameters are read by its plugin family (`super::sensor`,
//! `super::shape`, `super::emitter`, `super::bsdf`, `super::texture`,
//! `super::medium`, `super::integrator`, `super::film`, `super::sampler`), whose
//! registries list every type with the parameters it reads: `docs/plugins.md` is
//! generated from them ([`super::plugin::catalogue`]).
//!
//! An area emitter referenced by several shapes gives each its own [`Emitter::Area`];
//! `moment` around one nested integrator stands for that integrator (its mean).

use std::collections::{HashMap, HashSet};

use glam::Vec3;

use super::bsdf;
use super::builder::{Builder, MeshOptions};
use super::camera::SensorShape;
use super::emitter;
use super::integrator;
use super::plugin::{self, Family};
use super::properties::Properties;
use super::sensor::{self, SceneSensor};
use super::shape::{self, Geometry};
use super::xml::{Dialect, Document, Element};
use super::{
    Bsdf, Emitter, Error, Instance, IntegratorSpec, Medium, Quadric, Scene, ShapeGroup, Texture,
};

/// Loads a Mitsuba 3 scene read by [`super::xml::read`].
pub fn load(doc: &Document) -> Result<Scene, Error> {
    let root = super::inline_refs::inline(&doc.root)?;
    let mut ids = HashMap::new();
    collect_ids(&root, &mut ids)?;
    let mut l = Loader {
        b: Builder::default(),
        ids,
        bsdf_ids: HashMap::new(),
        area_ids: HashMap::new(),
        medium_ids: HashMap::new(),
        null_bsdfs: HashSet::new(),
        texture_ids: HashMap::new(),
        building: HashSet::new(),
        attached_areas: HashSet::new(),
        groups: Vec::new(),
        group_ids: HashMap::new(),
        instances: Vec::new(),
        shape_sensors: Vec::new(),
    };
    // Every sensor in document order (Mitsuba's order of `scene.sensors()`): those at
    // the top level and those nested in shapes.
    let mut sensors: Vec<SceneSensor> = Vec::new();
    let mut integrator: Option<IntegratorSpec> = None;
    for el in &root.children {
        match el.tag.as_str() {
            "sensor" => {
                let parts = sensor::mitsuba(el)?;
                sensors.push(l.sensor_choice(parts)?);
            }
            "integrator" => {
                if integrator.is_some() {
                    return Err(el.err("more than one <integrator>"));
                }
                integrator = Some(integrator::spec(el, Dialect::Mitsuba)?);
            }
            "shape" => {
                l.shape(el)?;
                for parts in std::mem::take(&mut l.shape_sensors) {
                    sensors.push(l.sensor_choice(parts)?);
                }
            }
            "bsdf" => {
                l.bsdf(el)?;
            }
            "emitter" => l.top_emitter(el)?,
            "medium" => {
                l.medium(el)?;
            }
            "texture" => {
                if el.attr("id").is_none() {
                    return Err(el.err(
                        "a texture outside a bsdf or emitter needs an id to be referenced by",
                    ));
                }
                l.texture(el, false)?;
            }
            _ => return Err(l.unexpected(el, "<scene>")),
        }
    }
    let SceneSensor {
        camera,
        sampler,
        spp,
        film,
        medium: camera_medium,
    } = sensors
        .first()
        .cloned()
        .ok_or_else(|| root.err("the scene has no <sensor>"))?;
    let environments =
        l.b.emitters
            .iter()
            .filter(|e| matches!(e, Emitter::Constant { .. } | Emitter::EnvMap { .. }))
            .count();
    if environments > 1 {
        return Err(root.err(
            "the scene has more than one environment emitter (constant or envmap); wavetrace supports one",
        ));
    }
    if !l.b.emitter_weights.is_empty() && l.b.emitter_weights.iter().all(|&w| w == 0.0) {
        return Err(doc
            .root
            .err("every emitter has sampling_weight 0: emitter sampling could choose none"));
    }
    let integrator = integrator.unwrap_or_else(|| IntegratorSpec {
        name: "path".into(),
        ..Default::default()
    });
    // B-spline curves' control points follow the sdfgrids in the grid buffer.
    let grid_words = l.b.sdfgrids.iter().map(|g| g.words()).sum();
    super::shape::bsplinecurve::place(&mut l.b.meshes, grid_words).map_err(|m| root.err(m))?;
    // Ellipsoids follow those.
    let curve_words: usize =
        l.b.meshes
            .iter()
            .filter(|m| m.is_bspline())
            .map(|m| 4 * m.positions.len())
            .sum();
    super::shape::ellipsoids::place(&mut l.b.meshes, grid_words + curve_words)
        .map_err(|m| root.err(m))?;
    let scene = Scene {
        path: root.file.as_ref().clone(),
        camera,
        film,
        spp,
        sampler,
        integrator,
        meshes: l.b.meshes,
        quadrics: l.b.quadrics,
        sdfgrids: l.b.sdfgrids,
        groups: l.groups,
        instances: l.instances,
        bsdfs: l.b.bsdfs,
        emitters: l.b.emitters,
        emitter_weights: l.b.emitter_weights,
        media: l.b.media,
        camera_medium,
        textures: l.b.textures,
        sensors,
    };
    super::texture::mesh_attribute::check(&scene)?;
    Ok(scene)
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

/// What a `<shape>` nests besides its parameters.
#[derive(Default)]
struct ShapeParts<'a> {
    bsdf: Option<u32>,
    /// A nested `<sensor>` (an irradiancemeter), read once the shape is placed.
    sensor: Option<&'a Element>,
    radiance: Option<(Emitter, f32)>,
    interior: Option<u32>,
    exterior: Option<u32>,
}

struct Loader<'a> {
    b: Builder,
    ids: HashMap<String, &'a Element>,
    /// BSDFs with an id, built once.
    bsdf_ids: HashMap<String, u32>,
    /// Area emitters with an id.
    area_ids: HashMap<String, (Emitter, f32)>,
    /// Textures with an id: index and mean.
    texture_ids: HashMap<String, (u32, Vec3)>,
    /// Media with an id, built once.
    medium_ids: HashMap<String, u32>,
    /// Indices of `null` BSDFs (boundaries of media, passed straight through).
    null_bsdfs: HashSet<u32>,
    /// Ids being built (reference cycle guard).
    building: HashSet<String>,
    /// Ids of area emitters a shape references (Mitsuba attaches one to one shape).
    attached_areas: HashSet<String>,
    /// Shape groups, and those with an id (built once, at their place or at the
    /// first instance that names them).
    groups: Vec<ShapeGroup>,
    group_ids: HashMap<String, u32>,
    instances: Vec<Instance>,
    /// The sensors nested in shapes (irradiancemeters).
    shape_sensors: Vec<sensor::SensorParts<'a>>,
}

impl<'a> Loader<'a> {
    /// The error for a `<ref>` naming `target`, which `parent` does not take: where,
    /// the id, what it names and where that was declared.
    fn misplaced_ref(r: &Element, target: &Element, parent: &str) -> Error {
        let article = if parent.starts_with('<') { "a " } else { "" };
        let what = match target.attr("type") {
            Some(t) => format!("<{} type=\"{t}\">", target.tag),
            None => format!("<{}>", target.tag),
        };
        r.err(format!(
            "<ref id=\"{}\"> names the {what} declared at {}:{}, which {article}{parent} does not take (Mitsuba refuses it too)",
            r.attr("id").unwrap_or(""),
            target.file.display(),
            target.line
        ))
    }

    fn unexpected(&self, el: &Element, parent: &str) -> Error {
        if el.tag == "ref" {
            return match self.deref(el) {
                Ok(target) => Self::misplaced_ref(el, target, parent),
                Err(e) => e,
            };
        }
        match el.tag.as_str() {
            "texture" => el.err(format!(
                "a <texture> in {parent} has no parameter to feed (textures go in a bsdf or an area emitter)"
            )),
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

    /// A `<medium>` element's index in the scene's media (built once per id).
    fn medium(&mut self, el: &'a Element) -> Result<u32, Error> {
        let id = el.attr("id").map(str::to_string);
        if let Some(i) = id.as_ref().and_then(|id| self.medium_ids.get(id)) {
            return Ok(*i);
        }
        // What a `<ref>` in a medium may name (volumes and phase functions) was copied
        // to its place (inline_refs); any other reference is misplaced.
        if let Some(r) = el.children.iter().find(|c| c.tag == "ref") {
            let target = self.deref(r)?;
            if target.tag == "texture" {
                return Err(r.err(format!(
                    "<ref id=\"{}\"> names a <texture> as a volume of a medium: Mitsuba takes it, wavetrace does not yet (use a <volume>)",
                    r.attr("id").unwrap_or("")
                )));
            }
            return Err(Self::misplaced_ref(r, target, "a <medium>"));
        }
        let m = Medium::from_mitsuba(el)?;
        if self.b.media.len() >= 0xfffe {
            return Err(el.err("more than 65534 media"));
        }
        self.b.media.push(m);
        let index = (self.b.media.len() - 1) as u32;
        if let Some(id) = id {
            self.medium_ids.insert(id, index);
        }
        Ok(index)
    }

    /// The medium a nested `<medium>` or a `<ref>` names.
    fn medium_of(&mut self, n: &'a Element, parent: &str) -> Result<u32, Error> {
        let target = if n.tag == "ref" { self.deref(n)? } else { n };
        if target.tag != "medium" {
            return Err(Self::misplaced_ref(n, target, parent));
        }
        self.medium(target)
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
            "null" => {
                // Mitsuba's null BSDF: the surface only bounds media. Shapes carrying it
                // are flagged; the diffuse stand-in is never evaluated.
                props.finish()?;
                if let Some(n) = nested.first() {
                    return Err(n.err(format!("unexpected <{}> in a null <bsdf>", n.tag)));
                }
                let index = self.b.add_bsdf(Bsdf::default());
                self.null_bsdfs.insert(index);
                Ok(index)
            }
            "twosided" => {
                // One nested BSDF used on both faces, or a front and a back one
                // (Mitsuba's twosided.cpp).
                props.finish()?;
                let inner = self.nested_bsdfs(el, nested)?;
                let sides: Vec<Bsdf> = match inner.as_slice() {
                    [_] | [_, _] => inner
                        .iter()
                        .map(|(i, _)| self.b.bsdfs[*i as usize].clone())
                        .collect(),
                    _ => return Err(el.err("twosided needs one or two nested <bsdf>s")),
                };
                if let Some(k) = sides.iter().position(Bsdf::transmits) {
                    return Err(inner[k]
                        .1
                        .err("twosided: only materials without transmission can be nested"));
                }
                let bsdf = match <[Bsdf; 2]>::try_from(sides) {
                    Ok(pair) => Bsdf::TwoSidedPair(Box::new(pair)),
                    Err(mut one) => Bsdf::TwoSided(Box::new(one.remove(0))),
                };
                Ok(self.b.add_bsdf(bsdf))
            }
            "mask" | "blendbsdf" | "bumpmap" => {
                // Composites (bsdf::composite): an opacity, a weight or a height field,
                // and their nested BSDFs.
                let mut props = props;
                let rest = self.attach_textures(&mut props, nested, false)?;
                let count = if t == "blendbsdf" { 2 } else { 1 };
                let bsdf = match t {
                    "mask" => {
                        let opacity = bsdf::mask::params(&props)?;
                        props.finish()?;
                        let inner = self.nested_bsdf_values(el, rest, count, t)?;
                        Bsdf::Mask {
                            opacity,
                            bsdf: Box::new(inner[0].clone()),
                        }
                    }
                    "blendbsdf" => {
                        let weight = bsdf::blendbsdf::params(&props)?;
                        props.finish()?;
                        let inner = self.nested_bsdf_values(el, rest, count, t)?;
                        Bsdf::Blend {
                            weight,
                            bsdfs: Box::new([inner[0].clone(), inner[1].clone()]),
                        }
                    }
                    _ => {
                        let params = bsdf::bumpmap::params(&props)?;
                        props.finish()?;
                        let inner = self.nested_bsdf_values(el, rest, count, t)?;
                        Bsdf::BumpMap {
                            params,
                            bsdf: Box::new(inner[0].clone()),
                        }
                    }
                };
                Ok(self.b.add_bsdf(bsdf))
            }
            "normalmap" => {
                // Mitsuba's normalmap.cpp: a `normalmap` texture and one nested BSDF.
                let mut props = props;
                let rest = self.attach_textures(&mut props, nested, false)?;
                let (normal_map, flip_invalid_normals, use_shadowing_function) =
                    bsdf::normalmap::params(&props)?;
                props.finish()?;
                let inner: Vec<&'a Element> = rest
                    .iter()
                    .map(|n| {
                        if n.tag == "ref" {
                            self.deref(n)
                        } else {
                            Ok(*n)
                        }
                    })
                    .collect::<Result<_, _>>()?;
                if inner.len() != 1 || inner[0].tag != "bsdf" {
                    return Err(el.err("normalmap needs exactly one nested <bsdf>"));
                }
                let index = self.bsdf(inner[0])?;
                let nested_bsdf = self.b.bsdfs[index as usize].clone();
                if bsdf::composite::is_composite(&nested_bsdf) {
                    return Err(inner[0].err(
                        "a normalmap around a composite BSDF (mask, blendbsdf, bumpmap, twosided with a composite or two sides) is not supported yet",
                    ));
                }
                Ok(self.b.add_bsdf(Bsdf::NormalMap {
                    bsdf: Box::new(nested_bsdf),
                    normal_map,
                    flip_invalid_normals,
                    use_shadowing_function,
                }))
            }
            _ => {
                let plugin = bsdf::plugin(Dialect::Mitsuba, t)
                    .ok_or_else(|| bsdf::unsupported(el, Dialect::Mitsuba))?;
                let mut props = props;
                let rest = self.attach_textures(&mut props, nested, false)?;
                if let Some(n) = rest.first() {
                    return Err(n.err(format!("unexpected <{}> in a {t} <bsdf>", n.tag)));
                }
                let bsdf = plugin
                    .read(&props)
                    .expect("the loader reads null, twosided, normalmap")?;
                props.finish()?;
                Ok(self.b.add_bsdf(bsdf))
            }
        }
    }

    /// The BSDFs nested in `el` (`<bsdf>`s, or `<ref>`s to them), built, with the
    /// element that names each; anything else nested is an error.
    fn nested_bsdfs(
        &mut self,
        el: &'a Element,
        nested: Vec<&'a Element>,
    ) -> Result<Vec<(u32, &'a Element)>, Error> {
        let mut out = Vec::new();
        for n in nested {
            let target = if n.tag == "ref" { self.deref(n)? } else { n };
            if target.tag != "bsdf" {
                return Err(if n.tag == "ref" {
                    Self::misplaced_ref(
                        n,
                        target,
                        &format!("a {} <bsdf>", el.attr("type").unwrap_or("")),
                    )
                } else {
                    n.err(format!(
                        "unexpected <{}> in a {} <bsdf>",
                        n.tag,
                        el.attr("type").unwrap_or("")
                    ))
                });
            }
            out.push((self.bsdf(target)?, n));
        }
        Ok(out)
    }

    /// Exactly `count` nested BSDFs of a `t` composite, as values.
    fn nested_bsdf_values(
        &mut self,
        el: &'a Element,
        nested: Vec<&'a Element>,
        count: usize,
        t: &str,
    ) -> Result<Vec<Bsdf>, Error> {
        let inner = self.nested_bsdfs(el, nested)?;
        if inner.len() != count {
            let what = if count == 1 {
                "one nested <bsdf>".to_string()
            } else {
                format!("{count} nested <bsdf>s")
            };
            return Err(el.err(format!("{t} needs exactly {what}, found {}", inner.len())));
        }
        Ok(inner
            .iter()
            .map(|(i, _)| self.b.bsdfs[*i as usize].clone())
            .collect())
    }

    /// A `<texture>` (nested, or the target of a `<ref>`): its index and mean.
    /// `within_emitter`: its colors are radiance (not clamped to [0, 1]).
    fn texture(&mut self, el: &'a Element, within_emitter: bool) -> Result<(u32, Vec3), Error> {
        if let Some(id) = el.attr("id") {
            if let Some(&t) = self.texture_ids.get(id) {
                return Ok(t);
            }
        }
        el.check_attrs(&["type", "id", "name"])?;
        let t = el.require("type")?;
        let (props, nested) = Properties::read(el, Dialect::Mitsuba, within_emitter)?;
        if let Some(n) = nested.first() {
            return Err(n.err(format!(
                "<{}> inside a texture is not supported (textures of textures)",
                n.tag
            )));
        }
        let texture = Texture::from_mitsuba(t, &props, el)?;
        let mean = texture.mean();
        let index = self.b.add_texture(texture);
        if let Some(id) = el.attr("id") {
            self.texture_ids.insert(id.to_string(), (index, mean));
        }
        Ok((index, mean))
    }

    /// Moves the `<texture name=...>` children and `<ref name=... id=.../>`s to
    /// textures among `nested` into `props`; returns the other nested elements.
    fn attach_textures(
        &mut self,
        props: &mut Properties,
        nested: Vec<&'a Element>,
        within_emitter: bool,
    ) -> Result<Vec<&'a Element>, Error> {
        let mut rest = Vec::new();
        for n in nested {
            let target = if n.tag == "ref" {
                let target = self.deref(n)?;
                if target.tag != "texture" {
                    rest.push(n);
                    continue;
                }
                target
            } else if n.tag == "texture" {
                n
            } else {
                rest.push(n);
                continue;
            };
            let name = n
                .attr("name")
                .ok_or_else(|| n.err("a texture here needs a name (the parameter it gives)"))?;
            let (index, mean) = self.texture(target, within_emitter)?;
            props.insert_texture(name, index, mean, n.line)?;
        }
        Ok(rest)
    }

    /// An `<emitter type="area">`: constant or textured radiance.
    fn area(&mut self, el: &'a Element) -> Result<(Emitter, f32), Error> {
        if let Some(id) = el.attr("id") {
            if let Some(e) = self.area_ids.get(id) {
                return Ok(e.clone());
            }
        }
        el.check_attrs(&["type", "id", "name"])?;
        let (mut props, nested) = Properties::read(el, Dialect::Mitsuba, true)?;
        let rest = self.attach_textures(&mut props, nested, true)?;
        if let Some(n) = rest.first() {
            return Err(n.err(format!(
                "<{}> inside an area emitter is not supported yet",
                n.tag
            )));
        }
        let (emitter, weight) = emitter::area::mitsuba(&props)?;
        if let Some(id) = el.attr("id") {
            self.area_ids
                .insert(id.to_string(), (emitter.clone(), weight));
        }
        Ok((emitter, weight))
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
        if t == "directionalarea" {
            return Err(el.err(
                "a directionalarea emitter must be nested in a <shape> (it emits along the shape's normal)",
            ));
        }
        let (mut props, nested) = Properties::read(el, Dialect::Mitsuba, true)?;
        if plugin::find(emitter::REGISTRY, Family::Emitter, Dialect::Mitsuba, t).is_none() {
            return Err(emitter::unsupported(el, Dialect::Mitsuba));
        }
        // Spot lights and projectors take textures (emitter::spot, emitter::projector;
        // directional refuses them by name); the others do not yet.
        let nested = if matches!(t, "spot" | "projector" | "directional") {
            self.attach_textures(&mut props, nested, true)?
        } else {
            nested
        };
        if let Some(n) = nested.first() {
            return Err(match n.tag.as_str() {
                "medium" | "ref" => n.err("media are not supported yet"),
                "texture" => n.err("textures are not supported yet"),
                tag => n.err(format!("unexpected <{tag}> in an emitter")),
            });
        }
        let emitter = emitter::mitsuba(t, el, &props, &mut self.b)?;
        let weight = emitter::sampling_weight(&props)?;
        props.finish()?;
        self.b.add_weighted_emitter(emitter, weight);
        Ok(())
    }

    /// The BSDF, area emitter and media nested in (or referenced by) a `<shape>`.
    fn shape_parts(&mut self, nested: Vec<&'a Element>) -> Result<ShapeParts<'a>, Error> {
        let mut p = ShapeParts::default();
        for n in nested {
            let (target, via_ref) = if n.tag == "ref" {
                (self.deref(n)?, true)
            } else {
                (n, false)
            };
            if via_ref
                && matches!(n.attr("name"), Some("interior" | "exterior"))
                && target.tag != "medium"
            {
                return Err(Self::misplaced_ref(
                    n,
                    target,
                    &format!("a shape's {}", n.attr("name").unwrap_or("")),
                ));
            }
            match target.tag.as_str() {
                "bsdf" => {
                    if p.bsdf.is_some() {
                        return Err(n.err("a shape can have only one bsdf"));
                    }
                    p.bsdf = Some(self.bsdf(target)?);
                }
                "emitter" => {
                    if p.radiance.is_some() {
                        return Err(n.err("a shape can carry only one emitter"));
                    }
                    p.radiance = Some(self.shape_emitter(n, target, via_ref)?);
                }
                "sensor" if n.tag == "sensor" => {
                    if p.sensor.is_some() {
                        return Err(n.err("a shape can carry only one sensor"));
                    }
                    p.sensor = Some(n);
                }
                "medium" => {
                    let slot = match n.attr("name") {
                        Some("interior") => &mut p.interior,
                        Some("exterior") => &mut p.exterior,
                        other => {
                            return Err(n.err(format!(
                            "a shape's medium is named \"interior\" or \"exterior\", found {:?}",
                            other.unwrap_or("")
                        )))
                        }
                    };
                    if slot.is_some() {
                        return Err(n.err("the shape's medium on that side is given twice"));
                    }
                    *slot = Some(self.medium_of(n, "a <shape>")?);
                }
                _ => return Err(self.unexpected(n, "<shape>")),
            }
        }
        Ok(p)
    }

    /// The emitter a shape carries (`n`, or the `target` of its reference): only an
    /// area emitter.
    fn shape_emitter(
        &mut self,
        n: &'a Element,
        target: &'a Element,
        via_ref: bool,
    ) -> Result<(Emitter, f32), Error> {
        target.check_attrs(&["type", "id", "name"])?;
        let et = target.require("type")?;
        if et == "directionalarea" {
            let (props, nested) = Properties::read(target, Dialect::Mitsuba, false)?;
            if let Some(x) = nested.first() {
                return Err(x.err(format!(
                    "unexpected <{}> in a directionalarea emitter",
                    x.tag
                )));
            }
            return emitter::directionalarea::mitsuba(&props);
        }
        if et != "area" {
            return Err(if via_ref || emitter::is_known(Dialect::Mitsuba, et) {
                n.err(format!(
                    "a shape can only carry an area emitter, not '{et}'"
                ))
            } else {
                emitter::unsupported(target, Dialect::Mitsuba)
            });
        }
        if let (true, Some(id)) = (via_ref, target.attr("id")) {
            if !self.attached_areas.insert(id.to_string()) {
                return Err(n.err(format!(
                    "<ref id=\"{id}\">: the area emitter declared at {}:{} is already attached to another shape; as in Mitsuba, an area emitter belongs to a single shape",
                    target.file.display(),
                    target.line
                )));
            }
        }
        self.area(target)
    }

    /// A `shapegroup` (Mitsuba's shapegroup.cpp): its shapes are loaded as any other
    /// and listed in the group, which only instances make visible.
    fn shapegroup(&mut self, el: &'a Element) -> Result<u32, Error> {
        el.check_attrs(&["type", "id", "name"])?;
        let id = el.attr("id");
        if let Some(&g) = id.and_then(|id| self.group_ids.get(id)) {
            return Ok(g);
        }
        let mut group = ShapeGroup {
            name: id.unwrap_or("").to_string(),
            ..ShapeGroup::default()
        };
        for c in &el.children {
            // A shape declared elsewhere with an id joins the group by reference (and
            // stays where it was declared too, as in Mitsuba).
            let c = if c.tag == "ref" {
                let target = self.deref(c)?;
                if target.tag != "shape" {
                    return Err(Self::misplaced_ref(c, target, "a shapegroup"));
                }
                target
            } else {
                c
            };
            if c.tag != "shape" {
                return Err(c.err(format!(
                    "a shapegroup holds shapes only, found <{}> (Mitsuba: \"Tried to add an unsupported object\")",
                    c.tag
                )));
            }
            match c.attr("type") {
                Some("shapegroup") => {
                    return Err(c.err("a shapegroup inside a shapegroup: nested shape groups are not permitted (as in Mitsuba)"))
                }
                Some("instance") => {
                    return Err(c.err("an instance inside a shapegroup: nested instancing is not permitted (as in Mitsuba)"))
                }
                _ => {}
            }
            let (m0, q0) = (self.b.meshes.len(), self.b.quadrics.len());
            self.shape(c)?;
            if self.b.meshes[m0..].iter().any(|m| m.is_ellipsoids()) {
                return Err(c.err("ellipsoids in a shapegroup are not supported yet"));
            }
            if self.b.meshes[m0..].iter().any(|m| m.is_curves()) {
                return Err(c.err("curves in a shapegroup are not supported yet"));
            }
            let emitters = self.b.meshes[m0..].iter().any(|m| m.emitter.is_some())
                || self.b.quadrics[q0..].iter().any(|q| q.emitter.is_some());
            if emitters {
                return Err(c.err("a shape in a shapegroup carries an emitter: instancing of emitters is not supported (as in Mitsuba)"));
            }
            if !self.shape_sensors.is_empty() {
                return Err(c.err("a shape in a shapegroup carries a sensor: an irradiancemeter measures a shape placed once"));
            }
            group.meshes.extend(m0 as u32..self.b.meshes.len() as u32);
            group
                .quadrics
                .extend(q0 as u32..self.b.quadrics.len() as u32);
        }
        self.groups.push(group);
        let g = (self.groups.len() - 1) as u32;
        if let Some(id) = id {
            self.group_ids.insert(id.to_string(), g);
        }
        Ok(g)
    }

    /// An `instance` (Mitsuba's instance.cpp): one shapegroup, by reference, placed by
    /// `to_world`.
    fn instance(&mut self, el: &'a Element) -> Result<(), Error> {
        el.check_attrs(&["type", "id", "name"])?;
        let (props, nested) = Properties::read(el, Dialect::Mitsuba, false)?;
        let to_world = props.transform("to_world")?;
        props.finish()?;
        let mut group = None;
        for n in nested {
            let target = match n.tag.as_str() {
                "ref" => self.deref(n)?,
                "shape" => n,
                _ => return Err(self.unexpected(n, "an instance")),
            };
            if target.tag != "shape" || target.attr("type") != Some("shapegroup") {
                let what = match target.attr("type") {
                    Some(t) => format!("<{} type=\"{t}\">", target.tag),
                    None => format!("<{}>", target.tag),
                };
                return Err(n.err(format!(
                    "an instance places a shapegroup only, this names a {what} (instances of instances are not permitted, as in Mitsuba)"
                )));
            }
            if group.is_some() {
                return Err(n.err("an instance names one shapegroup only"));
            }
            group = Some(self.shapegroup(target)?);
        }
        let group = group.ok_or_else(|| {
            el.err("an instance needs a shapegroup: <ref id=\"...\"/> naming one")
        })?;
        if !shape::instance::placeable(&to_world) {
            return Err(props.error(
                "to_world",
                "an instance's to_world must be finite, affine and invertible",
            ));
        }
        self.instances.push(Instance { group, to_world });
        Ok(())
    }

    /// A `merge` (shape::merge): its shapes, each loaded as a top-level one; no
    /// parameters; other nested objects ignored, as in Mitsuba 3.9.1.
    fn merge(&mut self, el: &'a Element) -> Result<(), Error> {
        el.check_attrs(&["type", "id", "name"])?;
        let (props, nested) = Properties::read(el, Dialect::Mitsuba, false)?;
        props.finish()?;
        for c in nested.into_iter().filter(|c| c.tag == "shape") {
            self.shape(c)?;
        }
        Ok(())
    }

    fn shape(&mut self, el: &'a Element) -> Result<(), Error> {
        el.check_attrs(&["type", "id", "name"])?;
        let t = el.require("type")?;
        match t {
            "shapegroup" => return self.shapegroup(el).map(|_| ()),
            "instance" => return self.instance(el),
            "merge" => return self.merge(el),
            _ => {}
        }
        let (props, nested) = Properties::read(el, Dialect::Mitsuba, false)?;
        let ShapeParts {
            bsdf,
            sensor,
            radiance,
            interior,
            exterior,
        } = self.shape_parts(nested)?;
        let bsdf = match bsdf {
            Some(b) => b,
            // Mitsuba gives a light without a BSDF a black one (it reflects nothing).
            None if radiance.is_some() => self.b.add_bsdf(Bsdf::Diffuse(bsdf::Diffuse {
                reflectance: Vec3::ZERO,
            })),
            None => self.b.default_bsdf(),
        };
        let flip_normals = props.boolean("flip_normals", false)?;
        let null_bsdf = self.null_bsdfs.contains(&bsdf);
        let (m, to_world, face_normals) = match shape::mitsuba(t, el, &props)? {
            Geometry::Quadric(kind, to_world) => {
                props.finish()?;
                let emitter = radiance.map(|(e, w)| self.b.add_weighted_emitter(e, w));
                self.b.add_quadric(
                    &props,
                    Quadric {
                        kind,
                        to_world,
                        flip_normals,
                        bsdf,
                        emitter,
                        interior,
                        exterior,
                        null_bsdf,
                    },
                )?;
                let index = (self.b.quadrics.len() - 1) as u32;
                return self.shape_sensor(sensor, SensorShape::Quadric(index));
            }
            Geometry::SdfGrid(grid, to_world) => {
                props.finish()?;
                if radiance.is_some() {
                    return Err(el.err(
                        "an sdfgrid cannot carry an area emitter (it has no surface area to sample, as in Mitsuba 3)",
                    ));
                }
                return self.b.add_sdfgrid(
                    &props,
                    *grid,
                    Quadric {
                        kind: shape::QuadricKind::SdfGrid(Default::default()),
                        to_world,
                        flip_normals,
                        bsdf,
                        emitter: None,
                        interior,
                        exterior,
                        null_bsdf,
                    },
                );
            }
            Geometry::Mesh {
                mesh,
                to_world,
                face_normals,
            } => (mesh, to_world, face_normals),
            Geometry::Curves { mesh, to_world } => {
                props.finish()?;
                if radiance.is_some() {
                    return Err(el.err(format!("an area emitter on a {t} is not supported yet")));
                }
                if interior.is_some() || exterior.is_some() {
                    return Err(el.err(format!(
                        "media inside or outside a {t} are not supported yet"
                    )));
                }
                return self.b.add_curves(el, mesh, to_world, bsdf, null_bsdf);
            }
        };
        props.finish()?;
        let emitter = radiance.map(|(e, w)| self.b.add_weighted_emitter(e, w));
        let options = MeshOptions {
            to_world,
            face_normals,
            flip_normals,
            compute_normals: true,
        };
        self.b.add_mesh(el, m, &options, bsdf, emitter)?;
        if let Some(m) = self.b.meshes.last_mut() {
            m.interior = interior;
            m.exterior = exterior;
            m.null_bsdf = null_bsdf;
        }
        let index = (self.b.meshes.len() - 1) as u32;
        self.shape_sensor(sensor, SensorShape::Mesh(index))
    }

    /// A sensor's parts with its medium resolved.
    fn sensor_choice(&mut self, parts: sensor::SensorParts<'a>) -> Result<SceneSensor, Error> {
        let (camera, (sampler, spp), film, medium) = parts;
        let medium = match medium {
            Some(m) => Some(self.medium_of(m, "a <sensor>")?),
            None => None,
        };
        Ok(SceneSensor {
            camera,
            sampler,
            spp,
            film,
            medium,
        })
    }

    /// The sensor nested in a shape (an irradiancemeter measuring it), if any.
    fn shape_sensor(&mut self, el: Option<&'a Element>, shape: SensorShape) -> Result<(), Error> {
        let Some(el) = el else { return Ok(()) };
        el.check_attrs(&["type", "id", "name"])?;
        let t = el.require("type")?;
        if t != "irradiancemeter" {
            return Err(el.err(format!(
                "a shape carries an irradiancemeter only, not a '{t}' sensor (place other sensors at the top level)"
            )));
        }
        let parts = sensor::irradiancemeter::mitsuba(el, shape)?;
        self.shape_sensors.push(parts);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::bsdf::{
        Conductor, Dielectric, Diffuse, Distribution, Plastic, RoughConductor, RoughDielectric,
        RoughPlastic, ThinDielectric,
    };
    use crate::scene::sensor::perspective::fov_x;
    use crate::scene::testutil::{error_at, load, mitsuba, TRI_OBJ};
    use glam::{Mat4, Vec4};

    fn close(a: f32, b: f32) -> bool {
        (a - b).abs() < 1e-4 * (1.0 + b.abs())
    }

    #[test]
    fn sensor_film_sampler() {
        let s = load(
            &[(
                "s.xml",
                r#"<scene version="3.0.0">
  <sensor type="perspective">
    <float name="fov" value="30"/>
    <string name="fov_axis" value="y"/>
    <float name="near_clip" value="0.5"/>
    <float name="far_clip" value="50"/>
    <float name="focus_distance" value="3"/>
    <film type="hdrfilm">
      <integer name="width" value="320"/><integer name="height" value="160"/>
      <rfilter type="gaussian"><float name="stddev" value="0.5"/></rfilter>
      <string name="pixel_format" value="rgb"/><string name="component_format" value="float32"/>
      <boolean name="banner" value="false"/>
    </film>
    <sampler type="stratified"><integer name="sample_count" value="64"/><integer name="seed" value="3"/></sampler>
  </sensor>
  <integrator type="path"><integer name="max_depth" value="8"/><boolean name="hide_emitters" value="true"/></integrator>
</scene>"#,
            )],
            &[],
        )
        .unwrap();
        let c = &s.camera;
        assert_eq!((c.width, c.height, s.spp), (320, 160, 64));
        assert!(close(
            c.fov_x_deg,
            fov_x(30.0, "y", 320, 160).unwrap() as f32
        ));
        assert_eq!((c.near_clip, c.far_clip), (0.5, 50.0));
        assert_eq!(s.integrator.name, "path");
        assert_eq!(s.integrator.line, Some(16));
        assert_eq!(
            s.integrator.params["max_depth"],
            crate::scene::integrator::Param::Integer(8)
        );
        assert_eq!(
            s.integrator.params["hide_emitters"],
            crate::scene::integrator::Param::Bool(true)
        );

        // Defaults: 768x576, fov from focal_length 50mm (diagonal of 35 mm film), 4 spp.
        let s = load(&[("s.xml", &mitsuba(""))], &[]).unwrap();
        assert_eq!((s.camera.width, s.camera.height, s.spp), (768, 576, 4));
        let fd = 2.0 * (43.266615f64 / 100.0).atan();
        let fx = fov_x(fd.to_degrees(), "diagonal", 768, 576).unwrap();
        assert!(
            close(s.camera.fov_x_deg, fx as f32),
            "{}",
            s.camera.fov_x_deg
        );
        assert_eq!((s.camera.near_clip, s.camera.far_clip), (0.01, 10000.0));
        assert_eq!(s.integrator.name, "path");
    }

    #[test]
    fn lookat_then_translate_composes_in_order() {
        let s = load(
            &[(
                "s.xml",
                r#"<scene version="3.0.0"><sensor type="perspective">
  <transform name="to_world">
    <lookat origin="1,0,0" target="1,0,-1" up="0,1,0"/>
    <translate value="0,0,5"/>
  </transform>
</sensor></scene>"#,
            )],
            &[],
        )
        .unwrap();
        let m = s.camera.to_world;
        // dir = (0,0,-1); left = normalize(cross(up, dir)) = (-1,0,0); up = (0,1,0).
        assert!(
            (m * Vec4::new(0.0, 0.0, 1.0, 0.0) - Vec4::new(0.0, 0.0, -1.0, 0.0)).length() < 1e-6
        );
        assert!(
            (m * Vec4::new(1.0, 0.0, 0.0, 0.0) - Vec4::new(-1.0, 0.0, 0.0, 0.0)).length() < 1e-6
        );
        assert!((m * Vec4::new(0.0, 1.0, 0.0, 0.0) - Vec4::Y).length() < 1e-6);
        // The translation applies after the lookat: origin (1,0,0) + (0,0,5).
        assert!((m.w_axis - Vec4::new(1.0, 0.0, 5.0, 1.0)).length() < 1e-6);
    }

    #[test]
    fn transform_ops_on_shapes() {
        let body = r#"
<shape type="rectangle"><transform name="to_world"><translate x="1"/><scale value="2"/></transform></shape>
<shape type="rectangle"><transform name="to_world"><rotate y="1" angle="90"/></transform></shape>
<shape type="rectangle"><transform name="to_world"><matrix value="1 0 0 10  0 1 0 20  0 0 1 30  0 0 0 1"/></transform></shape>
<shape type="rectangle"><transform name="to_world"><scale x="2" y="3"/></transform></shape>"#;
        let s = load(&[("s.xml", &mitsuba(body))], &[]).unwrap();
        // translate then scale: (-1,-1,0) -> (0,-1,0) -> (0,-2,0).
        assert_eq!(s.meshes[0].positions[0], Vec3::new(0.0, -2.0, 0.0));
        // rotation by 90 degrees about +y takes +z to +x.
        assert!((s.meshes[1].normals[0] - Vec3::X).length() < 1e-6);
        assert_eq!(s.meshes[2].positions[0], Vec3::new(9.0, 19.0, 30.0));
        assert!(close(s.meshes[3].area(), 24.0));
    }

    #[test]
    fn defaults_substitution_and_overrides() {
        let xml = r#"<scene version="3.0.0">
  <default name="spp" value="8"/>
  <default name="res" value="32"/>
  <sensor type="perspective">
    <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
    <film type="hdrfilm"><integer name="width" value="$res"/><integer name="height" value="$res"/></film>
  </sensor>
</scene>"#;
        let s = load(&[("s.xml", xml)], &[]).unwrap();
        assert_eq!((s.spp, s.camera.width), (8, 32));
        let s = load(&[("s.xml", xml)], &[("spp", "16")]).unwrap();
        assert_eq!((s.spp, s.camera.width), (16, 32));
        let e = error_at(load(&[("s.xml", xml)], &[("spp", "x")]), "s.xml", 5);
        assert!(e.contains("could not parse integer \"x\""), "{e}");
        let e = error_at(
            load(&[("s.xml", &mitsuba("<shape type=\"$kind\"/>"))], &[]),
            "s.xml",
            3,
        );
        assert!(e.contains("undefined parameter"), "{e}");
    }

    #[test]
    fn include_ref_and_ids() {
        let s = load(
            &[
                (
                    "main.xml",
                    r#"<scene version="3.0.0">
  <include filename="frag/shapes.xml"/>
  <sensor type="perspective"/>
  <emitter type="area" id="light"><rgb name="radiance" value="10"/></emitter>
</scene>"#,
                ),
                (
                    "frag/shapes.xml",
                    r#"<scene version="3.0.0">
  <include filename="bsdfs.xml"/>
  <shape type="rectangle"><ref id="red"/><ref id="light"/></shape>
  <shape type="cube"><ref id="red"/></shape>
  <shape type="disk"/>
  <shape type="rectangle"/>
</scene>"#,
                ),
                (
                    "frag/bsdfs.xml",
                    r#"<scene version="3.0.0"><bsdf type="diffuse" id="red"><rgb name="reflectance" value="0.8, 0.1, 0.1"/></bsdf></scene>"#,
                ),
            ],
            &[],
        )
        .unwrap();
        assert_eq!((s.meshes.len(), s.quadrics.len()), (3, 1));
        // The referenced BSDF is built once and shared; unnamed shapes share the default.
        assert_eq!(s.meshes[0].bsdf, s.meshes[1].bsdf);
        assert_eq!(
            s.bsdfs[s.meshes[0].bsdf as usize],
            Bsdf::Diffuse(Diffuse {
                reflectance: Vec3::new(0.8, 0.1, 0.1)
            })
        );
        assert_eq!(s.meshes[2].bsdf, s.quadrics[0].bsdf);
        assert_eq!(s.bsdfs[s.meshes[2].bsdf as usize], Bsdf::default());
        assert_eq!(s.bsdfs.len(), 2);
        let e = s.meshes[0].emitter.unwrap();
        assert_eq!(
            s.emitters[e as usize],
            Emitter::Area {
                radiance: Vec3::splat(10.0)
            }
        );
        assert_eq!(s.emitters.len(), 1);
        assert!(s.meshes[1].emitter.is_none());
    }

    #[test]
    fn include_errors() {
        let e = error_at(
            load(
                &[
                    ("a.xml", &mitsuba("<include filename=\"b.xml\"/>")),
                    (
                        "b.xml",
                        "<scene version=\"3.0.0\"><include filename=\"a.xml\"/></scene>",
                    ),
                ],
                &[],
            ),
            "b.xml",
            1,
        );
        assert!(e.contains("include cycle"), "{e}");
        let e = error_at(
            load(
                &[("a.xml", &mitsuba("<include filename=\"nope.xml\"/>"))],
                &[],
            ),
            "a.xml",
            3,
        );
        assert!(e.contains("nope.xml") && e.contains("not found"), "{e}");
        let e = error_at(
            load(
                &[
                    ("a.xml", &mitsuba("<include filename=\"b.xml\"/>")),
                    (
                        "b.xml",
                        "<scene version=\"3.0.0\">\n<shape type=\"teapot\"/></scene>",
                    ),
                ],
                &[],
            ),
            "b.xml",
            2,
        );
        assert!(e.contains("unknown shape type 'teapot'"), "{e}");
    }

    #[test]
    fn reference_errors() {
        let e = error_at(
            load(
                &[(
                    "s.xml",
                    &mitsuba("<shape type=\"cube\"><ref id=\"nope\"/></shape>"),
                )],
                &[],
            ),
            "s.xml",
            3,
        );
        assert!(e.contains("unknown id 'nope'"), "{e}");
        let e = error_at(
            load(
                &[(
                    "s.xml",
                    &mitsuba(
                        "<bsdf type=\"diffuse\" id=\"a\"/>\n<bsdf type=\"diffuse\" id=\"a\"/>",
                    ),
                )],
                &[],
            ),
            "s.xml",
            4,
        );
        assert!(e.contains("duplicate id 'a'"), "{e}");
        let e = error_at(
            load(
                &[(
                    "s.xml",
                    &mitsuba("<bsdf type=\"twosided\" id=\"a\"><ref id=\"a\"/></bsdf>"),
                )],
                &[],
            ),
            "s.xml",
            3,
        );
        assert!(e.contains("cycle"), "{e}");
    }

    #[test]
    fn colors_and_spectra() {
        let body = r#"<bsdf type="diffuse" id="a"><rgb name="reflectance" value="0.25"/></bsdf>
<bsdf type="diffuse" id="b"><spectrum name="reflectance" value="0.3"/></bsdf>
<bsdf type="diffuse" id="c"><spectrum name="reflectance" value="400:0.1, 550:0.1, 600:0.9, 700:0.9"/></bsdf>
<bsdf type="diffuse" id="d"><float name="reflectance" value="0.7"/></bsdf>
<bsdf type="twosided" id="e"><bsdf type="diffuse"><rgb name="reflectance" value="0.1,0.2,0.3"/></bsdf></bsdf>
<shape type="sphere"><emitter type="area"><spectrum name="radiance" value="400:0, 500:8, 600:15.6, 700:18.4"/></emitter></shape>"#;
        let s = load(&[("s.xml", &mitsuba(body))], &[]).unwrap();
        let refl = |i: usize| match s.bsdfs[i] {
            Bsdf::Diffuse(Diffuse { reflectance }) => reflectance,
            ref other => panic!("{other:?}"),
        };
        assert_eq!(s.bsdfs[5], Bsdf::TwoSided(Box::new(s.bsdfs[4].clone())));
        assert_eq!(refl(0), Vec3::splat(0.25));
        assert_eq!(refl(1), Vec3::splat(0.3));
        let c = refl(2);
        assert!(c.x > 2.0 * c.z && c.x <= 1.0, "{c}");
        assert_eq!(refl(3), Vec3::splat(0.7));
        assert_eq!(refl(4), Vec3::new(0.1, 0.2, 0.3));
        let Emitter::Area { radiance } = s.emitters[0] else {
            panic!()
        };
        // Emission is not clamped to 1; it is warm (red > blue).
        assert!(radiance.x > 1.0 && radiance.x > radiance.z, "{radiance}");
        let e = error_at(
            load(&[("s.xml", &mitsuba("<bsdf type=\"diffuse\"><spectrum name=\"reflectance\" value=\"500:0.1, 400:0.2\"/></bsdf>"))], &[]),
            "s.xml",
            3,
        );
        assert!(e.contains("increasing"), "{e}");
        let e = error_at(
            load(
                &[(
                    "s.xml",
                    &mitsuba(
                        "<bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"1,2\"/></bsdf>",
                    ),
                )],
                &[],
            ),
            "s.xml",
            3,
        );
        assert!(e.contains("1 or 3 values"), "{e}");
    }

    #[test]
    fn emitters() {
        let body = r#"<emitter type="point"><point name="position" value="1,2,3"/><rgb name="intensity" value="5"/></emitter>
<emitter type="point"><transform name="to_world"><translate value="4,5,6"/></transform></emitter>
<emitter type="constant"><rgb name="radiance" value="0.5"/></emitter>"#;
        let s = load(&[("s.xml", &mitsuba(body))], &[]).unwrap();
        assert_eq!(
            s.emitters[0],
            Emitter::Point {
                position: Vec3::new(1.0, 2.0, 3.0),
                intensity: Vec3::splat(5.0)
            }
        );
        assert_eq!(
            s.emitters[1],
            Emitter::Point {
                position: Vec3::new(4.0, 5.0, 6.0),
                intensity: Vec3::ONE
            }
        );
        assert_eq!(
            s.emitters[2],
            Emitter::Constant {
                radiance: Vec3::splat(0.5)
            }
        );
        let spot = r#"<emitter type="spot"><transform name="to_world"><lookat origin="0,5,0" target="0,0,0" up="0,0,1"/></transform>
    <float name="cutoff_angle" value="30"/></emitter>"#;
        let s = load(&[("s.xml", &mitsuba(spot))], &[]).unwrap();
        let Emitter::Spot {
            position,
            axis,
            cutoff_deg,
            beam_width_deg,
            ..
        } = s.emitters[0]
        else {
            panic!("{:?}", s.emitters[0]);
        };
        assert!((position - Vec3::new(0.0, 5.0, 0.0)).length() < 1e-6);
        assert!((axis - Vec3::new(0.0, -1.0, 0.0)).length() < 1e-6);
        assert_eq!((cutoff_deg, beam_width_deg), (30.0, 22.5));
        let bad = r#"<emitter type="spot"><float name="cutoff_angle" value="10"/><float name="beam_width" value="20"/></emitter>"#;
        let e = error_at(load(&[("s.xml", &mitsuba(bad))], &[]), "s.xml", 3);
        assert!(e.contains("beam_width"), "{e}");
        let e = error_at(
            load(&[("s.xml", &mitsuba("<emitter type=\"envmap\"/>"))], &[]),
            "s.xml",
            3,
        );
        assert!(e.contains("envmap needs a 'filename'"), "{e}");
        let e = error_at(
            load(&[("s.xml", &mitsuba("<emitter type=\"lamp\"/>"))], &[]),
            "s.xml",
            3,
        );
        assert!(e.contains("unknown emitter type 'lamp'"), "{e}");
        let e = error_at(
            load(&[("s.xml", &mitsuba("<emitter type=\"area\"/>"))], &[]),
            "s.xml",
            3,
        );
        assert!(e.contains("nested in a <shape>"), "{e}");
    }

    #[test]
    fn spheres() {
        let body = r#"<shape type="sphere"><point name="center" value="1,0,0"/><float name="radius" value="2"/>
  <transform name="to_world"><scale value="3"/><rotate z="1" angle="90"/><translate value="0,0,1"/></transform>
  <boolean name="flip_normals" value="true"/></shape>
<shape type="sphere"><transform name="to_world">
  <scale value="1,2,1"/></transform></shape>"#;
        let e = error_at(load(&[("s.xml", &mitsuba(body))], &[]), "s.xml", 6);
        assert!(e.contains("non-uniform"), "{e}");
        let s = load(
            &[("s.xml", &mitsuba(&body[..body.find("\n<shape").unwrap()]))],
            &[],
        )
        .unwrap();
        let sp = &s.quadrics[0];
        assert!(
            (sp.origin() - Vec3::new(0.0, 3.0, 1.0)).length() < 1e-5,
            "{}",
            sp.origin()
        );
        assert!(close(sp.radius(), 6.0) && sp.flip_normals && !sp.mirrored());
    }

    #[test]
    fn obj_options() {
        let files = |body: &str| {
            vec![
                ("s.xml".to_string(), mitsuba(body)),
                ("m/t.obj".to_string(), TRI_OBJ.to_string()),
            ]
        };
        let run = |body: &str| {
            let f = files(body);
            let refs: Vec<(&str, &str)> = f.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
            load(&refs, &[])
        };
        let s =
            run(r#"<shape type="obj"><string name="filename" value="m/t.obj"/></shape>"#).unwrap();
        let m = &s.meshes[0];
        assert_eq!(m.uvs[2], glam::Vec2::new(0.0, 0.0)); // v flipped: 1 - 1
        assert_eq!(m.normals.len(), 3);
        let s = run(
            r#"<shape type="obj"><string name="filename" value="m/t.obj"/>
<boolean name="flip_tex_coords" value="false"/><boolean name="face_normals" value="true"/>
<boolean name="flip_normals" value="true"/></shape>"#,
        )
        .unwrap();
        let m = &s.meshes[0];
        assert_eq!(m.uvs[2], glam::Vec2::new(0.0, 1.0));
        assert!(m.normals.is_empty());
        // flip_normals keeps the winding (as Mitsuba): the kernels negate the normals.
        assert_eq!(m.indices[0], [0, 1, 2]);
        assert!(m.flip_normals);
        let e = error_at(
            run("<shape type=\"obj\">\n<string name=\"filename\" value=\"m/none.obj\"/></shape>"),
            "s.xml",
            4,
        );
        assert!(e.contains("m/none.obj") && e.contains("not found"), "{e}");
        let e = error_at(run("<shape type=\"obj\"/>"), "s.xml", 3);
        assert!(e.contains("needs a 'filename'"), "{e}");
    }

    /// Every BSDF model with its parameters and defaults.
    #[test]
    fn bsdf_models() {
        let body = r#"<bsdf type="conductor" id="c0"/>
<bsdf type="conductor" id="c1"><string name="material" value="Au"/><rgb name="specular_reflectance" value="0.5"/></bsdf>
<bsdf type="conductor" id="c2"><rgb name="eta" value="0.2, 0.9, 1.1"/><rgb name="k" value="3.9, 2.4, 2.1"/></bsdf>
<bsdf type="roughconductor" id="r0"/>
<bsdf type="roughconductor" id="r1"><string name="distribution" value="GGX"/><float name="alpha_u" value="0.05"/><float name="alpha_v" value="0.3"/><string name="material" value="Cu"/><boolean name="sample_visible" value="true"/></bsdf>
<bsdf type="roughconductor" id="r2"><float name="alpha" value="0"/></bsdf>
<bsdf type="dielectric" id="d0"/>
<bsdf type="dielectric" id="d1"><string name="int_ior" value="Water"/><float name="ext_ior" value="1.5"/><rgb name="specular_transmittance" value="0.9"/></bsdf>
<bsdf type="roughdielectric" id="d2"><string name="distribution" value="ggx"/><float name="alpha" value="0.3"/><string name="int_ior" value="diamond"/></bsdf>
<bsdf type="plastic" id="p0"/>
<bsdf type="plastic" id="p1"><rgb name="diffuse_reflectance" value="0.1, 0.27, 0.36"/><float name="int_ior" value="1.9"/><boolean name="nonlinear" value="true"/></bsdf>
<bsdf type="roughplastic" id="p2"><string name="distribution" value="ggx"/><float name="alpha" value="0.2"/></bsdf>
<bsdf type="twosided" id="t"><bsdf type="roughplastic"/></bsdf>"#;
        let s = load(&[("s.xml", &mitsuba(body))], &[]).unwrap();
        let b = &s.bsdfs;
        assert_eq!(
            b[0],
            Bsdf::Conductor(Conductor {
                eta: Vec3::ZERO,
                k: Vec3::ONE,
                specular_reflectance: Vec3::ONE
            })
        );
        let Bsdf::Conductor(Conductor {
            eta,
            k,
            specular_reflectance,
        }) = b[1]
        else {
            panic!("{:?}", b[1])
        };
        // Gold: low η and high κ in red (yellow colour).
        assert!(eta.x < 0.2 && eta.z > 1.4 && k.x > 3.9, "{eta} {k}");
        assert_eq!(specular_reflectance, Vec3::splat(0.5));
        assert!(
            matches!(b[2], Bsdf::Conductor(Conductor { eta, .. }) if eta == Vec3::new(0.2, 0.9, 1.1))
        );
        assert!(matches!(
            b[3],
            Bsdf::RoughConductor(RoughConductor { distribution: Distribution::Beckmann, alpha_u, alpha_v, .. })
                if alpha_u == 0.1 && alpha_v == 0.1
        ));
        assert!(matches!(
            b[4],
            Bsdf::RoughConductor(RoughConductor { distribution: Distribution::Ggx, alpha_u, alpha_v, eta, .. })
                if alpha_u == 0.05 && alpha_v == 0.3 && eta.y > 0.9
        ));
        // alpha = 0 is clamped to 1e-4 as in Mitsuba.
        assert!(
            matches!(b[5], Bsdf::RoughConductor(RoughConductor { alpha_u, .. }) if alpha_u == 1e-4)
        );
        assert!(
            matches!(b[6], Bsdf::Dielectric(Dielectric { eta, .. }) if (eta - 1.5046 / 1.000277).abs() < 1e-6)
        );
        assert!(matches!(
            b[7],
            Bsdf::Dielectric(Dielectric { eta, specular_transmittance, .. })
                if (eta - 1.333 / 1.5).abs() < 1e-6 && specular_transmittance == Vec3::splat(0.9)
        ));
        assert!(matches!(
            b[8],
            Bsdf::RoughDielectric(RoughDielectric { distribution: Distribution::Ggx, alpha_u, eta, .. })
                if alpha_u == 0.3 && (eta - 2.419 / 1.000277).abs() < 1e-5
        ));
        assert_eq!(
            b[9],
            Bsdf::Plastic(Plastic {
                diffuse_reflectance: Vec3::splat(0.5),
                specular_reflectance: Vec3::ONE,
                eta: 1.49 / 1.000277,
                nonlinear: false
            })
        );
        assert!(
            matches!(b[10], Bsdf::Plastic(Plastic { nonlinear: true, eta, .. }) if (eta - 1.9 / 1.000277).abs() < 1e-6)
        );
        assert!(matches!(
            b[11],
            Bsdf::RoughPlastic(RoughPlastic { distribution: Distribution::Ggx, alpha, .. }) if alpha == 0.2
        ));
        assert!(
            matches!(&b[13], Bsdf::TwoSided(inner) if matches!(**inner, Bsdf::RoughPlastic(RoughPlastic { .. })))
        );
    }

    #[test]
    fn normalmap_options_default_as_mitsuba_3_9() {
        use crate::gpu::layout::{BsdfRecord, BSDF_NORMALMAP_FLIP, BSDF_NORMALMAP_SHADOWING};
        let map = r#"<texture type="checkerboard" name="normalmap"/><bsdf type="diffuse"/>"#;
        let body = format!(
            r#"<bsdf type="normalmap" id="a">{map}</bsdf>
<bsdf type="normalmap" id="b"><boolean name="flip_invalid_normals" value="false"/><boolean name="use_shadowing_function" value="false"/>{map}</bsdf>"#
        );
        let s = load(&[("s.xml", &mitsuba(&body))], &[]).unwrap();
        let flags: Vec<(bool, bool, u32)> = s
            .bsdfs
            .iter()
            .filter_map(|b| match b {
                Bsdf::NormalMap {
                    flip_invalid_normals,
                    use_shadowing_function,
                    ..
                } => Some((
                    *flip_invalid_normals,
                    *use_shadowing_function,
                    BsdfRecord::from(b).flags,
                )),
                _ => None,
            })
            .collect();
        let both = BSDF_NORMALMAP_FLIP | BSDF_NORMALMAP_SHADOWING;
        assert_eq!(flags, vec![(true, true, both), (false, false, 0)]);
    }

    /// Every named conductor of Mitsuba loads (the issue's example `a-C` among them,
    /// with Mitsuba's RGB values), and `eta` / `k` as a float or spectrum.
    #[test]
    fn named_conductors_and_spectral_eta() {
        let mut body: String = crate::scene::bsdf::CONDUCTOR_PRESETS
            .iter()
            .map(|p| format!("<bsdf type=\"roughconductor\"><string name=\"material\" value=\"{}\"/></bsdf>\n", p.0))
            .collect();
        body += r#"<bsdf type="conductor"><string name="material" value="a-C"/></bsdf>
<bsdf type="conductor"><spectrum name="eta" value="400:1.5, 700:1.5"/><float name="k" value="2"/></bsdf>"#;
        let s = load(&[("s.xml", &mitsuba(&body))], &[]).unwrap();
        let n = crate::scene::bsdf::CONDUCTOR_PRESETS.len();
        assert_eq!(s.bsdfs.len(), n + 2);
        let Bsdf::Conductor(Conductor { eta, k, .. }) = s.bsdfs[n] else {
            panic!("{:?}", s.bsdfs[n])
        };
        // Mitsuba 3.9.1 (scalar_rgb) prints eta [2.94405, 2.22714, 1.96816], k
        // [0.887465, 0.799299, 0.81529] for a-C.
        assert!(
            (eta - Vec3::new(2.94405, 2.22714, 1.96816))
                .abs()
                .max_element()
                < 1e-5,
            "{eta}"
        );
        assert!(
            (k - Vec3::new(0.887465, 0.799299, 0.81529))
                .abs()
                .max_element()
                < 1e-5,
            "{k}"
        );
        let Bsdf::Conductor(Conductor { eta, k, .. }) = s.bsdfs[n + 1] else {
            panic!("{:?}", s.bsdfs[n + 1])
        };
        assert!((eta - Vec3::splat(1.5)).abs().max_element() < 0.02, "{eta}");
        assert_eq!(k, Vec3::splat(2.0));
    }

    #[test]
    fn bsdf_errors() {
        let cases: &[(&str, u32, &str)] = &[
            ("<bsdf type=\"roughconductor\">\n<string name=\"distribution\" value=\"phong\"/></bsdf>", 4, "invalid distribution 'phong'"),
            ("<bsdf type=\"roughconductor\">\n<float name=\"alpha\" value=\"-0.1\"/></bsdf>", 4, "must be a finite number >= 0, found -0.1"),
            ("<bsdf type=\"roughdielectric\">\n<float name=\"alpha_u\" value=\"0.1\"/></bsdf>", 3, "both 'alpha_u' and 'alpha_v'"),
            ("<bsdf type=\"roughconductor\"><float name=\"alpha\" value=\"0.1\"/>\n<float name=\"alpha_u\" value=\"0.1\"/></bsdf>", 3, "either 'alpha' or 'alpha_u'"),
            ("<bsdf type=\"roughplastic\">\n<float name=\"alpha_u\" value=\"0.1\"/><float name=\"alpha_v\" value=\"0.2\"/></bsdf>", 4, "does not support anisotropic"),
            ("<bsdf type=\"conductor\">\n<string name=\"material\" value=\"Unobtainium\"/></bsdf>", 4, "unknown conductor material 'Unobtainium'"),
            ("<bsdf type=\"conductor\">\n<string name=\"material\" value=\"Unobtainium\"/></bsdf>", 4, "known: Ag, Al, AlAs, AlAs_palik, AlSb"),
            ("<bsdf type=\"roughconductor\">\n<string name=\"material\" value=\"Unobtainium\"/></bsdf>", 4, "W, a-C, d-C, d-C_palik, none"),
            ("<bsdf type=\"conductor\">\n<string name=\"material\" value=\"au\"/></bsdf>", 4, "unknown conductor material 'au' (did you mean 'Au'?)"),
            // eta and k may be textures (as in Mitsuba), but not beside a named material.
            ("<bsdf type=\"conductor\">\n<string name=\"material\" value=\"Au\"/><texture type=\"checkerboard\" name=\"eta\"/></bsdf>", 4, "not both"),
            ("<bsdf type=\"roughconductor\">\n<string name=\"material\" value=\"Cu\"/><texture type=\"checkerboard\" name=\"k\"/></bsdf>", 4, "not both"),
            ("<bsdf type=\"conductor\">\n<string name=\"material\" value=\"Au\"/><rgb name=\"eta\" value=\"1\"/></bsdf>", 4, "not both"),
            ("<bsdf type=\"dielectric\">\n<string name=\"int_ior\" value=\"glass\"/></bsdf>", 4, "unknown index of refraction 'glass'"),
            ("<bsdf type=\"dielectric\">\n<float name=\"int_ior\" value=\"-1.5\"/></bsdf>", 4, "must be positive"),
            ("<bsdf type=\"dielectric\">\n<rgb name=\"int_ior\" value=\"1.5\"/></bsdf>", 4, "must be a float or a material name"),
            ("<bsdf type=\"roughdielectric\">\n<float name=\"int_ior\" value=\"1.2\"/><float name=\"ext_ior\" value=\"1.2\"/></bsdf>", 4, "must differ"),
            ("<bsdf type=\"plastic\">\n<float name=\"alpha\" value=\"0.1\"/></bsdf>", 4, "unknown parameter 'alpha' for bsdf 'plastic'"),
            ("<bsdf type=\"plastic\">\n<texture type=\"bitmap\"/></bsdf>", 4, "needs a name"),
            ("<bsdf type=\"plastic\">\n<texture type=\"checkerboard\" name=\"int_ior\"/></bsdf>", 4, "'int_ior' of bsdf 'plastic' cannot be a texture"),
            ("<bsdf type=\"diffuse\"><texture type=\"bitmap\" name=\"reflectance\">\n<string name=\"filename\" value=\"missing.png\"/></texture></bsdf>", 4, "missing.png' not found"),
            ("<bsdf type=\"diffuse\"><texture type=\"checkerboard\" name=\"reflectance\">\n<string name=\"wrap_mode\" value=\"x\"/></texture></bsdf>", 4, "unknown parameter 'wrap_mode'"),
            ("<bsdf type=\"diffuse\"><texture type=\"noise\" name=\"reflectance\">\n<integer name=\"octaves\" value=\"0\"/></texture></bsdf>", 4, "octaves must be in"),
            ("<bsdf type=\"diffuse\">\n<texture type=\"wood\" name=\"reflectance\"/></bsdf>", 4, "unknown texture type 'wood'"),
            ("<bsdf type=\"normalmap\">\n<bsdf type=\"diffuse\"/></bsdf>", 3, "normalmap needs a <texture"),
            ("<bsdf type=\"diffuse\">\n<ref name=\"reflectance\" id=\"nothere\"/></bsdf>", 4, "unknown id 'nothere'"),
            ("<bsdf type=\"twosided\"><bsdf type=\"dielectric\"/></bsdf>", 3, "without transmission"),
        ];
        for (body, line, msg) in cases {
            let e = error_at(load(&[("s.xml", &mitsuba(body))], &[]), "s.xml", *line);
            assert!(e.contains(msg), "{e}\n  wanted: {msg}");
        }
    }

    #[test]
    fn composite_bsdfs() {
        use crate::scene::bsdf::composite::Weight;
        let xml = r#"<bsdf type="diffuse" id="d"><rgb name="reflectance" value="0.1,0.2,0.3"/></bsdf>
<bsdf type="blendbsdf" id="b"><float name="weight" value="0.25"/><ref id="d"/><bsdf type="conductor"/></bsdf>
<bsdf type="mask" id="m"><texture type="checkerboard" name="opacity"/><ref id="b"/></bsdf>
<bsdf type="twosided" id="t"><ref id="d"/><bsdf type="diffuse"/></bsdf>
<bsdf type="bumpmap" id="u"><texture type="checkerboard" name="h"/><ref id="t"/></bsdf>
<bsdf type="twosided" id="t1"><ref id="b"/></bsdf>"#;
        let s = load(&[("s.xml", &mitsuba(xml))], &[]).expect("loads");
        let b = &s.bsdfs;
        let d = b[0].clone();
        let Bsdf::Blend { weight, bsdfs } = &b[2] else {
            panic!("{:?}", b[2])
        };
        assert_eq!(*weight, Weight::constant(0.25));
        assert_eq!(bsdfs[0], d);
        assert!(matches!(bsdfs[1], Bsdf::Conductor(..)));
        let Bsdf::Mask { opacity, bsdf } = &b[3] else {
            panic!("{:?}", b[3])
        };
        assert_eq!(opacity.texture, Some(0));
        assert_eq!(**bsdf, b[2]);
        assert!(matches!(&b[5], Bsdf::TwoSidedPair(pair) if pair[0] == d));
        let Bsdf::BumpMap { params, bsdf } = &b[6] else {
            panic!("{:?}", b[6])
        };
        assert_eq!(
            (
                params.texture,
                params.scale,
                params.flip_invalid_normals,
                params.use_shadowing_function
            ),
            (1, 1.0, true, true)
        );
        assert_eq!(**bsdf, b[5]);
        // A twosided around a composite nests it whole.
        assert!(matches!(&b[7], Bsdf::TwoSided(inner) if **inner == b[2]));
        let cases: &[(&str, u32, &str)] = &[
            ("<bsdf type=\"mask\">\n<bsdf type=\"diffuse\"/></bsdf>", 3, "mask needs an 'opacity'"),
            ("<bsdf type=\"mask\"><float name=\"opacity\" value=\"0.5\"/></bsdf>", 3, "mask needs exactly one nested <bsdf>, found 0"),
            ("<bsdf type=\"mask\">\n<string name=\"opacity\" value=\"x\"/><bsdf type=\"diffuse\"/></bsdf>", 4, "'opacity' of bsdf 'mask' must be a float"),
            ("<bsdf type=\"blendbsdf\"><float name=\"weight\" value=\"0.5\"/><bsdf type=\"diffuse\"/></bsdf>", 3, "blendbsdf needs exactly 2 nested <bsdf>s, found 1"),
            ("<bsdf type=\"blendbsdf\"><bsdf type=\"diffuse\"/><bsdf type=\"diffuse\"/></bsdf>", 3, "blendbsdf needs a 'weight'"),
            ("<bsdf type=\"bumpmap\"><bsdf type=\"diffuse\"/></bsdf>", 3, "bumpmap needs one nested <texture>"),
            ("<bsdf type=\"bumpmap\"><texture type=\"checkerboard\" name=\"a\"/>\n<texture type=\"checkerboard\" name=\"b\"/><bsdf type=\"diffuse\"/></bsdf>", 4, "exactly one nested <texture>"),
            ("<bsdf type=\"twosided\"><bsdf type=\"diffuse\"/><bsdf type=\"diffuse\"/><bsdf type=\"diffuse\"/></bsdf>", 3, "one or two nested"),
            ("<bsdf type=\"twosided\"><bsdf type=\"diffuse\"/>\n<bsdf type=\"dielectric\"/></bsdf>", 4, "without transmission"),
            ("<bsdf type=\"twosided\">\n<bsdf type=\"mask\"><float name=\"opacity\" value=\"0.5\"/><bsdf type=\"diffuse\"/></bsdf></bsdf>", 4, "without transmission"),
            ("<bsdf type=\"mask\"><float name=\"opacity\" value=\"0.5\"/>\n<ref id=\"nothere\"/></bsdf>", 4, "unknown id 'nothere'"),
            ("<bsdf type=\"normalmap\"><texture type=\"checkerboard\" name=\"normalmap\"/>\n<bsdf type=\"mask\"><float name=\"opacity\" value=\"0.5\"/><bsdf type=\"diffuse\"/></bsdf></bsdf>", 4, "normalmap around a composite"),
        ];
        for (body, line, msg) in cases {
            let e = error_at(load(&[("s.xml", &mitsuba(body))], &[]), "s.xml", *line);
            assert!(e.contains(msg), "{e}\n  wanted: {msg}");
        }
    }

    #[test]
    fn parameter_errors() {
        let cases: &[(&str, u32, &str)] = &[
            ("<shape type=\"cube\">\n<float name=\"radius\" value=\"1\"/></shape>", 4, "unknown parameter 'radius' for shape 'cube'"),
            ("<shape type=\"sphere\">\n<string name=\"radius\" value=\"1\"/></shape>", 4, "parameter 'radius' of shape 'sphere' must be a float, found a string"),
            ("<shape type=\"sphere\">\n<float name=\"radius\" value=\"abc\"/></shape>", 4, "could not parse float \"abc\""),
            ("<shape type=\"sphere\">\n<float name=\"radius\" value=\"nan\"/></shape>", 4, "could not parse float \"nan\""),
            ("<shape type=\"sphere\"><float name=\"radius\" value=\"1\"/>\n<float name=\"radius\" value=\"2\"/></shape>", 4, "given twice"),
            ("<bsdf type=\"polarizer\"/>", 3, "bsdf type 'polarizer' is not supported yet"),
            ("<bsdf type=\"thindielectric\"><texture type=\"checkerboard\" name=\"int_ior\"/></bsdf>", 3, "'int_ior' of bsdf 'thindielectric' cannot be a texture"),
            ("<bsdf type=\"velvet\"/>", 3, "unknown bsdf type 'velvet'"),
            ("<shape type=\"cylinder\">\n<float name=\"radius\" value=\"0\"/></shape>", 4, "cylinder radius must be positive"),
            ("<shape type=\"cylinder\">\n<point name=\"p1\" value=\"0,0,0\"/></shape>", 4, "p0 and p1 apart"),
            ("<shape type=\"cylinder\"><transform name=\"to_world\"><scale value=\"1,2,1\"/></transform></shape>", 3, "non-uniform scale across the axis"),
            ("<shape type=\"disk\"><transform name=\"to_world\"><scale value=\"1,0,1\"/></transform></shape>", 3, "collapses the disk"),
            ("<shape type=\"serialized\">\n<string name=\"filename\" value=\"m.serialized\"/></shape>", 4, "m.serialized' not found"),
            ("<medium type=\"homogeneous\"><float name=\"albedo\" value=\"2\"/></medium>", 3, "albedo must be in [0, 1]"),
            ("<shape type=\"cube\"><bsdf type=\"measured\"/></shape>", 3, "measured BSDF needs a 'filename'"),
            ("<shape type=\"cube\" foo=\"1\"/>", 3, "unexpected attribute 'foo'"),
            ("<shape type=\"cube\"><transform name=\"to_world\"><lookat origin=\"0,0,0\" target=\"0,0,0\"/></transform></shape>", 3, "invalid <lookat>"),
            ("<shape type=\"cube\"><transform name=\"to_world\"><matrix value=\"1 2 3\"/></transform></shape>", 3, "16 numbers"),
            ("<shape type=\"cube\"><transform name=\"to_world\"><rotate angle=\"3\"/></transform></shape>", 3, "non-zero axis"),
        ];
        for (body, line, msg) in cases {
            let e = error_at(load(&[("s.xml", &mitsuba(body))], &[]), "s.xml", *line);
            assert!(e.contains(msg), "{e}\n  wanted: {msg}");
        }
        let e = error_at(
            load(
                &[(
                    "s.xml",
                    "<scene version=\"3.0.0\">\n<sensor type=\"batch\"/></scene>",
                )],
                &[],
            ),
            "s.xml",
            2,
        );
        assert!(
            e.contains("a batch sensor needs at least one child <sensor>"),
            "{e}"
        );
        let e = error_at(
            load(&[("s.xml", "<scene version=\"3.0.0\">\n<sensor type=\"perspective\">\n<float name=\"fov\" value=\"30\"/>\n<string name=\"fov_axis\" value=\"z\"/></sensor></scene>")], &[]),
            "s.xml",
            4,
        );
        assert!(e.contains("fov_axis"), "{e}");
        let e = error_at(
            load(
                &[(
                    "s.xml",
                    "<scene version=\"3.0.0\">\n<shape type=\"cube\"/></scene>",
                )],
                &[],
            ),
            "s.xml",
            1,
        );
        assert!(e.contains("no <sensor>"), "{e}");
    }

    #[test]
    fn search_paths_and_moment() {
        // <path> adds a folder (relative to the scene file) that file names and
        // includes are also searched in; the moment integrator stands for its inner one.
        let main = r#"<scene version="2.0.0">
  <path value="assets"/>
  <include filename="frag.xml"/>
  <integrator type="moment"><integrator type="volpathmis"><integer name="max_depth" value="16"/></integrator></integrator>
  <sensor type="perspective"/>
</scene>"#;
        let frag = r#"<scene version="2.0.0">
  <shape type="obj"><string name="filename" value="meshes/tri.obj"/></shape>
</scene>"#;
        let s = load(
            &[
                ("main.xml", main),
                ("assets/frag.xml", frag),
                ("assets/meshes/tri.obj", TRI_OBJ),
            ],
            &[],
        )
        .unwrap();
        assert_eq!(s.meshes.len(), 1);
        assert_eq!(s.integrator.name, "volpathmis");
        assert_eq!(
            s.integrator.params.get("max_depth"),
            Some(&crate::scene::integrator::Param::Integer(16))
        );
        let e = error_at(
            load(&[("s.xml", &mitsuba("<path value=\"nope\"/>"))], &[]),
            "s.xml",
            3,
        );
        assert!(e.contains("<path>: folder") && e.contains("nope"), "{e}");
        for inner in [
            "",
            "<integrator type=\"path\"/><integrator type=\"direct\"/>",
        ] {
            let e = error_at(
                load(
                    &[(
                        "s.xml",
                        &mitsuba(&format!("<integrator type=\"moment\">{inner}</integrator>")),
                    )],
                    &[],
                ),
                "s.xml",
                3,
            );
            assert!(e.contains("exactly one nested <integrator>"), "{e}");
        }
    }

    #[test]
    fn thindielectric_parameters() {
        let s = load(
            &[(
                "s.xml",
                &mitsuba(
                    r#"<bsdf type="thindielectric" id="a"/>
<bsdf type="thindielectric" id="b"><string name="int_ior" value="water"/><float name="ext_ior" value="1"/>
<rgb name="specular_transmittance" value="0.5"/></bsdf>"#,
                ),
            )],
            &[],
        )
        .unwrap();
        assert_eq!(
            s.bsdfs[0],
            Bsdf::ThinDielectric(ThinDielectric {
                eta: 1.5046 / 1.000277,
                specular_reflectance: Vec3::ONE,
                specular_transmittance: Vec3::ONE,
            })
        );
        assert_eq!(
            s.bsdfs[1],
            Bsdf::ThinDielectric(ThinDielectric {
                eta: 1.333,
                specular_reflectance: Vec3::ONE,
                specular_transmittance: Vec3::splat(0.5),
            })
        );
        assert!(s.bsdfs[0].transmits() && s.bsdfs[0].is_thin_dielectric());
    }

    #[test]
    fn dialect_detection() {
        let e = error_at(
            load(
                &[("s.xml", "<scene>\n<sensor type=\"perspective\"/></scene>")],
                &[],
            ),
            "s.xml",
            1,
        );
        assert!(e.contains("no version attribute"), "{e}");
        let e = error_at(
            load(
                &[("s.xml", "<scene><integrator type=\"ao\"/></scene>")],
                &[],
            ),
            "s.xml",
            1,
        );
        assert!(e.contains("cannot tell"), "{e}");
        let e = error_at(
            load(&[("s.xml", "<scene version=\"three\"/>")], &[]),
            "s.xml",
            1,
        );
        assert!(e.contains("version"), "{e}");
        let e = error_at(
            load(
                &[("s.xml", "<scene version=\"3.0.0\">\n<sensor>\n</scene>")],
                &[],
            ),
            "s.xml",
            3,
        );
        assert!(e.contains("malformed XML"), "{e}");
        let e = error_at(load(&[("s.xml", "<world/>")], &[]), "s.xml", 1);
        assert!(e.contains("<scene>"), "{e}");
        let _ = Mat4::IDENTITY;
    }
}
