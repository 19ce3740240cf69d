//! The integrator a scene names.

use std::collections::BTreeMap;

/// A parameter value as written in the scene file, before an integrator reads it.
#[derive(Debug, Clone, PartialEq)]
pub enum Param {
    Bool(bool),
    Integer(i64),
    Float(f64),
    String(String),
}

/// The integrator a scene names (`<integrator type="...">`), with its parameters.
///
/// Parameters stay unread here: the renderer knows which integrators exist and reads
/// their parameters with defaults (`render::integrator`), so an unknown key or a name
/// it does not implement is reported there, naming the scene file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct IntegratorSpec {
    /// The type as written (`ao`, `path`, `direct_mis`, ...).
    pub name: String,
    /// Parameters by name; Nori's camelCase names are kept as written.
    pub params: BTreeMap<String, Param>,
    /// Line of the `<integrator>` tag in the scene file, when known.
    pub line: Option<u32>,
}
