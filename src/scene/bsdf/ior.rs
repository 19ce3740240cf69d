//! Indices of refraction: Mitsuba's named presets for dielectrics and conductors,
//! and the readers of `int_ior` / `ext_ior` (a number or a name), `material` / `eta` /
//! `k`, and Nori's `intIOR` / `extIOR`.

use glam::Vec3;

use crate::scene::plugin::Param;
use crate::scene::properties::Properties;
use crate::scene::Error;

// `int_ior` of the dielectrics (default BK7) and `ext_ior` of every model that reads
// indices.
pub(super) const INT_IOR_BK7: Param = Param::new(
    "int_ior",
    "float|string",
    "bk7",
    "interior index of refraction, a number or a name (IOR_PRESETS)",
);
pub(super) const EXT_IOR: Param = Param::new(
    "ext_ior",
    "float|string",
    "air",
    "exterior index of refraction, a number or a name",
);
// Nori's `intIOR` and `extIOR`.
pub(super) const NORI_INT_IOR: Param =
    Param::new("intIOR", "float", "1.5046", "interior index of refraction");
pub(super) const NORI_EXT_IOR: Param = Param::new(
    "extIOR",
    "float",
    "1.000277",
    "exterior index of refraction",
);

/// Mitsuba's named indices of refraction (`include/mitsuba/render/ior.h`, values from
/// Hecht, "Optics", 4th ed., at about 589 nm).
pub const IOR_PRESETS: &[(&str, f32)] = &[
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.3330),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.470),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.5750),
    ("diamond", 2.419),
];

/// The index of a named material (case-insensitive, as Mitsuba's `lookup_ior`).
pub fn ior_preset(name: &str) -> Option<f32> {
    let lower = name.to_lowercase();
    IOR_PRESETS
        .iter()
        .find(|(n, _)| *n == lower)
        .map(|&(_, v)| v)
}

/// Complex indices of refraction (η, κ) of Mitsuba's conductor presets, in linear
/// sRGB. Made from Mitsuba's spectral data (`data/ior/<name>.eta.spd` and `.k.spd`,
/// from the luxpop.com database) the way Mitsuba's RGB variants reduce them
/// (`ior_from_file` in `include/mitsuba/render/ior.h` calling `spectrum_to_rgb`
/// unbounded), computed with [`crate::scene::spectrum::spectrum_to_srgb`]. They agree with
/// the values Mitsuba and pbrt print to about 1%.
pub const CONDUCTOR_PRESETS: &[(&str, [f32; 3], [f32; 3])] = &[
    ("Ag", [0.1545, 0.1170, 0.1382], [4.7996, 3.1330, 2.1443]),
    ("Al", [1.6434, 0.8857, 0.5203], [9.1747, 6.2874, 4.8314]),
    ("Au", [0.1456, 0.3729, 1.4414], [3.9565, 2.3955, 1.6007]),
    ("Cr", [4.3458, 2.9259, 1.6526], [5.1865, 4.2377, 3.7516]),
    ("Cu", [0.2037, 0.9220, 1.1017], [3.8845, 2.4632, 2.1396]),
];

/// (η, κ) of a conductor: `material` or `eta` + `k` (Mitsuba's `conductor.cpp`).
pub(super) fn conductor_ior(props: &Properties) -> Result<(Vec3, Vec3), Error> {
    let material = props.string_opt("material")?;
    let given = props.has("eta") || props.has("k");
    match material.as_deref() {
        None | Some("none") => {
            if material.is_some() && given {
                return Err(props.error(
                    "material",
                    "give either 'eta' and 'k' or a 'material', not both",
                ));
            }
            Ok((
                props.color("eta", Vec3::ZERO)?,
                props.color("k", Vec3::ONE)?,
            ))
        }
        Some(name) => {
            if given {
                return Err(props.error(
                    "material",
                    "give either 'eta' and 'k' or a 'material', not both",
                ));
            }
            let Some((_, eta, k)) = CONDUCTOR_PRESETS.iter().find(|(n, _, _)| *n == name) else {
                let known: Vec<&str> = CONDUCTOR_PRESETS.iter().map(|p| p.0).collect();
                return Err(props.error(
                    "material",
                    format!(
                        "unknown conductor material '{name}' (known: {}, none)",
                        known.join(", ")
                    ),
                ));
            };
            Ok((Vec3::from(*eta), Vec3::from(*k)))
        }
    }
}

/// An index of refraction given as a number or a preset name.
fn ior(props: &Properties, key: &str, default: &str) -> Result<f32, Error> {
    if !props.has(key) {
        return ior_preset(default).ok_or_else(|| props.error(key, "internal: bad default"));
    }
    let v = match props.float_opt(key) {
        Ok(Some(v)) => v,
        Ok(None) => unreachable!("has() said the parameter exists"),
        Err(_) => {
            let name = props.string_opt(key).map_err(|_| {
                props.error(
                    key,
                    format!(
                        "parameter '{key}' of {} must be a float or a material name",
                        props.object()
                    ),
                )
            })?;
            let name = name.unwrap_or_default();
            ior_preset(&name).ok_or_else(|| {
                let known: Vec<&str> = IOR_PRESETS.iter().map(|p| p.0).collect();
                props.error(
                    key,
                    format!(
                        "unknown index of refraction '{name}' (known: {})",
                        known.join(", ")
                    ),
                )
            })?
        }
    };
    if !(v > 0.0 && v.is_finite()) {
        return Err(props.error(
            key,
            format!("index of refraction '{key}' must be positive, found {v}"),
        ));
    }
    Ok(v)
}

/// int / ext index of refraction; `differ`: the two must not be equal (rough models).
pub(super) fn relative_ior(
    props: &Properties,
    int_key: &str,
    ext_key: &str,
    int_default: &str,
    differ: bool,
) -> Result<f32, Error> {
    let int = ior(props, int_key, int_default)?;
    let ext = ior(props, ext_key, "air")?;
    if differ && int == ext {
        return Err(props.error(
            int_key,
            format!(
                "'{int_key}' and '{ext_key}' must differ for {}",
                props.object()
            ),
        ));
    }
    Ok(int / ext)
}

/// Nori's `intIOR` (1.5046) / `extIOR` (1.000277), plain floats.
pub(super) fn nori_eta(props: &Properties, differ: bool) -> Result<f32, Error> {
    let int = props.float("intIOR", 1.5046)?;
    let ext = props.float("extIOR", 1.000277)?;
    for (key, v) in [("intIOR", int), ("extIOR", ext)] {
        if !(v > 0.0 && v.is_finite()) {
            return Err(props.error(key, format!("'{key}' must be positive, found {v}")));
        }
    }
    if differ && int == ext {
        return Err(props.error("intIOR", "'intIOR' and 'extIOR' must differ"));
    }
    Ok(int / ext)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets() {
        assert_eq!(ior_preset("BK7"), Some(1.5046));
        assert_eq!(ior_preset("water"), Some(1.333));
        assert_eq!(ior_preset("glass"), None);
    }
}
