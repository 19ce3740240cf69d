//! `rawconstant`: one value everywhere, taken as written (Mitsuba 3.9.1's
//! `src/spectra/rawconstant.cpp`): no color conversion and no range check, so it may
//! hold a normal map's constant texel, a negative number or a value above 1. `value`
//! is a `float` (broadcast to the three channels) or a 3D `vector`; there is no `to_uv`.
//!
//! ```xml
//! <texture type="rawconstant" name="normalmap"><vector name="value" value="0.5, 0.5, 1.0"/></texture>
//! ```

use glam::Vec3;

use super::Texture;
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::Error;

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Texture,
    Dialect::Mitsuba,
    "rawconstant",
    "A constant value with no color conversion (float or 3D vector).",
    &[Param::new(
        "value",
        "float or vector",
        "",
        "the value (required); a float is broadcast to three channels",
    )],
);

/// A Mitsuba `rawconstant` texture.
pub fn mitsuba(props: &Properties) -> Result<Texture, Error> {
    if !props.has("value") {
        return Err(props.object_error("rawconstant needs a 'value' (a float or a 3D vector)"));
    }
    let value = match props.float_opt("value") {
        Ok(Some(v)) => Vec3::splat(v),
        _ => props
            .point_opt("value")
            .map_err(|_| {
                props.error(
                    "value",
                    "'value' of rawconstant must be a float or a 3D vector",
                )
            })?
            .unwrap_or_default(),
    };
    if !value.is_finite() {
        return Err(props.error("value", "'value' of rawconstant is not finite"));
    }
    Ok(Texture::Constant { value })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::testutil::{error_at, load, mitsuba};

    fn textures(body: &str) -> Vec<Texture> {
        load(&[("s.xml", &mitsuba(body))], &[]).unwrap().textures
    }

    /// Mitsuba's test_rawconstant.py values: a float broadcast, a vector as written
    /// (negative and above 1 alike), no color conversion.
    #[test]
    fn values_as_written() {
        let t = textures(
            r#"<texture type="rawconstant" id="a"><float name="value" value="-2.5"/></texture>
<texture type="rawconstant" id="b"><vector name="value" value="-0.5, 2.0, -1.3"/></texture>
<texture type="rawconstant" id="c"><integer name="value" value="3"/></texture>"#,
        );
        let uv = glam::Vec2::new(0.3, 0.7);
        assert_eq!(t[0].eval(uv), Vec3::splat(-2.5));
        assert_eq!(t[1].eval(uv), Vec3::new(-0.5, 2.0, -1.3));
        assert_eq!(t[1].mean(), Vec3::new(-0.5, 2.0, -1.3));
        assert_eq!(t[2].eval(uv), Vec3::splat(3.0));
    }

    #[test]
    fn errors() {
        let cases: &[(&str, u32, &str)] = &[
            ("<texture type=\"rawconstant\" id=\"a\">\n</texture>", 3, "needs a 'value'"),
            ("<texture type=\"rawconstant\" id=\"a\">\n<rgb name=\"value\" value=\"0.5\"/></texture>", 4, "must be a float or a 3D vector"),
            ("<texture type=\"rawconstant\" id=\"a\"><float name=\"value\" value=\"1\"/>\n<transform name=\"to_uv\"><scale value=\"2\"/></transform></texture>", 4, "unknown parameter 'to_uv'"),
        ];
        for (body, line, msg) in cases {
            let e = error_at(load(&[("s.xml", &mitsuba(body))], &[]), "s.xml", *line);
            assert!(e.contains(msg), "{e}\n  wanted: {msg}");
        }
    }
}
