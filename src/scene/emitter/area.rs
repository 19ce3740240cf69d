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
        Param::new("radiance", "rgb|texture", "1", "emitted radiance"),
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
        // Mitsuba 3.9.1's area light defaults its radiance to 1 (Nori's requires one).
        Emitter::Area {
            radiance: props.color("radiance", Vec3::ONE)?,
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

#[cfg(test)]
mod tests {
    use crate::scene::testutil::{error_at, load};
    use crate::scene::Emitter;
    use glam::Vec3;

    /// Mitsuba 3.9.1 loads an area light without a radiance as radiance 1
    /// (`mi.traverse` gives `radiance.value` 1.0); Nori's area light requires one.
    #[test]
    fn radiance_defaults_as_each_dialect_says() {
        let mitsuba = "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"/>\n<shape type=\"rectangle\"><emitter type=\"area\"/></shape>\n</scene>\n";
        let scene = load(&[("s.xml", mitsuba)], &[]).unwrap();
        assert!(
            matches!(scene.emitters[..], [Emitter::Area { radiance }] if radiance == Vec3::ONE)
        );
        let nori = "<scene>\n<integrator type=\"path_mis\"/>\n<camera type=\"perspective\"/>\n<mesh type=\"obj\"><string name=\"filename\" value=\"m.obj\"/>\n<emitter type=\"area\"/></mesh>\n</scene>\n";
        let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        let e = error_at(load(&[("n.xml", nori), ("m.obj", obj)], &[]), "n.xml", 5);
        assert!(e.contains("area emitter needs a 'radiance'"), "{e}");
    }
}
