//! `area`: uniform (or textured) emission from the front side of the shape that
//! carries it.
//!
//! Mitsuba 3: nested in a `<shape>` or referenced by one (an area emitter referenced
//! by several shapes gives each its own [`Emitter::Area`]); `radiance` is a color or a
//! `<texture name="radiance">` ([`Emitter::TexturedArea`], times wavetrace's extra
//! `scale`). Nori: nested in a `<mesh>`, `radiance` a color.
//!
//! ```xml
//! <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="10"/></emitter></shape>
//! ```

use glam::Vec3;

use crate::gpu::layout::{EmitterRecord, EMITTER_AREA, NONE};

use super::{Emitter, SAMPLING_WEIGHT};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::{Dialect, Element};
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Emitter,
    Dialect::Mitsuba,
    "area",
    "Uniform or textured emission from the front side of the shape carrying it (nested in or referenced by a shape).",
    &[
        Param::new("radiance", "rgb|texture", "", "emitted radiance (required)"),
        Param::new(
            "scale",
            "rgb",
            "1",
            "wavetrace's extension: a factor on a radiance texture",
        ),
        SAMPLING_WEIGHT,
    ],
);

pub const NORI: PluginDoc = PluginDoc::new(
    Family::Emitter,
    Dialect::Nori,
    "area",
    "Uniform emission from the front side of the mesh it is nested in.",
    &[Param::new(
        "radiance",
        "color",
        "",
        "emitted radiance (required)",
    )],
);

/// A Mitsuba area emitter from its `props` (textures already attached): the emitter
/// and its sampling weight. Checks that every parameter was read.
pub fn mitsuba(props: &Properties) -> Result<(Emitter, f32), Error> {
    let textures = props.textures();
    let emitter = if let Some((name, index)) = textures.first() {
        if name != "radiance" {
            return Err(props.error(
                name,
                format!("'{name}' of an area emitter cannot be a texture"),
            ));
        }
        let _ = props.color_opt("radiance")?;
        // wavetrace's extension: a factor on the texture (Mitsuba has none).
        let scale = props.color("scale", Vec3::ONE)?;
        Emitter::TexturedArea {
            texture: *index,
            scale,
        }
    } else {
        Emitter::Area {
            radiance: props
                .color_opt("radiance")?
                .ok_or_else(|| props.object_error("area emitter needs a 'radiance'"))?,
        }
    };
    let weight = super::sampling_weight(props)?;
    props.finish()?;
    Ok((emitter, weight))
}

/// A Nori `<emitter>` nested in a `<mesh>`: only `area` is allowed there.
pub fn nori(n: &Element) -> Result<Emitter, Error> {
    n.check_attrs(&["type"])?;
    let et = n.require("type")?;
    if et != "area" {
        return Err(n.err(format!("a mesh can only carry an area emitter, not '{et}'")));
    }
    let (p, nn) = Properties::read(n, Dialect::Nori, true)?;
    if let Some(x) = nn.first() {
        return Err(x.err(format!("unexpected <{}> in an emitter", x.tag)));
    }
    let radiance = p
        .color_opt("radiance")?
        .ok_or_else(|| p.object_error("area emitter needs a 'radiance'"))?;
    p.finish()?;
    Ok(Emitter::Area { radiance })
}

/// The GPU record of an area emitter (the shape it sits on is filled in by the
/// caller).
pub fn record(radiance: Vec3) -> EmitterRecord {
    EmitterRecord {
        kind: EMITTER_AREA,
        radiance: radiance.into(),
        shape: NONE,
        ..Default::default()
    }
}

/// The GPU record of a textured area emitter (texture `texture` times `scale`).
pub fn textured_record(texture: u32, scale: Vec3) -> EmitterRecord {
    EmitterRecord {
        kind: EMITTER_AREA,
        radiance: scale.into(),
        shape: NONE,
        texture: texture + 1,
        ..Default::default()
    }
}
