//! `normalmap`: the nested model shaded with a normal read from a texture (Mitsuba
//! 3.9's `normalmap.cpp`). The texture `normalmap` (usually a `raw` bitmap) gives in
//! its RGB in [0, 1]³ a tangent-space normal 2c − 1 in the frame (∂p/∂u, n × ∂p/∂u,
//! n) of the shading normal n. Light from directions on opposite sides of n and of
//! the mapped normal is dropped, so the map never lets light through the surface.
//! GLSL: `shaders/bsdf/normal_map.glsl`. The Mitsuba loader reads it (it attaches
//! the texture and resolves the nested BSDF) with [`params`].
//!
//! | parameter | type | default |
//! |-----------|------|---------|
//! | `normalmap` | texture | (required) |
//! | `flip_invalid_normals` | boolean | true: negates the tangential part of a mapped normal that faces away from the viewer (Schüssler et al. 2017, "Microfacet-based Normal Mapping for Robust Monte Carlo Path Tracing") |
//! | `use_shadowing_function` | boolean | true: scales the value by the shadowing term of Estevez et al. 2019, which darkens light from grazing directions on strongly tilted normals |
//!
//! ```xml
//! <bsdf type="normalmap"><texture type="bitmap" name="normalmap"><string name="filename" value="n.png"/><boolean name="raw" value="true"/></texture><bsdf type="diffuse"/></bsdf>
//! ```

use super::{Bsdf, Plugin};
use crate::gpu::layout::{BsdfRecord, BSDF_NORMALMAP_FLIP, BSDF_NORMALMAP_SHADOWING};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const MITSUBA: Plugin = Plugin::loader(PluginDoc::new(
    Family::Bsdf,
    Dialect::Mitsuba,
    "normalmap",
    "One nested BSDF shaded with a normal read from a texture.",
    &[
        Param::new(
            "normalmap",
            "texture",
            "",
            "tangent-space normal map (usually a raw bitmap); required",
        ),
        Param::new(
            "flip_invalid_normals",
            "boolean",
            "true",
            "flip mapped normals that face away from the viewer (Schüssler et al. 2017)",
        ),
        Param::new(
            "use_shadowing_function",
            "boolean",
            "true",
            "apply the shadowing term of Estevez et al. 2019",
        ),
    ],
));

/// The normal map's own parameters, from `props` with its textures attached: the
/// texture index of `normalmap`, `flip_invalid_normals`, `use_shadowing_function`.
pub fn params(props: &Properties) -> Result<(u32, bool, bool), Error> {
    let normal_map = props
        .textures()
        .iter()
        .find(|(n, _)| n == "normalmap")
        .map(|(_, i)| *i)
        .ok_or_else(|| props.object_error("normalmap needs a <texture name=\"normalmap\">"))?;
    props.ignore(&["normalmap"]);
    let flip_invalid_normals = props.boolean("flip_invalid_normals", true)?;
    let use_shadowing_function = props.boolean("use_shadowing_function", true)?;
    Ok((normal_map, flip_invalid_normals, use_shadowing_function))
}

/// The record of a [`Bsdf::NormalMap`]: its model's, with the map's texture id + 1
/// and flags.
pub(super) fn pack(
    bsdf: &Bsdf,
    normal_map: u32,
    flip_invalid_normals: bool,
    use_shadowing_function: bool,
) -> BsdfRecord {
    let mut r = BsdfRecord::from(bsdf);
    r.normal_map = normal_map + 1;
    if flip_invalid_normals {
        r.flags |= BSDF_NORMALMAP_FLIP;
    }
    if use_shadowing_function {
        r.flags |= BSDF_NORMALMAP_SHADOWING;
    }
    r
}
