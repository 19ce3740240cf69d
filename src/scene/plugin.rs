//! What every plugin family shares: the catalogue entry of one plugin type.
//!
//! Each family (`bsdf/`, `emitter/`, `shape/`, ...) keeps one registry, a list of
//! [`PluginDoc`]s beside the functions that read and pack each type. The parser's
//! "not supported yet" and "unknown" errors, `wavetrace info` and `docs/plugins.md`
//! are all derived from those registries, so a plugin is declared in one place
//! (Mitsuba 3's `MI_REGISTER_PLUGIN`, one line per plugin).

use std::fmt::Write;

use super::xml::{Dialect, Element};
use super::Error;

/// A plugin family: the XML tag its objects are written with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Family {
    Bsdf,
    Emitter,
    Shape,
    Sensor,
    Film,
    ReconstructionFilter,
    Sampler,
    Texture,
    Medium,
    Phase,
    Volume,
    Integrator,
}

impl Family {
    /// The tag of an object of this family in a Mitsuba scene (`rfilter` for
    /// reconstruction filters; Nori writes some families with other tags).
    pub fn tag(self) -> &'static str {
        match self {
            Family::Bsdf => "bsdf",
            Family::Emitter => "emitter",
            Family::Shape => "shape",
            Family::Sensor => "sensor",
            Family::Film => "film",
            Family::ReconstructionFilter => "rfilter",
            Family::Sampler => "sampler",
            Family::Texture => "texture",
            Family::Medium => "medium",
            Family::Phase => "phase",
            Family::Volume => "volume",
            Family::Integrator => "integrator",
        }
    }

    /// The tag in `dialect`: Nori writes shapes as `<mesh>` and sensors as `<camera>`.
    pub fn tag_in(self, dialect: Dialect) -> &'static str {
        match (self, dialect) {
            (Family::Shape, Dialect::Nori) => "mesh",
            (Family::Sensor, Dialect::Nori) => "camera",
            _ => self.tag(),
        }
    }
}

/// Whether wavetrace renders a plugin type, or knows the name but lacks it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Support {
    /// Read and rendered.
    Yes,
    /// A type of Mitsuba 3 or Nori that wavetrace does not implement yet: a scene
    /// naming it gets "not supported yet" instead of "unknown".
    NotYet,
}

/// One parameter a plugin reads: its name in the scene file, its type as written
/// there (`float`, `rgb`, `texture`, `string`, `boolean`, `integer`, `point`,
/// `transform`, ...; `float|texture` where either is accepted), its default (empty
/// when it has none or must be given) and one line of meaning. `with`: the parameter
/// it is read only together with (`alpha_u` with `alpha_v`), or empty.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Param {
    pub name: &'static str,
    pub ty: &'static str,
    pub default: &'static str,
    pub doc: &'static str,
    pub with: &'static str,
}

impl Param {
    pub const fn new(
        name: &'static str,
        ty: &'static str,
        default: &'static str,
        doc: &'static str,
    ) -> Param {
        Param {
            name,
            ty,
            default,
            doc,
            with: "",
        }
    }

    /// The same parameter, read only together with `partner`.
    pub const fn with(self, partner: &'static str) -> Param {
        Param {
            with: partner,
            ..self
        }
    }
}

/// The catalogue entry of one plugin type of one dialect.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PluginDoc {
    pub family: Family,
    /// The `type` attribute that selects it.
    pub name: &'static str,
    pub dialect: Dialect,
    pub support: Support,
    /// One sentence: what it is.
    pub summary: &'static str,
    /// The parameters read, in the order the manual lists them (none for
    /// [`Support::NotYet`]).
    pub params: &'static [Param],
}

impl PluginDoc {
    /// A supported plugin.
    pub const fn new(
        family: Family,
        dialect: Dialect,
        name: &'static str,
        summary: &'static str,
        params: &'static [Param],
    ) -> PluginDoc {
        PluginDoc {
            family,
            name,
            dialect,
            support: Support::Yes,
            summary,
            params,
        }
    }

    /// A type of the dialect that wavetrace does not implement yet.
    pub const fn not_yet(family: Family, dialect: Dialect, name: &'static str) -> PluginDoc {
        PluginDoc {
            family,
            name,
            dialect,
            support: Support::NotYet,
            summary: "",
            params: &[],
        }
    }
}

/// The error for an object whose `type` no supported entry of `registry` names:
/// "`<tag>` type 'X' is not supported yet" for a type the registry lists as
/// [`Support::NotYet`], "unknown `<tag>` type 'X'" (with the supported types) for any
/// other; at the element's line.
pub fn unsupported(
    el: &Element,
    family: Family,
    dialect: Dialect,
    registry: &[PluginDoc],
) -> Error {
    let t = el.attr("type").unwrap_or("");
    let tag = family.tag_in(dialect);
    let of_dialect = || {
        registry
            .iter()
            .filter(|p| p.family == family && p.dialect == dialect)
    };
    if of_dialect().any(|p| p.name == t && p.support == Support::NotYet) {
        return el.err(format!("{tag} type '{t}' is not supported yet"));
    }
    let known: Vec<&str> = of_dialect()
        .filter(|p| p.support == Support::Yes)
        .map(|p| p.name)
        .collect();
    if known.is_empty() {
        el.err(format!("unknown {tag} type '{t}'"))
    } else {
        el.err(format!(
            "unknown {tag} type '{t}' (supported: {})",
            known.join(", ")
        ))
    }
}

/// The supported entry of `registry` for `family`, `dialect` and type `t`.
pub fn find<'a>(
    registry: &'a [PluginDoc],
    family: Family,
    dialect: Dialect,
    t: &str,
) -> Option<&'a PluginDoc> {
    registry.iter().find(|p| {
        p.family == family && p.dialect == dialect && p.name == t && p.support == Support::Yes
    })
}

/// Every plugin type of both dialects, family by family: the registries concatenated.
/// `docs/plugins.md` is [`markdown`] of it.
pub fn catalogue() -> Vec<PluginDoc> {
    [
        super::bsdf::REGISTRY,
        super::emitter::REGISTRY,
        super::shape::REGISTRY,
        super::sensor::REGISTRY,
        super::film::REGISTRY,
        super::sampler::REGISTRY,
        super::texture::REGISTRY,
        super::medium::REGISTRY,
        super::integrator::REGISTRY,
    ]
    .concat()
}

/// `docs/plugins.md`: one section per dialect and family, a table of the supported
/// types with their parameters, then the types not supported yet.
pub fn markdown(catalogue: &[PluginDoc]) -> String {
    let mut s = String::from(
        "# Plugins\n\n\
         Every scene object type wavetrace reads, by dialect and family, with the\n\
         parameters it reads (name, type, default, meaning). Generated from the\n\
         plugin registries in `src/scene/` (`cargo test --lib plugin_docs` checks it;\n\
         `WAVETRACE_WRITE_DOCS=1 cargo test --lib plugin_docs` rewrites it).\n",
    );
    for (dialect, title) in [(Dialect::Mitsuba, "Mitsuba 3"), (Dialect::Nori, "Nori")] {
        let mut families: Vec<Family> = catalogue
            .iter()
            .filter(|p| p.dialect == dialect)
            .map(|p| p.family)
            .collect();
        families.sort();
        families.dedup();
        for family in families {
            let _ = write!(s, "\n## {title}: `<{}>`\n", family.tag_in(dialect));
            let of = |support| {
                catalogue.iter().filter(move |p| {
                    p.dialect == dialect && p.family == family && p.support == support
                })
            };
            for p in of(Support::Yes) {
                let _ = write!(s, "\n### `{}`\n\n{}\n", p.name, p.summary);
                if !p.params.is_empty() {
                    s.push_str(
                        "\n| parameter | type | default | meaning |\n| --- | --- | --- | --- |\n",
                    );
                    for q in p.params {
                        let default = if q.default.is_empty() {
                            "—"
                        } else {
                            q.default
                        };
                        let _ = writeln!(
                            s,
                            "| `{}` | {} | {} | {} |",
                            q.name,
                            q.ty.replace('|', " or "),
                            default.replace('|', "\\|"),
                            q.doc.replace('|', "\\|")
                        );
                    }
                }
            }
            let missing: Vec<String> = of(Support::NotYet)
                .map(|p| format!("`{}`", p.name))
                .collect();
            if !missing.is_empty() {
                let _ = write!(s, "\nNot supported yet: {}.\n", missing.join(", "));
            }
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    const PARAMS: &[Param] = &[Param::new("reflectance", "rgb|texture", "0.5", "albedo")];
    const REGISTRY: &[PluginDoc] = &[
        PluginDoc::new(
            Family::Bsdf,
            Dialect::Mitsuba,
            "diffuse",
            "Lambertian.",
            PARAMS,
        ),
        PluginDoc::not_yet(Family::Bsdf, Dialect::Mitsuba, "hair"),
    ];

    /// The first child of a Mitsuba scene holding `xml`.
    fn element(xml: &str) -> Element {
        let dir = std::env::temp_dir().join(format!("wavetrace-plugin-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let path = dir.join(format!("{}.xml", xml.len()));
        std::fs::write(&path, format!(r#"<scene version="3.0.0">{xml}</scene>"#)).expect("write");
        let doc = super::super::xml::read(&path, &[]).expect("test XML parses");
        doc.root.children[0].clone()
    }

    #[test]
    fn errors_tell_not_yet_from_unknown() {
        let hair = element(r#"<bsdf type="hair"/>"#);
        let e = unsupported(&hair, Family::Bsdf, Dialect::Mitsuba, REGISTRY).to_string();
        assert!(e.contains("bsdf type 'hair' is not supported yet"), "{e}");
        let typo = element(r#"<bsdf type="difuse"/>"#);
        let e = unsupported(&typo, Family::Bsdf, Dialect::Mitsuba, REGISTRY).to_string();
        assert!(
            e.contains("unknown bsdf type 'difuse' (supported: diffuse)"),
            "{e}"
        );
        assert!(find(REGISTRY, Family::Bsdf, Dialect::Mitsuba, "diffuse").is_some());
        assert!(find(REGISTRY, Family::Bsdf, Dialect::Mitsuba, "hair").is_none());
        assert!(find(REGISTRY, Family::Bsdf, Dialect::Nori, "diffuse").is_none());
    }

    /// docs/plugins.md is the registries' markdown; `WAVETRACE_WRITE_DOCS=1` rewrites it.
    #[test]
    fn plugin_docs_match_the_registries() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/plugins.md");
        let text = markdown(&catalogue());
        if std::env::var("WAVETRACE_WRITE_DOCS").as_deref() == Ok("1") {
            std::fs::create_dir_all(path.parent().expect("docs folder")).expect("mkdir docs");
            std::fs::write(&path, &text).expect("write docs/plugins.md");
            return;
        }
        let on_disk = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            on_disk == text,
            "docs/plugins.md differs from the plugin registries: rewrite it with \
             WAVETRACE_WRITE_DOCS=1 cargo test --lib plugin_docs"
        );
    }

    /// No two entries of one family and dialect share a name.
    #[test]
    fn plugin_docs_name_each_type_once() {
        let all = catalogue();
        for (i, p) in all.iter().enumerate() {
            assert!(
                !all[..i]
                    .iter()
                    .any(|q| (q.family, q.dialect, q.name) == (p.family, p.dialect, p.name)),
                "{:?} {:?} '{}' is listed twice",
                p.dialect,
                p.family,
                p.name
            );
        }
    }

    /// A value tag for parameter `q` that its plugin accepts, or `None` where the
    /// test cannot make one (files, textures, volumes).
    fn value_tag(q: &Param, dialect: Dialect) -> Option<String> {
        let ty = q.ty.split('|').next().unwrap_or("");
        let number = |fallback: &str| {
            if q.default.parse::<f64>().is_ok() {
                q.default.to_string()
            } else {
                fallback.to_string()
            }
        };
        let name = q.name;
        Some(match ty {
            "float" => format!(r#"<float name="{name}" value="{}"/>"#, number("0.5")),
            "integer" => {
                let v = if name == "resolution" {
                    "8".into()
                } else {
                    number("1")
                };
                format!(r#"<integer name="{name}" value="{v}"/>"#)
            }
            "boolean" => {
                let v = if q.default == "true" { "true" } else { "false" };
                format!(r#"<boolean name="{name}" value="{v}"/>"#)
            }
            "rgb" | "color" => {
                let tag = if dialect == Dialect::Nori {
                    "color"
                } else {
                    "rgb"
                };
                format!(r#"<{tag} name="{name}" value="{}"/>"#, number("0.5"))
            }
            "point" => {
                let v = match (q.default, name) {
                    (_, "bounds_max") => "1,1,1",
                    ("", _) => "0,0,0",
                    (d, _) => d,
                };
                format!(r#"<point name="{name}" value="{v}"/>"#)
            }
            "vector" => format!(r#"<vector name="{name}" value="0,0,1"/>"#),
            "transform" => {
                format!(r#"<transform name="{name}"><translate value="0,0,0"/></transform>"#)
            }
            "string" if !q.default.is_empty() && !q.default.contains(' ') => {
                format!(r#"<string name="{name}" value="{}"/>"#, q.default)
            }
            _ => return None,
        })
    }

    /// A Mitsuba scene holding plugin `p` with the value tags `body`, or `None` for
    /// the families this test does not place.
    fn scene_with(p: &PluginDoc, body: &str) -> Option<String> {
        let t = p.name;
        let sensor = |inner: &str| format!(r#"<sensor type="perspective">{inner}</sensor>"#);
        let default_sensor = sensor("");
        let objects = match p.family {
            Family::Emitter if t == "area" => format!(
                r#"{default_sensor}<shape type="rectangle"><emitter type="area">{}{body}</emitter></shape>"#,
                if body.contains(r#"name="radiance""#) {
                    ""
                } else {
                    r#"<rgb name="radiance" value="1"/>"#
                }
            ),
            Family::Emitter if t == "directionalarea" => format!(
                r#"{default_sensor}<shape type="rectangle"><emitter type="{t}">{body}</emitter></shape>"#
            ),
            Family::Emitter => format!(r#"{default_sensor}<emitter type="{t}">{body}</emitter>"#),
            // An instance needs its group.
            Family::Shape if t == "instance" => format!(
                r#"{default_sensor}<shape type="shapegroup" id="g"><shape type="cube"/></shape><shape type="instance"><ref id="g"/>{body}</shape>"#
            ),
            Family::Shape => format!(r#"{default_sensor}<shape type="{t}">{body}</shape>"#),
            // A thin lens needs its aperture whatever else is given.
            Family::Sensor if t == "thinlens" && !body.contains("aperture_radius") => sensor(
                &format!(r#"<float name="aperture_radius" value="0.1"/>{body}"#),
            )
            .replace("perspective", t),
            // A radiance meter needs a 1 x 1 film.
            Family::Sensor if matches!(t, "radiancemeter" | "distant") => sensor(&format!(
                r#"<film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/></film>{body}"#
            ))
            .replace("perspective", t),
            Family::Sensor => sensor(body).replace("perspective", t),
            Family::Film => sensor(&format!(r#"<film type="{t}">{body}</film>"#)),
            Family::ReconstructionFilter => sensor(&format!(
                r#"<film type="hdrfilm"><rfilter type="{t}">{body}</rfilter></film>"#
            )),
            Family::Sampler => sensor(&format!(r#"<sampler type="{t}">{body}</sampler>"#)),
            Family::Texture => format!(
                r#"{default_sensor}<shape type="rectangle"><bsdf type="diffuse"><texture type="{t}" name="reflectance">{body}</texture></bsdf></shape>"#
            ),
            Family::Medium => format!(
                r#"{default_sensor}<shape type="cube"><bsdf type="null"/><medium type="{t}" name="interior">{body}</medium></shape>"#
            ),
            Family::Phase => format!(
                r#"{default_sensor}<shape type="cube"><bsdf type="null"/><medium type="homogeneous" name="interior"><phase type="{t}">{body}</phase></medium></shape>"#
            ),
            Family::Volume => format!(
                r#"{default_sensor}<shape type="cube"><bsdf type="null"/><medium type="heterogeneous" name="interior"><volume type="{t}" name="sigma_t">{}{body}</volume></medium></shape>"#,
                if matches!(t, "cloud" | "perlin") && !body.contains("resolution") {
                    r#"<integer name="resolution" value="8"/>"#
                } else {
                    ""
                }
            ),
            // A normal map needs its texture and a nested BSDF besides its flags.
            Family::Bsdf if t == "normalmap" => format!(
                r#"{default_sensor}<shape type="rectangle"><bsdf type="{t}"><texture type="checkerboard" name="normalmap"/><bsdf type="diffuse"/>{body}</bsdf></shape>"#
            ),
            // Composites need their nested BSDFs (and a bump map its height field).
            Family::Bsdf if matches!(t, "mask" | "blendbsdf" | "bumpmap") => format!(
                r#"{default_sensor}<shape type="rectangle"><bsdf type="{t}">{}<bsdf type="diffuse"/>{}{body}</bsdf></shape>"#,
                if t == "bumpmap" {
                    r#"<texture type="checkerboard" name="h"/>"#
                } else {
                    ""
                },
                if t == "blendbsdf" {
                    r#"<bsdf type="diffuse"/>"#
                } else {
                    ""
                },
            ),
            Family::Bsdf => format!(
                r#"{default_sensor}<shape type="rectangle"><bsdf type="{t}">{body}</bsdf></shape>"#
            ),
            Family::Integrator => return None,
        };
        Some(format!("<scene version=\"3.0.0\">\n{objects}\n</scene>\n"))
    }

    /// Every parameter a Mitsuba registry lists is one its plugin reads: a scene
    /// giving it (alone, with a value the plugin accepts) loads without "unknown
    /// parameter". Plugins that need a file, and parameters of texture or volume
    /// type, are left out.
    #[test]
    fn plugin_docs_list_parameters_the_parser_reads() {
        // Read only beside a parameter of another kind than this test gives: an area
        // emitter's scale multiplies a radiance texture; fov_axis says along which
        // axis fov is measured. Pairs (`Param::with`) are given together.
        // A mesh_attribute names an attribute that the rectangle here does not have.
        const ONLY_WITH_OTHERS: &[(&str, &str)] = &[
            ("area", "scale"),
            ("perspective", "fov_axis"),
            ("thinlens", "fov_axis"),
            ("projector", "fov_axis"),
            ("mesh_attribute", "name"),
            ("mesh_attribute", "scale"),
        ];
        let mut checked = 0;
        let mut failed = Vec::new();
        for p in catalogue() {
            if p.dialect != Dialect::Mitsuba || p.support != Support::Yes {
                continue;
            }
            if p.params.iter().any(|q| q.name == "filename") {
                continue;
            }
            for q in p.params {
                if ONLY_WITH_OTHERS.contains(&(p.name, q.name)) {
                    continue;
                }
                let Some(mut tag) = value_tag(q, Dialect::Mitsuba) else {
                    continue;
                };
                if !q.with.is_empty() {
                    let partner = p.params.iter().find(|o| o.name == q.with);
                    let Some(partner_tag) = partner.and_then(|o| value_tag(o, Dialect::Mitsuba))
                    else {
                        failed.push(format!(
                            "'{}' '{}': no partner '{}'",
                            p.name, q.name, q.with
                        ));
                        continue;
                    };
                    tag += &partner_tag;
                }
                let Some(xml) = scene_with(&p, &tag) else {
                    continue;
                };
                let r = crate::scene::testutil::load(&[("s.xml", &xml)], &[]);
                if let Err(e) = r {
                    failed.push(format!(
                        "{:?} '{}' parameter '{}': {e}\n{xml}",
                        p.family, p.name, q.name
                    ));
                }
                checked += 1;
            }
        }
        assert!(failed.is_empty(), "{}", failed.join("\n"));
        assert!(checked > 50, "only {checked} parameters checked");
    }

    /// A Nori scene holding plugin `p` with the value tags `body`, or `None` for the
    /// families this test does not place.
    fn nori_scene_with(p: &PluginDoc, body: &str) -> Option<String> {
        let t = p.name;
        let has = |name: &str| body.contains(&format!(r#"name="{name}""#));
        let given = |name: &str, tag: &str| {
            if has(name) {
                String::new()
            } else {
                tag.to_string()
            }
        };
        let camera = r#"<camera type="perspective"/>"#;
        let objects = match p.family {
            Family::Sensor => format!(r#"<camera type="{t}">{body}</camera>"#),
            Family::ReconstructionFilter => {
                format!(
                    r#"<camera type="perspective"><rfilter type="{t}">{body}</rfilter></camera>"#
                )
            }
            Family::Sampler => format!(r#"{camera}<sampler type="{t}">{body}</sampler>"#),
            Family::Emitter if t == "area" => format!(
                r#"{camera}<mesh type="obj"><string name="filename" value="t.obj"/><emitter type="area">{}{body}</emitter></mesh>"#,
                given("radiance", r#"<color name="radiance" value="1"/>"#)
            ),
            Family::Emitter => format!(
                r#"{camera}<emitter type="{t}">{}{}{body}</emitter>"#,
                if t == "point" {
                    given("power", r#"<color name="power" value="1"/>"#)
                } else {
                    String::new()
                },
                if t == "distantdisk" {
                    given("radiance", r#"<color name="radiance" value="1"/>"#)
                } else {
                    String::new()
                },
            ),
            Family::Shape => format!(
                r#"{camera}<mesh type="{t}">{}{body}</mesh>"#,
                given("filename", r#"<string name="filename" value="t.obj"/>"#)
            ),
            Family::Medium => format!(
                r#"{camera}<medium type="{t}">{}{}{body}</medium>"#,
                given("bounds_min", r#"<point name="bounds_min" value="0,0,0"/>"#),
                given("bounds_max", r#"<point name="bounds_max" value="1,1,1"/>"#)
            ),
            Family::Bsdf => format!(
                r#"{camera}<mesh type="obj"><string name="filename" value="t.obj"/><bsdf type="{t}">{body}</bsdf></mesh>"#
            ),
            _ => return None,
        };
        Some(format!(
            "<scene>\n<integrator type=\"normals\"/>\n{objects}\n</scene>\n"
        ))
    }

    /// The same for Nori's registries.
    #[test]
    fn plugin_docs_list_nori_parameters_the_parser_reads() {
        let mut checked = 0;
        let mut failed = Vec::new();
        for p in catalogue() {
            if p.dialect != Dialect::Nori || p.support != Support::Yes {
                continue;
            }
            for q in p.params {
                let Some(tag) = value_tag(q, Dialect::Nori) else {
                    continue;
                };
                let Some(xml) = nori_scene_with(&p, &tag) else {
                    continue;
                };
                let files = [
                    ("s.xml", xml.as_str()),
                    ("t.obj", crate::scene::testutil::TRI_OBJ),
                ];
                if let Err(e) = crate::scene::testutil::load(&files, &[]) {
                    failed.push(format!(
                        "{:?} '{}' parameter '{}': {e}\n{xml}",
                        p.family, p.name, q.name
                    ));
                }
                checked += 1;
            }
        }
        assert!(failed.is_empty(), "{}", failed.join("\n"));
        assert!(checked > 30, "only {checked} parameters checked");
    }

    /// Every parameter an integrator's registry entry lists is one it reads.
    #[test]
    fn plugin_docs_list_integrator_parameters_read() {
        use crate::scene::integrator::{self, IntegratorSpec, Param as Value};
        for p in integrator::REGISTRY {
            // `aov` wraps another integrator (its `aovs` is read by scene::integrator::aov).
            if p.support != Support::Yes || p.name == "aov" {
                continue;
            }
            for q in p.params {
                let value = match q.ty {
                    "integer" => Value::Integer(q.default.parse().unwrap_or(1)),
                    "float" => Value::Float(q.default.parse().unwrap_or(0.5)),
                    "boolean" => Value::Bool(false),
                    _ => Value::String(q.default.split(' ').next().unwrap_or("").to_string()),
                };
                let spec = IntegratorSpec {
                    name: p.name.to_string(),
                    params: [(q.name.to_string(), value)].into_iter().collect(),
                    line: Some(1),
                    ..Default::default()
                };
                if let Err(e) = integrator::read(&spec, None) {
                    panic!(
                        "integrator '{}' parameter '{}': {}",
                        p.name, q.name, e.message
                    );
                }
            }
        }
    }

    #[test]
    fn markdown_lists_parameters_and_missing_types() {
        let md = markdown(REGISTRY);
        assert!(md.contains("## Mitsuba 3: `<bsdf>`"), "{md}");
        assert!(
            md.contains("| `reflectance` | rgb or texture | 0.5 | albedo |"),
            "{md}"
        );
        assert!(md.contains("Not supported yet: `hair`."), "{md}");
        assert!(!md.contains("## Nori"), "{md}");
    }
}
