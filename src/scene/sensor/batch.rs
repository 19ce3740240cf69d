//! `batch`: Mitsuba 3's meta-sensor of several child sensors side by side in one film
//! (`src/sensors/batch.cpp`). The batch's film (width divisible by the number of
//! children n, else an error) and sampler render all of them: child i sees columns
//! [i w / n, (i + 1) w / n) as its own (w / n) x h film. Mitsuba sets each child's
//! film to that size once the child is built: its horizontal fov is what `fov_axis`
//! gave against the child's own film (its nested `<film>`, else 768 x 576), its
//! vertical one follows the (w / n) x h aspect. The children's samplers, media and
//! films otherwise are not used (the batch's medium is the camera's). A film position x in [0, 1) goes to child floor(x n) (at most
//! n - 1) at x n - floor(x n) (`BatchSensor::sample_ray`).
//!
//! Children here: `perspective`, `orthographic`, `thinlens` and `radiancemeter`, at
//! most [`MAX_CHILDREN`] (the GPU frame holds their records: `Frame::batch_*`). A
//! radiancemeter child, as in Mitsuba, needs its own film to be 1 x 1 (checked before
//! the batch resizes it) and then fills its slice with estimates of its one ray's
//! radiance. Mitsuba's batch also takes an irradiancemeter nested in a `<shape>` child;
//! that is refused here for now.
//!
//! ```xml
//! <sensor type="batch">
//!     <sensor type="perspective"><float name="fov" value="45"/>
//!         <transform name="to_world"><lookat origin="0,0,4" target="0,0,0" up="0,1,0"/></transform></sensor>
//!     <sensor type="perspective"><float name="fov" value="45"/>
//!         <transform name="to_world"><lookat origin="4,0,0" target="0,0,0" up="0,1,0"/></transform></sensor>
//!     <film type="hdrfilm"><integer name="width" value="256"/><integer name="height" value="128"/></film>
//! </sensor>
//! ```

use super::{SensorParts, FILM_HEIGHT, FILM_WIDTH};
use crate::scene::plugin::{Family, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::sampler::Sampler;
use crate::scene::xml::{Dialect, Element};
use crate::scene::{Error, Film};

/// The most children a batch holds (the records `Frame::batch_*` has room for).
pub const MAX_CHILDREN: usize = 8;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Sensor,
    Dialect::Mitsuba,
    "batch",
    "Several sensors side by side in one film: nests 1 to 8 perspective, orthographic, thinlens or radiancemeter (with its own 1 x 1 film) <sensor>s, each rendering a (width / n) x height slice, left to right in document order, and the <film> (width divisible by n), <sampler> and <medium> they share.",
    &[],
);

/// A Mitsuba `<sensor type="batch">` (its type already checked).
pub fn mitsuba(el: &Element) -> Result<SensorParts<'_>, Error> {
    let (props, nested) = Properties::read(el, Dialect::Mitsuba, false)?;
    let mut size = None;
    let mut spp = None;
    let mut medium = None;
    let mut children = Vec::new();
    for n in nested {
        match n.tag.as_str() {
            "film" if size.is_none() => size = Some(super::film(n)?),
            "sampler" if spp.is_none() => spp = Some(super::sampler(n)?),
            "film" | "sampler" => {
                return Err(n.err(format!("more than one <{}> in <sensor>", n.tag)))
            }
            "medium" | "ref" if medium.is_none() => medium = Some(n),
            "medium" | "ref" => return Err(n.err("a sensor sits in one medium")),
            "sensor" => {
                n.check_attrs(&["type", "id", "name"])?;
                let t = n.require("type")?;
                if !matches!(
                    t,
                    "perspective" | "orthographic" | "thinlens" | "radiancemeter"
                ) {
                    return Err(n.err(format!(
                        "a batch sensor's children are perspective, orthographic, thinlens or radiancemeter sensors, not '{t}'"
                    )));
                }
                children.push((n, t));
            }
            // Mitsuba's batch also takes a <shape> holding an irradiancemeter.
            "shape" => {
                return Err(n.err(
                    "an irradiancemeter (a <shape> with a <sensor>) as a batch sensor's child \
                     is not supported yet: render it as a sensor of its own (nested in its \
                     shape at the top level, picked by --sensor)",
                ))
            }
            _ => return Err(n.err(format!("unexpected <{}> in <sensor>", n.tag))),
        }
    }
    props.finish()?;
    if children.is_empty() {
        return Err(el.err("a batch sensor needs at least one child <sensor>"));
    }
    if children.len() > MAX_CHILDREN {
        return Err(children[MAX_CHILDREN].0.err(format!(
            "a batch sensor holds at most {MAX_CHILDREN} sensors, found {}",
            children.len()
        )));
    }
    let (width, height, film) = size.unwrap_or((FILM_WIDTH, FILM_HEIGHT, Film::default()));
    let n = children.len() as u32;
    if width % n != 0 {
        return Err(el.err(format!(
            "the film's width ({width}) must be divisible by the number of child sensors ({n})"
        )));
    }
    let mut batch = Vec::with_capacity(children.len());
    for (c, t) in children {
        let (camera, _, _, _) =
            super::perspective::projective_sized(c, t, Some((width / n, height)))?;
        batch.push(camera);
    }
    let mut camera = batch[0].clone();
    camera.width = width;
    camera.height = height;
    camera.batch = batch;
    Ok((camera, spp.unwrap_or((Sampler::default(), 4)), film, medium))
}
