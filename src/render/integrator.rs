//! Integrators: which wavefront schedule and shading code a render runs, and their
//! parameters as read from the scene.

use std::path::Path;

use crate::scene::integrator::{IntegratorSpec, Param};

use super::error::{Error, Result};

/// An integrator with its parameters read.
#[derive(Debug, Clone, PartialEq)]
pub enum Integrator {
    /// Debug view of the shading normal, |n| per component (Nori's `normals`).
    Normals,
    /// Ambient occlusion (1/π)∫V(x,ω)cosθ dω over the hemisphere of the shading
    /// normal (Nori's `ao`). Camera rays that hit nothing are black, as in Nori.
    ///
    /// Parameters: `max_t` (float, default infinity): occluders farther than this are
    /// ignored, so a closed room is not black; `sampling` (string, `cosine` (default)
    /// or `uniform`): how hemisphere directions are drawn.
    ///
    /// ```xml
    /// <integrator type="ao"><float name="max_t" value="2"/></integrator>
    /// ```
    Ao { max_t: f32, uniform: bool },
    /// Point lights on diffuse surfaces with shadows (Nori's `simple`): one point
    /// light chosen uniformly per sample, L = (ρ/π) I cosθ / d². Uses the surface's
    /// diffuse reflectance where Nori's assignment assumes ρ = 1.
    Simple,
}

/// Names `--integrator` and scenes may use in this version.
pub const NAMES: &[&str] = &["normals", "ao", "simple"];

impl Integrator {
    /// The id of the shading code (`INTEGRATOR_*` in shaders/common/integrator.glsl).
    pub fn id(&self) -> u32 {
        match self {
            Integrator::Normals => 0,
            Integrator::Ao { .. } => 1,
            Integrator::Simple => 2,
        }
    }

    pub fn name(&self) -> &'static str {
        match self {
            Integrator::Normals => "normals",
            Integrator::Ao { .. } => "ao",
            Integrator::Simple => "simple",
        }
    }

    /// Longest path in segments: 1 for every integrator of this version.
    pub fn max_depth(&self) -> u32 {
        1
    }

    /// Reads the integrator the scene names, or `override_name` instead (the scene's
    /// parameters apply only if the override names the same integrator).
    pub fn from_spec(
        spec: &IntegratorSpec,
        override_name: Option<&str>,
        scene_file: &Path,
    ) -> Result<Integrator> {
        let err = |line: Option<u32>, message: String| Error::Integrator {
            file: scene_file.to_path_buf(),
            line,
            message,
        };
        let (name, params, line) = match override_name {
            Some(n) if n != spec.name => (n, Default::default(), None),
            _ => (spec.name.as_str(), spec.params.clone(), spec.line),
        };
        let mut params = params;
        let mut take = |key: &str| params.remove(key);
        let integrator = match name {
            "normals" => Integrator::Normals,
            "simple" => Integrator::Simple,
            "ao" => {
                let max_t = match take("max_t") {
                    None => f32::INFINITY,
                    Some(Param::Float(v)) if v > 0.0 => v as f32,
                    Some(Param::Integer(v)) if v > 0 => v as f32,
                    Some(p) => {
                        return Err(err(
                            line,
                            format!("integrator 'ao': max_t must be a positive float, got {p:?}"),
                        ))
                    }
                };
                let uniform = match take("sampling") {
                    None => false,
                    Some(Param::String(s)) if s == "cosine" => false,
                    Some(Param::String(s)) if s == "uniform" => true,
                    Some(p) => {
                        return Err(err(
                            line,
                            format!("integrator 'ao': sampling must be \"cosine\" or \"uniform\", got {p:?}"),
                        ))
                    }
                };
                Integrator::Ao { max_t, uniform }
            }
            "" => {
                return Err(err(
                    line,
                    format!(
                        "the scene names no integrator; choose one with --integrator ({})",
                        NAMES.join(", ")
                    ),
                ))
            }
            other => {
                return Err(err(
                    line,
                    format!(
                        "integrator '{other}' is not implemented in this version; available: {}",
                        NAMES.join(", ")
                    ),
                ))
            }
        };
        if let Some(key) = params.keys().next() {
            return Err(err(
                line,
                format!("integrator '{name}' has no parameter '{key}'"),
            ));
        }
        Ok(integrator)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(name: &str, params: &[(&str, Param)]) -> IntegratorSpec {
        IntegratorSpec {
            name: name.into(),
            params: params
                .iter()
                .map(|(k, v)| (k.to_string(), v.clone()))
                .collect(),
            line: Some(7),
        }
    }

    #[test]
    fn reads_ao_parameters() {
        let s = spec(
            "ao",
            &[
                ("max_t", Param::Float(2.5)),
                ("sampling", Param::String("uniform".into())),
            ],
        );
        let i = Integrator::from_spec(&s, None, Path::new("a.xml")).unwrap();
        assert_eq!(
            i,
            Integrator::Ao {
                max_t: 2.5,
                uniform: true
            }
        );
        let d = Integrator::from_spec(&spec("ao", &[]), None, Path::new("a.xml")).unwrap();
        assert_eq!(
            d,
            Integrator::Ao {
                max_t: f32::INFINITY,
                uniform: false
            }
        );
    }

    #[test]
    fn unknown_key_and_bad_values_name_file_and_line() {
        let e = Integrator::from_spec(
            &spec("ao", &[("maxt", Param::Float(1.0))]),
            None,
            Path::new("s.xml"),
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "s.xml:7: integrator 'ao' has no parameter 'maxt'"
        );
        let e = Integrator::from_spec(
            &spec("ao", &[("max_t", Param::Float(-1.0))]),
            None,
            Path::new("s.xml"),
        )
        .unwrap_err();
        assert!(e
            .to_string()
            .starts_with("s.xml:7: integrator 'ao': max_t must be a positive float"));
        let e =
            Integrator::from_spec(&spec("path_mis", &[]), None, Path::new("s.xml")).unwrap_err();
        assert!(
            e.to_string().contains("'path_mis' is not implemented"),
            "{e}"
        );
    }

    #[test]
    fn override_replaces_the_scene_integrator_and_drops_its_parameters() {
        let s = spec("path", &[("max_depth", Param::Integer(5))]);
        let i = Integrator::from_spec(&s, Some("ao"), Path::new("s.xml")).unwrap();
        assert_eq!(
            i,
            Integrator::Ao {
                max_t: f32::INFINITY,
                uniform: false
            }
        );
        let e = Integrator::from_spec(&s, Some("bogus"), Path::new("s.xml")).unwrap_err();
        assert!(e.to_string().contains("'bogus' is not implemented"));
    }
}
