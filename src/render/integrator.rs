//! Integrators: which wavefront schedule and shading code a render runs. What each
//! integrator is and the parameters it reads live in `scene::integrator`.

use std::path::Path;

use crate::scene::integrator::{self, IntegratorSpec};
pub use crate::scene::integrator::{
    Integrator, PathParams, PhotonBudget, PhotonMapperParams, SppmParams, MAX_BOUNCES,
};

use super::error::{Error, Result};

/// Camera paths of the photon mappers play Russian roulette from this depth on, as
/// the path tracers do by default.
pub const PHOTON_CAMERA_RR_DEPTH: u32 = 5;

impl Integrator {
    /// The id of the shading code (`INTEGRATOR_*` in shaders/integrator/integrator.glsl).
    pub fn id(&self) -> u32 {
        match self {
            Integrator::Normals => 0,
            Integrator::Ao { .. } => 1,
            Integrator::Simple => 2,
            Integrator::DirectEms { .. } => 3,
            Integrator::DirectMats { .. } => 4,
            Integrator::DirectMis { .. } => 5,
            Integrator::PathMats(_) => 6,
            Integrator::PathMis(_) => 7,
            Integrator::VolPathSimple(_) => 8,
            Integrator::VolPathMis(_) => 9,
            Integrator::SingleScatter {
                equiangular: false, ..
            } => 10,
            Integrator::SingleScatter { .. } => 11,
            Integrator::PhotonMapper(_) => 12,
            Integrator::Sppm(_) => 13,
            Integrator::Ptracer(_) => 14,
            Integrator::Depth => 15,
        }
    }

    /// Whether the integrator follows light through media.
    pub fn is_volumetric(&self) -> bool {
        matches!(
            self,
            Integrator::VolPathSimple(_)
                | Integrator::VolPathMis(_)
                | Integrator::SingleScatter { .. }
        )
    }

    pub fn name(&self) -> &'static str {
        match self {
            Integrator::Normals => "normals",
            Integrator::Ao { .. } => "ao",
            Integrator::Simple => "simple",
            Integrator::DirectEms { .. } => "direct_ems",
            Integrator::DirectMats { .. } => "direct_mats",
            Integrator::DirectMis { .. } => "direct_mis",
            Integrator::PathMats(_) => "path_mats",
            Integrator::PathMis(_) => "path_mis",
            Integrator::VolPathSimple(_) => "vol_path_simple",
            Integrator::VolPathMis(_) => "vol_path_mis",
            Integrator::SingleScatter { .. } => "single_scatter",
            Integrator::PhotonMapper(_) => "photonmapper",
            Integrator::Sppm(_) => "sppm",
            Integrator::Ptracer(_) => "ptracer",
            Integrator::Depth => "depth",
        }
    }

    /// Longest path in segments (`u32::MAX`: unbounded), as the kernels see it.
    pub fn max_depth(&self) -> u32 {
        match self {
            Integrator::Normals
            | Integrator::Ao { .. }
            | Integrator::Simple
            | Integrator::Depth => 1,
            Integrator::DirectEms { .. }
            | Integrator::DirectMats { .. }
            | Integrator::DirectMis { .. }
            | Integrator::SingleScatter { .. } => 2,
            Integrator::PathMats(p)
            | Integrator::PathMis(p)
            | Integrator::VolPathSimple(p)
            | Integrator::VolPathMis(p)
            | Integrator::Ptracer(p) => p.max_depth.unwrap_or(u32::MAX),
            Integrator::PhotonMapper(_) => u32::MAX,
            // pbrt's maxdepth d samples light at camera vertices 0 .. d-1: d + 1 segments.
            Integrator::Sppm(p) => p.max_depth.map_or(u32::MAX, |d| d + 1),
        }
    }

    /// Bounces the host dispatches: one per path vertex that can still add light.
    pub fn bounces(&self) -> u32 {
        match self {
            Integrator::Normals
            | Integrator::Ao { .. }
            | Integrator::Simple
            | Integrator::Depth
            | Integrator::DirectEms { .. } => 1,
            Integrator::DirectMats { .. }
            | Integrator::DirectMis { .. }
            | Integrator::SingleScatter { .. } => 2,
            Integrator::PathMats(p)
            | Integrator::PathMis(p)
            | Integrator::VolPathSimple(p)
            | Integrator::VolPathMis(p) => p.max_depth.unwrap_or(MAX_BOUNCES).min(MAX_BOUNCES),
            Integrator::PhotonMapper(_) => MAX_BOUNCES,
            Integrator::Sppm(p) => p
                .max_depth
                .map_or(MAX_BOUNCES, |d| (d + 1).min(MAX_BOUNCES)),
            // A light path's surfaces: depths 1 .. max_depth - 1 are connected.
            Integrator::Ptracer(p) => p
                .max_depth
                .map_or(MAX_BOUNCES, |d| (d - 1).min(MAX_BOUNCES)),
        }
    }

    /// Whether bounce `depth` of a path batch only ends paths: `shade` (path.glsl)
    /// adds the emission its rays find and spawns nothing, since a further vertex
    /// would exceed max_depth (depth + 2 > max_depth). The renderer runs such
    /// bounces with `shade_last`, whose BSDF and sampling code compiles away. Only
    /// where `shade` runs path vertices ([`Self::shades_paths`]).
    pub fn ends_paths_at(&self, depth: u32) -> bool {
        self.shades_paths() && depth.saturating_add(2) > self.max_depth()
    }

    /// Whether `shade` runs the path vertices of path.glsl (direct lighting, path
    /// tracers, volumetric ones): not the first-hit integrators (first_hit.glsl) nor
    /// the photon mappers (their own kernels).
    pub fn shades_paths(&self) -> bool {
        let first_hit = matches!(
            self,
            Integrator::Normals | Integrator::Ao { .. } | Integrator::Simple | Integrator::Depth
        );
        !first_hit && !self.is_photon_mapper()
    }

    /// Whether the integrator is a photon mapper (`render::photon` runs it), or the
    /// particle tracer, which traces light paths with the photon mappers' kernels and
    /// buffers.
    pub fn is_photon_mapper(&self) -> bool {
        matches!(
            self,
            Integrator::PhotonMapper(_) | Integrator::Sppm(_) | Integrator::Ptracer(_)
        )
    }

    /// Russian roulette start depth (segments); never for non-path integrators.
    pub fn rr_depth(&self) -> u32 {
        match self {
            Integrator::PathMats(p)
            | Integrator::PathMis(p)
            | Integrator::VolPathSimple(p)
            | Integrator::VolPathMis(p)
            | Integrator::Ptracer(p) => p.rr_depth,
            Integrator::PhotonMapper(_) | Integrator::Sppm(_) => PHOTON_CAMERA_RR_DEPTH,
            _ => u32::MAX,
        }
    }

    /// Whether the image comes from emitters (everything but the `normals` and `ao`
    /// views): a scene without any renders black.
    pub fn needs_emitters(&self) -> bool {
        !matches!(
            self,
            Integrator::Normals | Integrator::Ao { .. } | Integrator::Depth
        )
    }

    /// Whether MIS weighs by the power heuristic (else the balance heuristic).
    pub fn power_heuristic(&self) -> bool {
        match self {
            Integrator::PathMis(p) | Integrator::VolPathMis(p) => p.power_heuristic,
            Integrator::DirectMis {
                power_heuristic, ..
            } => *power_heuristic,
            // pbrt-v4's SPPM weighs emitter and BSDF sampling by the power heuristic.
            Integrator::Sppm(_) => true,
            _ => false,
        }
    }

    /// Whether a visible environment makes every camera path count as covered for the
    /// film's alpha: Mitsuba's `path` and `volpath` start `valid_ray` as "emitters
    /// visible and an environment present"; its `direct` and first-hit integrators
    /// count only camera rays that hit something.
    pub fn counts_environment_coverage(&self) -> bool {
        matches!(
            self,
            Integrator::PathMats(_)
                | Integrator::PathMis(_)
                | Integrator::VolPathSimple(_)
                | Integrator::VolPathMis(_)
                | Integrator::SingleScatter { .. }
        )
    }

    /// Whether camera rays skip the emission of the emitters they hit.
    pub fn hide_emitters(&self) -> bool {
        match self {
            Integrator::DirectEms { hide_emitters }
            | Integrator::DirectMats { hide_emitters }
            | Integrator::DirectMis { hide_emitters, .. }
            | Integrator::SingleScatter { hide_emitters, .. } => *hide_emitters,
            Integrator::PathMats(p)
            | Integrator::PathMis(p)
            | Integrator::VolPathSimple(p)
            | Integrator::VolPathMis(p)
            | Integrator::Ptracer(p) => p.hide_emitters,
            _ => false,
        }
    }

    /// Reads the integrator the scene names, or `override_name` instead (the scene's
    /// parameters apply only if the override names the same integrator).
    pub fn from_spec(
        spec: &IntegratorSpec,
        override_name: Option<&str>,
        scene_file: &Path,
    ) -> Result<Integrator> {
        integrator::read(spec, override_name).map_err(|e| Error::Integrator {
            file: scene_file.to_path_buf(),
            line: e.line,
            message: e.message,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::integrator::Param;

    fn spec(name: &str, params: &[(&str, Param)]) -> IntegratorSpec {
        IntegratorSpec {
            name: name.into(),
            params: params
                .iter()
                .map(|(k, v)| (k.to_string(), v.clone()))
                .collect(),
            line: Some(7),
            ..Default::default()
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
    fn bounces_that_only_end_paths() {
        let path = |max_depth| {
            Integrator::PathMis(PathParams {
                max_depth,
                rr_depth: 5,
                hide_emitters: false,
                power_heuristic: true,
            })
        };
        // max_depth 3: vertices at depths 0 and 1 sample further segments, 2 ends.
        let p = path(Some(3));
        assert_eq!(p.bounces(), 3);
        assert_eq!(
            (0..3).map(|d| p.ends_paths_at(d)).collect::<Vec<_>>(),
            [false, false, true]
        );
        assert!(path(Some(1)).ends_paths_at(0));
        assert!(!(0..MAX_BOUNCES).any(|d| path(None).ends_paths_at(d)));
        // direct_*: the BSDF-sampled ray's vertex only adds emission.
        let direct = Integrator::DirectMis {
            hide_emitters: false,
            power_heuristic: false,
        };
        assert!(!direct.ends_paths_at(0) && direct.ends_paths_at(1));
        assert!(!Integrator::DirectEms {
            hide_emitters: false
        }
        .ends_paths_at(0));
        // First-hit integrators and photon mappers shade in their own ways.
        assert!(!Integrator::Simple.ends_paths_at(0));
        assert!(!Integrator::Normals.ends_paths_at(5));
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
        let e = Integrator::from_spec(&spec("bdpt", &[]), None, Path::new("s.xml")).unwrap_err();
        assert!(e.to_string().contains("'bdpt' is not implemented"), "{e}");
        let e = Integrator::from_spec(
            &spec("path", &[("max_depth", Param::Integer(0))]),
            None,
            Path::new("s.xml"),
        )
        .unwrap_err();
        assert!(e.to_string().contains("max_depth must be -1"), "{e}");
    }

    #[test]
    fn mitsuba_names_map_to_the_mis_integrators() {
        let i = Integrator::from_spec(
            &spec("path", &[("max_depth", Param::Integer(6))]),
            None,
            Path::new("a"),
        )
        .unwrap();
        assert_eq!(
            i,
            Integrator::PathMis(PathParams {
                max_depth: Some(6),
                rr_depth: 5,
                hide_emitters: false,
                power_heuristic: true,
            })
        );
        assert_eq!((i.max_depth(), i.bounces()), (6, 6));
        assert!(i.power_heuristic());
        let d = Integrator::from_spec(&spec("direct", &[]), None, Path::new("a")).unwrap();
        assert_eq!(
            d,
            Integrator::DirectMis {
                hide_emitters: false,
                power_heuristic: true,
            }
        );
        let u = Integrator::from_spec(&spec("path_mats", &[]), None, Path::new("a")).unwrap();
        assert_eq!((u.max_depth(), u.bounces()), (u32::MAX, MAX_BOUNCES));
    }

    #[test]
    fn mis_heuristic_defaults_per_integrator_and_is_checked() {
        let read = |name: &str, params: &[(&str, Param)]| {
            Integrator::from_spec(&spec(name, params), None, Path::new("s.xml"))
        };
        assert!(read("path_mis", &[]).unwrap().power_heuristic());
        assert!(!read("volpath", &[]).unwrap().power_heuristic());
        assert!(!read("direct_mis", &[]).unwrap().power_heuristic());
        assert!(read("direct", &[]).unwrap().power_heuristic());
        let balance = [("mis_heuristic", Param::String("balance".into()))];
        assert!(!read("path", &balance).unwrap().power_heuristic());
        let power = [("mis_heuristic", Param::String("power".into()))];
        assert!(read("vol_path_mis", &power).unwrap().power_heuristic());
        let bad = [("mis_heuristic", Param::String("maximum".into()))];
        let e = read("path", &bad).unwrap_err();
        assert!(e.to_string().contains("mis_heuristic must be"), "{e}");
        assert!(
            read("direct", &power).is_err(),
            "direct_mis takes no mis_heuristic"
        );
    }

    #[test]
    fn override_replaces_the_scene_integrator_and_keeps_only_parameters_it_reads() {
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
        // A path tracer keeps the depth of the scene's path tracer.
        let p = Integrator::from_spec(&s, Some("path_mats"), Path::new("s.xml")).unwrap();
        assert_eq!(p.max_depth(), 5);
    }

    #[test]
    fn reads_the_photon_mappers_parameters_by_either_name() {
        let read = |name: &str, params: &[(&str, Param)]| {
            Integrator::from_spec(&spec(name, params), None, Path::new("s.xml"))
        };
        assert_eq!(
            read("photonmapper", &[]).unwrap(),
            Integrator::PhotonMapper(PhotonMapperParams {
                photon_count: 1_000_000,
                radius: None
            })
        );
        let pm = read(
            "photonmapper",
            &[
                ("photonCount", Param::Integer(5_000_000)),
                ("photonRadius", Param::Float(1.0)),
            ],
        )
        .unwrap();
        assert_eq!(
            pm,
            Integrator::PhotonMapper(PhotonMapperParams {
                photon_count: 5_000_000,
                radius: Some(1.0)
            })
        );
        assert!(pm.is_photon_mapper());
        assert_eq!((pm.max_depth(), pm.bounces()), (u32::MAX, MAX_BOUNCES));
        assert_eq!(
            read("photonmapper", &[("photonRadius", Param::Float(0.0))]).unwrap(),
            read("photonmapper", &[]).unwrap()
        );
        for bad in [
            ("photonCount", Param::Integer(0)),
            ("photonRadius", Param::Float(-1.0)),
            ("photonRadius", Param::String("big".into())),
        ] {
            let e = read("photonmapper", std::slice::from_ref(&bad)).unwrap_err();
            assert!(e.to_string().contains(bad.0), "{e}");
        }

        let d = read("sppm", &[]).unwrap();
        assert_eq!(
            d,
            Integrator::Sppm(SppmParams {
                max_depth: Some(5),
                radius: None,
                photons: PhotonBudget::Emitted(None),
                alpha: 2.0 / 3.0,
            })
        );
        // pbrt's maxdepth 5: light sampled at camera vertices 0-4, 6 segments.
        assert_eq!((d.max_depth(), d.bounces()), (6, 6));
        assert!(d.power_heuristic());
        let pbrt = read(
            "sppm",
            &[
                ("maxdepth", Param::Integer(8)),
                ("radius", Param::Float(0.25)),
                ("photonsperiteration", Param::Integer(10_000)),
                ("alpha", Param::Float(0.7)),
            ],
        )
        .unwrap();
        let mitsuba = read(
            "sppm",
            &[
                ("maxDepth", Param::Integer(8)),
                ("initialRadius", Param::Float(0.25)),
                ("photonCount", Param::Integer(10_000)),
                ("alpha", Param::Float(0.7)),
            ],
        )
        .unwrap();
        let Integrator::Sppm(p) = pbrt else {
            panic!("sppm")
        };
        let Integrator::Sppm(m) = mitsuba else {
            panic!("sppm")
        };
        assert_eq!(
            (p.max_depth, p.radius, p.alpha),
            (m.max_depth, m.radius, m.alpha)
        );
        assert_eq!(p.photons, PhotonBudget::Emitted(Some(10_000)));
        assert_eq!(m.photons, PhotonBudget::Stored(10_000));
        // Mitsuba's initialRadius 0 is automatic; pbrt's radius must be positive.
        assert!(matches!(
            read("sppm", &[("initialRadius", Param::Float(0.0))]).unwrap(),
            Integrator::Sppm(SppmParams { radius: None, .. })
        ));
        assert!(read("sppm", &[("radius", Param::Float(0.0))]).is_err());
        let both = read(
            "sppm",
            &[
                ("maxdepth", Param::Integer(3)),
                ("maxDepth", Param::Integer(4)),
            ],
        )
        .unwrap_err();
        assert!(
            both.to_string().contains("either maxdepth or maxDepth"),
            "{both}"
        );
        for bad in [
            ("alpha", Param::Float(1.0)),
            ("maxdepth", Param::Integer(0)),
            ("photonsperiteration", Param::Integer(0)),
            ("granularity", Param::Integer(100)),
        ] {
            let e = read("sppm", std::slice::from_ref(&bad)).unwrap_err();
            assert!(e.to_string().contains(bad.0), "{e}");
        }
        assert!(
            read("sppm", &[("maxdepth", Param::Integer(-1))])
                .unwrap()
                .max_depth()
                == u32::MAX
        );
    }
}
