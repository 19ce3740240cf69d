//! The one parameter reader (STYLE.md rule 11).
//!
//! [`Properties`] holds the value tags of one scene object (`<float name="fov" .../>`,
//! `<rgb name="reflectance" .../>`, ...). A plugin reads them with typed getters and
//! defaults; each read is remembered, and [`Properties::finish`] reports any parameter
//! the plugin did not read, naming the object, the key and the line. A value of the
//! wrong type is an error at the value's line.

use std::cell::Cell;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::rc::Rc;

use glam::{Mat4, Vec3};

use super::integrator::Param;
use super::spectrum;
use super::transform;
use super::xml::{parse_number, parse_numbers, tokens, Dialect, Element, SearchPath};
use super::Error;

/// A parameter value as written in the scene file.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Boolean(bool),
    Integer(i64),
    Float(f64),
    String(String),
    /// `rgb`, `spectrum` (Mitsuba) or `color` (Nori), as linear sRGB.
    Color(Vec3),
    Point(Vec3),
    Vector(Vec3),
    Transform(Mat4),
    /// A nested or referenced `<texture>`: its index in the scene's textures, and its
    /// mean (what color and float getters return, e.g. for sampling weights).
    Texture {
        index: u32,
        mean: Vec3,
    },
}

impl Value {
    fn type_name(&self) -> &'static str {
        match self {
            Value::Boolean(_) => "a boolean",
            Value::Integer(_) => "an integer",
            Value::Float(_) => "a float",
            Value::String(_) => "a string",
            Value::Color(_) => "a color",
            Value::Point(_) => "a point",
            Value::Vector(_) => "a vector",
            Value::Transform(_) => "a transform",
            Value::Texture { .. } => "a texture",
        }
    }
}

#[derive(Debug)]
struct Entry {
    value: Value,
    line: u32,
    read: Cell<bool>,
}

/// The parameters of one scene object, with typed getters that remember what was read.
#[derive(Debug)]
pub struct Properties {
    /// The object, for messages: `sensor 'perspective'`.
    object: String,
    file: Rc<PathBuf>,
    line: u32,
    entries: BTreeMap<String, Entry>,
    /// Where the file names it holds are found ([`Properties::resolve`]).
    search: Rc<SearchPath>,
}

/// Names of Mitsuba spectrum parameters that are not clamped to [0, 1].
const UNBOUNDED: &[&str] = &[
    "eta", "k", "int_ior", "ext_ior", "sigma_t", "sigma_a", "sigma_s",
];

impl Properties {
    /// Reads the value tags among `el`'s children. Returns the properties and the other
    /// children (nested objects such as `<bsdf>`, `<film>`, `<ref>`), which the caller
    /// must handle or reject. `within_emitter` selects Mitsuba's clamping of spectra.
    pub fn read(
        el: &Element,
        dialect: Dialect,
        within_emitter: bool,
    ) -> Result<(Properties, Vec<&Element>), Error> {
        let object = match el.attr("type") {
            Some(t) => format!("{} '{}'", el.tag, t),
            None => el.tag.clone(),
        };
        let mut props = Properties {
            object,
            file: el.file.clone(),
            line: el.line,
            entries: BTreeMap::new(),
            search: el.search.clone(),
        };
        let mut nested = Vec::new();
        for child in &el.children {
            let value = match (dialect, child.tag.as_str()) {
                (_, "boolean" | "integer" | "float" | "string" | "point" | "vector") => {
                    scalar(child)?
                }
                (_, "transform") => {
                    child.check_attrs(&["name"])?;
                    Value::Transform(transform::parse(child)?)
                }
                (Dialect::Mitsuba, "rgb") => {
                    child.check_attrs(&["name", "value"])?;
                    Value::Color(color(child)?)
                }
                (Dialect::Nori, "color") => {
                    child.check_attrs(&["name", "value"])?;
                    Value::Color(color(child)?)
                }
                (Dialect::Mitsuba, "spectrum") if child.attr("type").is_none() => {
                    child.check_attrs(&["name", "value", "filename"])?;
                    Value::Color(spectrum_value(child, within_emitter)?)
                }
                _ => {
                    nested.push(child);
                    continue;
                }
            };
            let name = child.require("name")?.to_string();
            if name.is_empty() {
                return Err(child.err(format!("<{}> needs a non-empty name", child.tag)));
            }
            if let Some(prev) = props.entries.get(&name) {
                return Err(child.err(format!(
                    "parameter '{name}' of {} is given twice (first at line {})",
                    props.object, prev.line
                )));
            }
            props.entries.insert(
                name,
                Entry {
                    value,
                    line: child.line,
                    read: Cell::new(false),
                },
            );
        }
        Ok((props, nested))
    }

    /// Resolves a file name given in these properties as Mitsuba's file resolver does
    /// ([`crate::scene::xml::Element::resolve`]); on failure, the paths tried.
    pub fn resolve(&self, name: &str) -> Result<PathBuf, String> {
        self.search.resolve(name)
    }

    /// The object these properties belong to, for messages (`sensor 'perspective'`).
    pub fn object(&self) -> &str {
        &self.object
    }

    /// Whether parameter `name` was given (does not count as reading it).
    pub fn has(&self, name: &str) -> bool {
        self.entries.contains_key(name)
    }

    /// The line of parameter `name`, or of the object when it was not given.
    pub fn line_of(&self, name: &str) -> u32 {
        self.entries.get(name).map_or(self.line, |e| e.line)
    }

    /// An error at the line of parameter `name` (or of the object).
    pub fn error(&self, name: &str, message: impl Into<String>) -> Error {
        Error::at(self.file.as_path(), self.line_of(name), message)
    }

    /// An error at the object's line.
    pub fn object_error(&self, message: impl Into<String>) -> Error {
        Error::at(self.file.as_path(), self.line, message)
    }

    /// Marks parameters as read that are accepted and have no effect here.
    pub fn ignore(&self, names: &[&str]) {
        for n in names {
            if let Some(e) = self.entries.get(*n) {
                e.read.set(true);
            }
        }
    }

    fn get(&self, name: &str) -> Option<&Entry> {
        let e = self.entries.get(name)?;
        e.read.set(true);
        Some(e)
    }

    fn wrong_type(&self, name: &str, e: &Entry, expected: &str) -> Error {
        Error::at(
            self.file.as_path(),
            e.line,
            format!(
                "parameter '{name}' of {} must be {expected}, found {}",
                self.object,
                e.value.type_name()
            ),
        )
    }

    pub fn float_opt(&self, name: &str) -> Result<Option<f32>, Error> {
        match self.get(name) {
            None => Ok(None),
            Some(Entry {
                value: Value::Float(v),
                ..
            }) => Ok(Some(*v as f32)),
            Some(Entry {
                value: Value::Integer(v),
                ..
            }) => Ok(Some(*v as f32)),
            Some(Entry {
                value: Value::Texture { mean, .. },
                ..
            }) => Ok(Some(mean.dot(glam::Vec3::new(0.2126, 0.7152, 0.0722)))),
            Some(e) => Err(self.wrong_type(name, e, "a float")),
        }
    }

    pub fn float(&self, name: &str, default: f32) -> Result<f32, Error> {
        Ok(self.float_opt(name)?.unwrap_or(default))
    }

    pub fn integer_opt(&self, name: &str) -> Result<Option<i64>, Error> {
        match self.get(name) {
            None => Ok(None),
            Some(Entry {
                value: Value::Integer(v),
                ..
            }) => Ok(Some(*v)),
            Some(e) => Err(self.wrong_type(name, e, "an integer")),
        }
    }

    pub fn integer(&self, name: &str, default: i64) -> Result<i64, Error> {
        Ok(self.integer_opt(name)?.unwrap_or(default))
    }

    /// A positive integer that fits in u32 (image sizes, sample counts).
    pub fn positive(&self, name: &str, default: u32) -> Result<u32, Error> {
        match self.integer_opt(name)? {
            None => Ok(default),
            Some(v) if v > 0 && v <= i64::from(u32::MAX) => Ok(v as u32),
            Some(v) => Err(self.error(
                name,
                format!(
                    "parameter '{name}' of {} must be positive, found {v}",
                    self.object
                ),
            )),
        }
    }

    pub fn boolean(&self, name: &str, default: bool) -> Result<bool, Error> {
        match self.get(name) {
            None => Ok(default),
            Some(Entry {
                value: Value::Boolean(v),
                ..
            }) => Ok(*v),
            Some(e) => Err(self.wrong_type(name, e, "a boolean")),
        }
    }

    pub fn string_opt(&self, name: &str) -> Result<Option<String>, Error> {
        match self.get(name) {
            None => Ok(None),
            Some(Entry {
                value: Value::String(v),
                ..
            }) => Ok(Some(v.clone())),
            Some(e) => Err(self.wrong_type(name, e, "a string")),
        }
    }

    pub fn string(&self, name: &str, default: &str) -> Result<String, Error> {
        Ok(self
            .string_opt(name)?
            .unwrap_or_else(|| default.to_string()))
    }

    /// A color (`rgb`, `spectrum`, `color`); a plain float or integer means a grey.
    pub fn color_opt(&self, name: &str) -> Result<Option<Vec3>, Error> {
        match self.get(name) {
            None => Ok(None),
            Some(Entry {
                value: Value::Color(v),
                ..
            }) => Ok(Some(*v)),
            Some(Entry {
                value: Value::Float(v),
                ..
            }) => Ok(Some(Vec3::splat(*v as f32))),
            Some(Entry {
                value: Value::Integer(v),
                ..
            }) => Ok(Some(Vec3::splat(*v as f32))),
            Some(Entry {
                value: Value::Texture { mean, .. },
                ..
            }) => Ok(Some(*mean)),
            Some(e) => Err(self.wrong_type(name, e, "a color")),
        }
    }

    pub fn color(&self, name: &str, default: Vec3) -> Result<Vec3, Error> {
        Ok(self.color_opt(name)?.unwrap_or(default))
    }

    /// A `point` or `vector`.
    pub fn point_opt(&self, name: &str) -> Result<Option<Vec3>, Error> {
        match self.get(name) {
            None => Ok(None),
            Some(Entry {
                value: Value::Point(v) | Value::Vector(v),
                ..
            }) => Ok(Some(*v)),
            Some(e) => Err(self.wrong_type(name, e, "a point")),
        }
    }

    pub fn point(&self, name: &str, default: Vec3) -> Result<Vec3, Error> {
        Ok(self.point_opt(name)?.unwrap_or(default))
    }

    /// A `vector` or `point`.
    pub fn vector(&self, name: &str, default: Vec3) -> Result<Vec3, Error> {
        self.point(name, default)
    }

    pub fn transform_opt(&self, name: &str) -> Result<Option<Mat4>, Error> {
        match self.get(name) {
            None => Ok(None),
            Some(Entry {
                value: Value::Transform(m),
                ..
            }) => Ok(Some(*m)),
            Some(e) => Err(self.wrong_type(name, e, "a transform")),
        }
    }

    /// A transform, identity when absent.
    pub fn transform(&self, name: &str) -> Result<Mat4, Error> {
        Ok(self.transform_opt(name)?.unwrap_or(Mat4::IDENTITY))
    }

    /// Adds texture `index` (mean color `mean`) as parameter `name`, given at `line`.
    pub fn insert_texture(
        &mut self,
        name: &str,
        index: u32,
        mean: Vec3,
        line: u32,
    ) -> Result<(), Error> {
        if name.is_empty() {
            return Err(Error::at(
                self.file.as_path(),
                line,
                format!("a texture in {} needs a name", self.object),
            ));
        }
        if let Some(prev) = self.entries.get(name) {
            return Err(Error::at(
                self.file.as_path(),
                line,
                format!(
                    "parameter '{name}' of {} is given twice (first at line {})",
                    self.object, prev.line
                ),
            ));
        }
        self.entries.insert(
            name.to_string(),
            Entry {
                value: Value::Texture { index, mean },
                line,
                read: Cell::new(false),
            },
        );
        Ok(())
    }

    /// The parameters given as textures: (name, texture index).
    pub fn textures(&self) -> Vec<(String, u32)> {
        self.entries
            .iter()
            .filter_map(|(n, e)| match e.value {
                Value::Texture { index, .. } => Some((n.clone(), index)),
                _ => None,
            })
            .collect()
    }

    /// Every parameter as written, for objects whose parameters are read elsewhere
    /// (the integrator). Only booleans, integers, floats and strings are allowed.
    pub fn into_params(self) -> Result<BTreeMap<String, Param>, Error> {
        let mut out = BTreeMap::new();
        for (name, e) in &self.entries {
            let p = match &e.value {
                Value::Boolean(v) => Param::Bool(*v),
                Value::Integer(v) => Param::Integer(*v),
                Value::Float(v) => Param::Float(*v),
                Value::String(v) => Param::String(v.clone()),
                other => {
                    return Err(Error::at(
                        self.file.as_path(),
                        e.line,
                        format!(
                            "parameter '{name}' of {} is {}; only booleans, integers, floats and strings are supported here",
                            self.object,
                            other.type_name()
                        ),
                    ))
                }
            };
            out.insert(name.clone(), p);
        }
        Ok(out)
    }

    /// Errors on the first (by line) parameter no getter read.
    pub fn finish(&self) -> Result<(), Error> {
        let mut unread: Vec<(&String, &Entry)> =
            self.entries.iter().filter(|(_, e)| !e.read.get()).collect();
        unread.sort_by_key(|(_, e)| e.line);
        if let Some((name, e)) = unread.first() {
            let others = if unread.len() > 1 {
                format!(
                    " (also unknown: {})",
                    unread[1..]
                        .iter()
                        .map(|(n, _)| format!("'{n}'"))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            } else {
                String::new()
            };
            return Err(Error::at(
                self.file.as_path(),
                e.line,
                format!("unknown parameter '{name}' for {}{others}", self.object),
            ));
        }
        Ok(())
    }
}

/// `boolean`, `integer`, `float`, `string`, `point`, `vector`.
fn scalar(el: &Element) -> Result<Value, Error> {
    if el.tag == "point" || el.tag == "vector" {
        el.check_attrs(&["name", "value", "x", "y", "z"])?;
        return Ok(match vec3_value(el)? {
            v if el.tag == "point" => Value::Point(v),
            v => Value::Vector(v),
        });
    }
    el.check_attrs(&["name", "value"])?;
    let s = el.require("value")?;
    Ok(match el.tag.as_str() {
        "boolean" => match s.trim().to_ascii_lowercase().as_str() {
            "true" => Value::Boolean(true),
            "false" => Value::Boolean(false),
            _ => {
                return Err(el.err(format!(
                    "could not parse boolean \"{s}\" (must be true or false)"
                )))
            }
        },
        "integer" => Value::Integer(
            s.trim()
                .parse()
                .map_err(|_| el.err(format!("could not parse integer \"{s}\"")))?,
        ),
        "float" => Value::Float(
            parse_number(s).ok_or_else(|| el.err(format!("could not parse float \"{s}\"")))?,
        ),
        _ => Value::String(s.to_string()),
    })
}

/// `value="x,y,z"` (or one number for all three), or `x`, `y`, `z` attributes (default 0).
fn vec3_value(el: &Element) -> Result<Vec3, Error> {
    if let Some(s) = el.attr("value") {
        let v = parse_numbers(s)
            .ok_or_else(|| el.err(format!("could not parse <{}> value \"{s}\"", el.tag)))?;
        return match v.len() {
            1 => Ok(Vec3::splat(v[0] as f32)),
            3 => Ok(Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32)),
            n => Err(el.err(format!(
                "<{}> value needs 1 or 3 numbers, found {n}",
                el.tag
            ))),
        };
    }
    let mut out = Vec3::ZERO;
    for (i, name) in ["x", "y", "z"].iter().enumerate() {
        if let Some(s) = el.attr(name) {
            out[i] = parse_number(s)
                .ok_or_else(|| el.err(format!("could not parse '{name}' = \"{s}\"")))?
                as f32;
        }
    }
    Ok(out)
}

/// `<rgb value="r,g,b">` / `<color value="r,g,b">`, or one value for all three.
fn color(el: &Element) -> Result<Vec3, Error> {
    let s = el.require("value")?;
    let v = parse_numbers(s)
        .ok_or_else(|| el.err(format!("could not parse <{}> value \"{s}\"", el.tag)))?;
    match v.len() {
        1 => Ok(Vec3::splat(v[0] as f32)),
        3 => Ok(Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32)),
        n => Err(el.err(format!(
            "<{}> needs 1 or 3 values, found {n} in \"{s}\"",
            el.tag
        ))),
    }
}

/// `<spectrum value="0.5">` (constant: [`spectrum::constant_to_srgb`]),
/// `value="400:0.1, 500:0.2, ..."` or `filename="x.spd"` (a file of wavelength-value
/// lines, [`spectrum_file`]) (linear sRGB via [`spectrum::spectrum_to_srgb`]), as
/// Mitsuba's RGB variants read them (emitters differ from everything else).
fn spectrum_value(el: &Element, within_emitter: bool) -> Result<Vec3, Error> {
    if let Some(file) = el.attr("filename") {
        if el.attr("value").is_some() {
            return Err(el.err("<spectrum> takes a value or a filename, not both"));
        }
        let path = el
            .resolve(file)
            .map_err(|tried| el.err(format!("spectrum file {tried} not found")))?;
        let (wavelengths, values) = spectrum_file(&path)?;
        return Ok(spectrum_pairs_to_srgb(
            el,
            &wavelengths,
            &values,
            within_emitter,
        ));
    }
    let s = el.require("value")?;
    let toks: Vec<&str> = tokens(s).collect();
    if toks.len() == 1 && !toks[0].contains(':') {
        let v = parse_number(toks[0])
            .ok_or_else(|| el.err(format!("could not parse constant spectrum \"{s}\"")))?;
        return Ok(spectrum::constant_to_srgb(v, within_emitter));
    }
    let mut wavelengths = Vec::with_capacity(toks.len());
    let mut values = Vec::with_capacity(toks.len());
    for t in &toks {
        let pair = t
            .split_once(':')
            .and_then(|(w, v)| Some((parse_number(w)?, parse_number(v)?)))
            .ok_or_else(|| {
                el.err(format!(
                    "could not parse \"{t}\" in <spectrum> (expected wavelength:value pairs)"
                ))
            })?;
        if wavelengths.last().is_some_and(|&last| pair.0 <= last) {
            return Err(el.err("<spectrum> wavelengths must be strictly increasing"));
        }
        wavelengths.push(pair.0);
        values.push(pair.1);
    }
    if wavelengths.is_empty() {
        return Err(el.err("<spectrum> has an empty value"));
    }
    Ok(spectrum_pairs_to_srgb(
        el,
        &wavelengths,
        &values,
        within_emitter,
    ))
}

/// The linear sRGB of the piecewise-linear spectrum of `el` (its parameter name says
/// whether it is clamped to [0, 1]).
fn spectrum_pairs_to_srgb(
    el: &Element,
    wavelengths: &[f64],
    values: &[f64],
    within_emitter: bool,
) -> Vec3 {
    let name = el.attr("name").unwrap_or("");
    let bounded = !UNBOUNDED.contains(&name);
    spectrum::spectrum_to_srgb(wavelengths, values, within_emitter, bounded)
}

/// The wavelengths (nm) and values of a spectrum file (Mitsuba's `.spd`), read as
/// Mitsuba 3.9.1 reads them (`Properties`' spectrum loading; checked against it): one
/// `wavelength value` pair per line, each number parsed from the line's start as C's
/// `strtod` does (leading blanks skipped, anything after the value ignored, so `400
/// 0.5 # note` is fine); a line that is empty or starts with `#` is skipped, any other
/// line without two numbers is an error; at least two entries, wavelengths strictly
/// increasing. Errors name the file and line.
pub fn spectrum_file(path: &std::path::Path) -> Result<(Vec<f64>, Vec<f64>), Error> {
    let text = std::fs::read(path)
        .map_err(|e| Error::file(path, format!("cannot read spectrum file: {e}")))?;
    let text = String::from_utf8_lossy(&text);
    let (mut wavelengths, mut values) = (Vec::new(), Vec::new());
    for (i, line) in text.split('\n').enumerate() {
        let n = i as u32 + 1;
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let shown = line.trim_end();
        let (w, rest) = strtod_prefix(line).ok_or_else(|| {
            Error::at(
                path,
                n,
                format!("could not read a wavelength in \"{shown}\""),
            )
        })?;
        let (v, _) = strtod_prefix(rest)
            .ok_or_else(|| Error::at(path, n, format!("could not read a value in \"{shown}\"")))?;
        if wavelengths.last().is_some_and(|&last| w <= last) {
            return Err(Error::at(
                path,
                n,
                format!(
                    "wavelength {w} does not increase (the line before has {})",
                    wavelengths.last().copied().unwrap_or(w)
                ),
            ));
        }
        wavelengths.push(w);
        values.push(v);
    }
    if wavelengths.len() < 2 {
        return Err(Error::file(
            path,
            format!(
                "a spectrum file needs at least two wavelength-value lines, found {}",
                wavelengths.len()
            ),
        ));
    }
    Ok((wavelengths, values))
}

/// The number at the start of `s` as C's `strtod` reads it (leading blanks skipped,
/// the longest prefix that is a decimal number), and what follows it.
fn strtod_prefix(s: &str) -> Option<(f64, &str)> {
    let t = s.trim_start_matches([' ', '\t', '\r', '\x0b', '\x0c']);
    let b = t.as_bytes();
    let mut end = 0;
    let mut best = None;
    // Candidate ends: the number's characters run [+-]digits[.digits][e[+-]digits];
    // the longest prefix that parses wins.
    while end < b.len() && (b[end].is_ascii_digit() || b"+-.eE".contains(&b[end])) {
        end += 1;
        if let Ok(v) = t[..end].parse::<f64>() {
            best = Some((v, end));
        }
    }
    best.map(|(v, e)| (v, &t[e..]))
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use crate::scene::bsdf::{Bsdf, Conductor, Diffuse};
    use crate::scene::testutil::{error_at, load, mitsuba};
    use crate::scene::Emitter;

    /// A file with a comment line, a blank line and a note after a value, and one with
    /// values past 1.
    const A_SPD: &str = "# test\n400 0.1\n  500   0.5 # mid\n\n600 0.9\n700 0.3\n";
    const BIG_SPD: &str = "400 1.1\n500 2.5\n600 3.9\n700 0.3\n";

    fn close(got: Vec3, want: [f32; 3]) {
        let want = Vec3::from(want);
        assert!(
            (got - want).abs().max_element() <= 2e-6 * want.max_element().max(1.0),
            "{got}, Mitsuba {want}"
        );
    }

    /// Each value as Mitsuba 3.9.1 `scalar_rgb` reads the same files (mi.traverse of
    /// the loaded scene): a reflectance (clamped to [0, 1]), a conductor's eta and k
    /// (not clamped), an emitter's radiance (no D65).
    #[test]
    fn spectrum_files_reduce_to_mitsubas_rgb() {
        let body = r#"<bsdf type="diffuse"><spectrum name="reflectance" filename="a.spd"/></bsdf>
<bsdf type="diffuse"><spectrum name="reflectance" filename="big.spd"/></bsdf>
<bsdf type="conductor"><spectrum name="eta" filename="big.spd"/><spectrum name="k" filename="a.spd"/></bsdf>
<shape type="sphere"><emitter type="area"><spectrum name="radiance" filename="a.spd"/></emitter></shape>"#;
        let s = load(
            &[
                ("s.xml", &mitsuba(body)),
                ("a.spd", A_SPD),
                ("big.spd", BIG_SPD),
            ],
            &[],
        )
        .unwrap();
        let refl = |i: usize| match s.bsdfs[i] {
            Bsdf::Diffuse(Diffuse { reflectance }) => reflectance,
            ref other => panic!("{other:?}"),
        };
        close(refl(0), [0.854797, 0.68754, 0.265015]);
        close(refl(1), [1.0, 1.0, 1.0]);
        let Bsdf::Conductor(Conductor { eta, k, .. }) = s.bsdfs[2] else {
            panic!("{:?}", s.bsdfs[2])
        };
        close(eta, [3.42372, 3.17993, 1.67715]);
        close(k, [0.854797, 0.68754, 0.265015]);
        let Emitter::Area { radiance } = s.emitters[0] else {
            panic!("{:?}", s.emitters[0])
        };
        close(radiance, [0.999234, 0.6597, 0.229444]);
    }

    /// Bad files: an error naming the spectrum file and its line (or the scene's line
    /// for a file that is not there), as Mitsuba refuses the same files.
    #[test]
    fn bad_spectrum_files_name_file_and_line() {
        let scene = |file: &str| {
            mitsuba(&format!(
                "<bsdf type=\"diffuse\"><spectrum name=\"reflectance\" filename=\"{file}\"/></bsdf>"
            ))
        };
        let run = |content: &str| load(&[("s.xml", &scene("x.spd")), ("x.spd", content)], &[]);
        let e = error_at(load(&[("s.xml", &scene("none.spd"))], &[]), "s.xml", 3);
        assert!(e.contains("none.spd") && e.contains("not found"), "{e}");
        let e = error_at(run("400 0.1\n500\n"), "x.spd", 2);
        assert!(e.contains("value"), "{e}");
        let e = error_at(run("400 0.1\n   \n500 0.5\n"), "x.spd", 2);
        assert!(e.contains("wavelength"), "{e}");
        let e = error_at(run("400 0.1\n// c\n"), "x.spd", 2);
        assert!(e.contains("wavelength"), "{e}");
        let e = error_at(run("400,0.1\n500,0.5\n"), "x.spd", 1);
        assert!(e.contains("value"), "{e}");
        let e = error_at(run("500 0.1\n400 0.5\n"), "x.spd", 2);
        assert!(e.contains("increase"), "{e}");
        for one in ["500 0.5\n", "", "# nothing\n"] {
            let e = run(one).unwrap_err().to_string();
            assert!(e.contains("x.spd") && e.contains("at least two"), "{e}");
        }
        // What Mitsuba accepts: tabs, CRLF, exponents, a missing final newline, words
        // after the value.
        for ok in [
            "400\t0.1\r\n500\t0.5\r\n",
            "4e2 0.1\n5e2 0.5",
            "400 0.1x\n500 0.5 y\n",
        ] {
            run(ok).unwrap_or_else(|e| panic!("{ok:?}: {e}"));
        }
        let e = error_at(
            load(
                &[(
                    "s.xml",
                    &mitsuba("<bsdf type=\"diffuse\"><spectrum name=\"reflectance\" filename=\"x.spd\" value=\"0.5\"/></bsdf>"),
                ), ("x.spd", "400 0.1\n500 0.5\n")],
                &[],
            ),
            "s.xml",
            3,
        );
        assert!(e.contains("not both"), "{e}");
    }
}
