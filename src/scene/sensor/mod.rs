//! Sensors: the camera of a scene, one file per plugin type (Mitsuba 3's
//! `src/sensors/`; Nori's `<camera>`), and [`REGISTRY`], every sensor type of both
//! dialects. A Mitsuba sensor nests the film ([`crate::scene::film`]) and the sampler
//! ([`crate::scene::sampler`]).

pub mod batch;
pub mod distant;
pub mod irradiancemeter;
pub mod orthographic;
pub mod perspective;
pub mod radiancemeter;
pub mod thinlens;

use super::plugin::{self, Family, PluginDoc};
use super::sampler::Sampler;
use super::xml::{Dialect, Element};
use super::{Camera, Error, Film};

/// Every sensor type of both dialects.
pub const REGISTRY: &[PluginDoc] = &[
    perspective::MITSUBA,
    thinlens::MITSUBA,
    orthographic::MITSUBA,
    radiancemeter::MITSUBA,
    irradiancemeter::MITSUBA,
    distant::MITSUBA,
    batch::MITSUBA,
    perspective::NORI,
];

/// One sensor of a scene, with what it nests: its camera, sampler and sample count,
/// film, and the medium it sits in. A Mitsuba scene may hold several
/// ([`crate::scene::Scene::sensors`]).
#[derive(Debug, Clone)]
pub struct SceneSensor {
    pub camera: Camera,
    pub sampler: Sampler,
    pub spp: u32,
    pub film: Film,
    pub medium: Option<u32>,
}

/// Default `<film>` size.
const FILM_WIDTH: u32 = 768;
const FILM_HEIGHT: u32 = 576;

/// What a `<sensor>` says: the camera, its sampler and sample count, its film and the
/// `<medium>` (or `<ref>` to one) it sits in.
pub type SensorParts<'a> = (Camera, (Sampler, u32), Film, Option<&'a Element>);

/// A Mitsuba `<sensor>`: the registry's dispatch.
pub fn mitsuba(el: &Element) -> Result<SensorParts<'_>, Error> {
    el.check_attrs(&["type", "id", "name"])?;
    match el.require("type")? {
        "perspective" => perspective::mitsuba(el),
        "thinlens" => thinlens::mitsuba(el),
        "orthographic" => orthographic::mitsuba(el),
        "batch" => batch::mitsuba(el),
        "radiancemeter" => perspective::projective(el, "radiancemeter"),
        "distant" => perspective::projective(el, "distant"),
        "irradiancemeter" => Err(el
            .err("an irradiancemeter measures the shape it is nested in: put it inside a <shape>")),
        _ => Err(plugin::unsupported(
            el,
            Family::Sensor,
            Dialect::Mitsuba,
            REGISTRY,
        )),
    }
}

/// A Nori `<camera>` and its film.
pub fn nori(el: &Element) -> Result<(Camera, Film), Error> {
    el.check_attrs(&["type"])?;
    match el.require("type")? {
        "perspective" => perspective::nori(el),
        _ => Err(plugin::unsupported(
            el,
            Family::Sensor,
            Dialect::Nori,
            REGISTRY,
        )),
    }
}

/// The film's size and the rest of it ([`Film::from_mitsuba`]).
fn film(el: &Element) -> Result<(u32, u32, Film), Error> {
    el.check_attrs(&["type", "id", "name"])?;
    if el.require("type")? != "hdrfilm" {
        return Err(plugin::unsupported(
            el,
            Family::Film,
            Dialect::Mitsuba,
            crate::scene::film::REGISTRY,
        ));
    }
    Film::from_mitsuba(el, FILM_WIDTH, FILM_HEIGHT)
}

/// A Mitsuba `<sampler>` nested in a sensor.
fn sampler(el: &Element) -> Result<(Sampler, u32), Error> {
    crate::scene::sampler::read(el, Dialect::Mitsuba, "sample_count", 4)
}
