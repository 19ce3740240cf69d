//! `bumpmap`: the nested BSDF shaded in the frame of a height field (Mitsuba 3's
//! `bumpmap.cpp`). The texture's gradient ∇h = scale · (∂h/∂u, ∂h/∂v) tilts the
//! surface's derivatives, ∂p/∂u' = ∂p/∂u + (∂h/∂u − n·∂p/∂u) n and likewise for v,
//! and the shading normal becomes ∂p/∂u' × ∂p/∂v', turned to the side of the
//! geometric normal. From there on it is Mitsuba 3.9's normal map
//! ([`super::normalmap`]): invalid normals flipped, light on different sides of the
//! old and the new normal dropped, and the shadowing term of Estevez et al. 2019. The
//! texture (any name, exactly one) is usually a `raw` bitmap; its gradient is that of
//! its bilinear interpolation (Mitsuba's `eval_1_grad`). GLSL:
//! `shaders/bsdf/composite.glsl`. The Mitsuba loader reads it with [`params`].
//!
//! | parameter | type | default |
//! |-----------|------|---------|
//! | (one texture, any name) | texture | (required): the height field |
//! | `scale` | float | 1 |
//! | `flip_invalid_normals` | boolean | true (as `normalmap`'s) |
//! | `use_shadowing_function` | boolean | true (as `normalmap`'s) |
//!
//! ```xml
//! <bsdf type="bumpmap"><texture type="bitmap" name="bump"><string name="filename" value="h.png"/><boolean name="raw" value="true"/></texture><float name="scale" value="0.02"/><bsdf type="diffuse"/></bsdf>
//! ```

use super::Plugin;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const MITSUBA: Plugin = Plugin::loader(PluginDoc::new(
    Family::Bsdf,
    Dialect::Mitsuba,
    "bumpmap",
    "One nested BSDF shaded with the normal of a height field texture.",
    &[
        Param::new(
            "(texture)",
            "texture",
            "",
            "the height field, one nested texture of any name; required",
        ),
        Param::new(
            "scale",
            "float",
            "1",
            "factor of the height field's gradient",
        ),
    ],
));

/// A bump map's own parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BumpParams {
    /// The height field's texture index.
    pub texture: u32,
    pub scale: f32,
    pub flip_invalid_normals: bool,
    pub use_shadowing_function: bool,
}

/// The bump map's parameters, from `props` with its textures attached.
pub fn params(props: &Properties) -> Result<BumpParams, Error> {
    let textures = props.textures();
    let texture = match textures.as_slice() {
        [(name, index)] => {
            props.ignore(&[name.as_str()]);
            *index
        }
        [] => {
            return Err(props.object_error("bumpmap needs one nested <texture> (the height field)"))
        }
        [_, (name, _), ..] => {
            return Err(props.error(name, "bumpmap takes exactly one nested <texture>"))
        }
    };
    Ok(BumpParams {
        texture,
        scale: props.float("scale", 1.0)?,
        flip_invalid_normals: props.boolean("flip_invalid_normals", true)?,
        use_shadowing_function: props.boolean("use_shadowing_function", true)?,
    })
}
