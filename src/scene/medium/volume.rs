//! Volumes, nested in a `<medium>` as its `sigma_t` or `albedo`: `constvolume` (a
//! color over the unit cube its `to_world` places), `gridvolume` (a Mitsuba `.vol`
//! file, 1 or 3 float32 channels, or an OpenVDB `.vdb` file's scalar grid, see
//! [`crate::scene::vdb`]; trilinear interpolation between voxel centres, as Mitsuba
//! 3's `gridvolume`), and wavetrace's procedural `cloud` and `perlin`, baked to a grid
//! at load ([`crate::scene::procedural`]).
//!
//! ```xml
//! <volume type="gridvolume" name="sigma_t"><string name="filename" value="smoke.vol"/></volume>
//! ```

use glam::{Mat4, Vec3};

use super::{read_vol, Grid};
use crate::scene::plugin::{self, Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::{Dialect, Element};
use crate::scene::Error;

const TO_WORLD: Param = Param::new(
    "to_world",
    "transform",
    "identity",
    "places the volume's unit cube",
);

pub const CONSTVOLUME: PluginDoc = PluginDoc::new(
    Family::Volume,
    Dialect::Mitsuba,
    "constvolume",
    "A constant over the unit cube its to_world places.",
    &[Param::new("value", "rgb", "1", "the constant"), TO_WORLD],
);

pub const GRIDVOLUME: PluginDoc = PluginDoc::new(
    Family::Volume,
    Dialect::Mitsuba,
    "gridvolume",
    "A voxel grid from a Mitsuba .vol file or an OpenVDB .vdb file, interpolated trilinearly.",
    &[
        Param::new("filename", "string", "", "the .vol or .vdb file (required)"),
        TO_WORLD,
        Param::new(
            "use_grid_bbox",
            "boolean",
            "false",
            "place a .vol grid on its own bounding box (a .vdb grid always is)",
        ),
        Param::new(
            "grid",
            "string",
            "",
            "the .vdb file's scalar grid (default: the first named density, else the first)",
        ),
        Param::new("filter_type", "string", "trilinear", "trilinear only"),
        Param::new("raw", "boolean", "", "read and ignored"),
        Param::new("accel", "boolean", "", "read and ignored"),
        Param::new("wrap_mode", "string", "", "read and ignored"),
    ],
);

const RESOLUTION: Param = Param::new("resolution", "integer", "64", "voxels along each axis");
const SEED: Param = Param::new("seed", "integer", "1", "noise seed");
const DENSITY: Param = Param::new("density", "float", "1", "factor on the density");
const FADE: Param = Param::new(
    "fade",
    "float",
    "",
    "margin (fraction of the cube) fading to 0",
);

pub const CLOUD: PluginDoc = PluginDoc::new(
    Family::Volume,
    Dialect::Mitsuba,
    "cloud",
    "wavetrace's procedural cloud (Worley-noise fBm), baked to a grid.",
    &[
        RESOLUTION,
        SEED,
        Param::new("frequency", "float", "3", "base cells per unit"),
        Param::new("octaves", "integer", "3", "fBm octaves, in [1, 8]"),
        Param::new("threshold", "float", "0.5", "base shape kept above this"),
        Param::new("detail_frequency", "float", "12", "detail cells per unit"),
        Param::new("detail_strength", "float", "0.3", "detail subtracted"),
        Param::new("fade", "float", "0.1", FADE.doc),
        DENSITY,
        TO_WORLD,
    ],
);

pub const PERLIN: PluginDoc = PluginDoc::new(
    Family::Volume,
    Dialect::Mitsuba,
    "perlin",
    "wavetrace's procedural Perlin-noise fBm density, baked to a grid.",
    &[
        RESOLUTION,
        SEED,
        Param::new("frequency", "float", "4", "base frequency"),
        Param::new("octaves", "integer", "4", "fBm octaves, in [1, 8]"),
        Param::new("lacunarity", "float", "2", "frequency factor per octave"),
        Param::new("gain", "float", "0.5", "amplitude factor per octave"),
        Param::new(
            "offset",
            "float",
            "0",
            "added to the fBm before clamping at 0",
        ),
        Param::new("fade", "float", "0", FADE.doc),
        DENSITY,
        TO_WORLD,
    ],
);

/// A nested `<volume name=...>`: a constant color (with the `to_world` that places
/// its unit cube) or a grid.
pub enum Volume {
    Constant(Vec3, Mat4),
    Grid(Grid),
}

/// A `<volume>` element.
pub fn read(el: &Element) -> Result<Volume, Error> {
    el.check_attrs(&["type", "id", "name"])?;
    let t = el.require("type")?;
    let (props, nested) = Properties::read(el, Dialect::Mitsuba, false)?;
    if let Some(n) = nested.first() {
        return Err(n.err(format!("unexpected <{}> in a <volume>", n.tag)));
    }
    let v = match t {
        "constvolume" => Volume::Constant(
            props.color("value", Vec3::ONE)?,
            props.transform("to_world")?,
        ),
        "gridvolume" => Volume::Grid(grid(el, &props)?),
        "cloud" | "perlin" => Volume::Grid(crate::scene::procedural::bake(t, &props)?),
        _ => {
            return Err(plugin::unsupported(
                el,
                Family::Volume,
                Dialect::Mitsuba,
                super::REGISTRY,
            ))
        }
    };
    props.finish()?;
    Ok(v)
}

/// A `gridvolume`'s grid, placed in the scene.
fn grid(el: &Element, props: &Properties) -> Result<Grid, Error> {
    let name = props
        .string_opt("filename")?
        .ok_or_else(|| props.object_error("gridvolume needs a 'filename'"))?;
    let path = el
        .resolve(&name)
        .map_err(|tried| props.error("filename", format!("grid file {tried} not found")))?;
    let to_world = props.transform("to_world")?;
    let vdb = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("vdb"));
    let grid = if vdb {
        let grid = props.string_opt("grid")?;
        if props.has("use_grid_bbox") && !props.boolean("use_grid_bbox", true)? {
            return Err(props.error(
                "use_grid_bbox",
                "a .vdb grid is always placed by its own transform (then to_world)",
            ));
        }
        let mut g = crate::scene::vdb::read_vdb(&path, grid.as_deref())
            .map_err(|m| props.error(if grid.is_some() { "grid" } else { "filename" }, m))?;
        g.to_world = to_world * g.to_world;
        g
    } else {
        if props.has("grid") {
            return Err(props.error(
                "grid",
                format!("'grid' picks a grid of a .vdb file; {name} is a .vol file"),
            ));
        }
        let mut g = read_vol(&path).map_err(|m| props.error("filename", m))?;
        if !props.boolean("use_grid_bbox", false)? {
            g.to_world = Mat4::IDENTITY;
        }
        g.to_world = to_world * g.to_world;
        g
    };
    if grid.to_world.determinant().abs() < 1e-30 || !grid.to_world.is_finite() {
        return Err(props.error("to_world", "the grid's to_world is not invertible"));
    }
    match props.string("filter_type", "trilinear")?.as_str() {
        "trilinear" => {}
        other => {
            return Err(props.error(
                "filter_type",
                format!("filter_type '{other}' is not supported (trilinear only)"),
            ))
        }
    }
    props.ignore(&["raw", "accel", "wrap_mode"]);
    Ok(grid)
}
