//! `mesh_attribute`: a mesh's per-vertex or per-face values as a texture (Mitsuba
//! 3.9.1's `src/textures/mesh_attribute.cpp`, `Mesh::eval_attribute` in
//! `src/render/mesh.cpp`). `name` is the attribute, `vertex_...` or `face_...`;
//! `scale` (1) multiplies it. A vertex attribute is interpolated over the hit triangle
//! by its barycentrics, a face attribute is constant over the face; one value is
//! broadcast to the three channels (and a color read as a float is its luminance).
//! Every mesh whose BSDF or area light reads the texture must have the attribute.
//!
//! Attributes come from PLY files, named as Mitsuba's PLY reader names them
//! ([`ply_attributes`], after `find_other_fields` in Mitsuba's `src/shapes/ply.h`):
//! properties `r`, `g`, `b` (or `red`, `green`, `blue`) become `vertex_color` /
//! `face_color`; properties `{prefix}_{x|y|z}`, `_{r|g|b}`, `_{0|1|2}` or `_{1|2|3}`,
//! consecutive, become the 3-channel `vertex_{prefix}` (`vertex_{prefix}_color` for
//! r, g, b), one such property alone a 1-channel attribute. Integer properties keep
//! their values (255 stays 255), as in Mitsuba. A polygon's face attribute holds for
//! each triangle of its fan.
//!
//! ```xml
//! <bsdf type="diffuse"><texture type="mesh_attribute" name="reflectance"><string name="name" value="vertex_color"/></texture></bsdf>
//! ```
//!
//! On the GPU ([`records`]) the texture's record points at a table with one word per
//! shape, the start of that shape's values among the texels (offset so that the
//! global vertex or triangle number indexes it directly) or `NONE`; texture.glsl reads
//! the hit that the last `surface_at` recorded (its shape, triangle and barycentrics).

use glam::Vec3;

use super::Texture;
use crate::gpu::layout::{TextureRecord, NONE, TEXTURE_ATTRIBUTE_FACE, TEXTURE_MESH_ATTRIBUTE};
use crate::scene::plugin::{Family, Param, PluginDoc};
use crate::scene::properties::Properties;
use crate::scene::xml::Dialect;
use crate::scene::{Error, Mesh, Scene};

pub const MITSUBA: PluginDoc = PluginDoc::new(
    Family::Texture,
    Dialect::Mitsuba,
    "mesh_attribute",
    "A mesh's vertex (interpolated) or face attribute, e.g. a PLY file's vertex colors.",
    &[
        Param::new(
            "name",
            "string",
            "",
            "the attribute, vertex_... or face_... (required)",
        ),
        Param::new("scale", "float", "1", "factor on the attribute's value"),
    ],
);

/// Named per-vertex or per-triangle values of a mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshAttribute {
    /// As a `mesh_attribute` texture names it: `vertex_color`, `face_weight`, ...
    pub name: String,
    /// Values per vertex or face: 1 or 3 (4 for a color with alpha, which no texture
    /// can read, as in Mitsuba).
    pub dim: u32,
    /// `dim` values per vertex (`vertex_...`) or per triangle (`face_...`), in order.
    pub values: Vec<f32>,
}

impl MeshAttribute {
    pub fn is_face(&self) -> bool {
        self.name.starts_with("face_")
    }
}

/// A Mitsuba `mesh_attribute` texture.
pub fn mitsuba(props: &Properties) -> Result<Texture, Error> {
    let name = props
        .string_opt("name")?
        .ok_or_else(|| props.object_error("mesh_attribute needs a 'name' (the attribute)"))?;
    if !(name.starts_with("vertex_") || name.starts_with("face_")) {
        return Err(props.error(
            "name",
            format!(
                "invalid mesh attribute name '{name}': it must start with 'vertex_' or 'face_'"
            ),
        ));
    }
    let scale = props.float("scale", 1.0)?;
    if !scale.is_finite() {
        return Err(props.error("scale", "scale must be finite"));
    }
    Ok(Texture::MeshAttribute { name, scale })
}

/// The attributes Mitsuba's PLY reader makes of the properties of element `element`
/// (`vertex` or `face`), `names` in the file's order (scalar properties only; the
/// ones the reader uses otherwise are skipped): each attribute's name and the
/// properties that hold its channels, in order.
pub fn ply_attributes(element: &str, names: &[&str]) -> Vec<(String, Vec<String>)> {
    let prefix = format!("{element}_");
    let reserved: &[&str] = if element == "vertex" {
        &[
            "x",
            "y",
            "z",
            "nx",
            "ny",
            "nz",
            "u",
            "v",
            "s",
            "t",
            "texture_u",
            "texture_v",
            "texture_s",
            "texture_t",
        ]
    } else {
        &["vertex_indices", "vertex_index"]
    };
    let has = |n: &str| names.contains(&n);
    let mut out = Vec::new();
    // r, g, b (and a), or red, green, blue (and alpha): `{element}_color`.
    let color: Option<Vec<&str>> = if has("r") && has("g") && has("b") {
        Some(if has("a") {
            vec!["r", "g", "b", "a"]
        } else {
            vec!["r", "g", "b"]
        })
    } else if has("red") && has("green") && has("blue") {
        Some(if has("alpha") {
            vec!["red", "green", "blue", "alpha"]
        } else {
            vec!["red", "green", "blue"]
        })
    } else {
        None
    };
    let color_fields: Vec<&str> = color.clone().unwrap_or_default();
    if let Some(c) = color {
        out.push((
            format!("{prefix}color"),
            c.iter().map(|s| s.to_string()).collect(),
        ));
    }
    // Consecutive `{p}_{c}` with c running through one row of postfixes.
    const POSTFIXES: [&[u8; 4]; 4] = [b"xr01", b"yg12", b"zb23", b"wa34"];
    let mut seen: Vec<String> = Vec::new();
    let mut current: Option<(String, usize, Vec<String>)> = None;
    let flush = |cur: &mut Option<(String, usize, Vec<String>)>,
                 out: &mut Vec<(String, Vec<String>)>,
                 seen: &mut Vec<String>| {
        if let Some((p, column, fields)) = cur.take() {
            // Mitsuba keeps 1 or 3 fields (warning otherwise).
            if fields.len() == 1 || fields.len() == 3 {
                let color = if column == 1 { "_color" } else { "" };
                out.push((format!("{prefix}{p}{color}"), fields));
            }
            seen.push(p);
        }
    };
    for &name in names {
        if reserved.contains(&name)
            || color_fields.contains(&name)
            || ["r", "g", "b", "a"].contains(&name)
        {
            continue;
        }
        let Some(pos) = name.rfind('_') else {
            flush(&mut current, &mut out, &mut seen);
            continue;
        };
        let (p, post) = (&name[..pos], &name.as_bytes()[pos + 1..]);
        if post.len() != 1 {
            flush(&mut current, &mut out, &mut seen);
            continue;
        }
        if current.as_ref().is_some_and(|c| c.0 != p) {
            flush(&mut current, &mut out, &mut seen);
        }
        match &mut current {
            None => {
                if seen.iter().any(|s| s == p) {
                    continue;
                }
                if let Some(column) = POSTFIXES[0].iter().position(|&c| c == post[0]) {
                    current = Some((p.to_string(), column, vec![name.to_string()]));
                }
            }
            Some((_, column, fields)) => {
                let level = fields.len();
                if level < 4 && POSTFIXES[level][*column] == post[0] {
                    fields.push(name.to_string());
                } else {
                    // An invalid sequence: the attribute is dropped.
                    seen.push(p.to_string());
                    current = None;
                }
            }
        }
    }
    flush(&mut current, &mut out, &mut seen);
    out
}

/// An error unless every mesh that reads a `mesh_attribute` texture (through its
/// BSDF's textured parameters or normal map, or its area light's radiance) has that
/// attribute with 1 or 3 channels; quadrics have none. The message names the mesh
/// file and the attribute.
pub fn check(scene: &Scene) -> Result<(), Error> {
    let names: Vec<Option<&str>> = scene
        .textures
        .iter()
        .map(|t| match t {
            Texture::MeshAttribute { name, .. } => Some(name.as_str()),
            _ => None,
        })
        .collect();
    if names.iter().all(Option::is_none) {
        return Ok(());
    }
    let read = |bsdf: u32, emitter: Option<u32>| -> Vec<&str> {
        let mut ids = Vec::new();
        if let Some(b) = scene.bsdfs.get(bsdf as usize) {
            bsdf_texture_ids(b, &mut ids);
        }
        if let Some(crate::scene::Emitter::TexturedArea { texture, .. }) =
            emitter.and_then(|e| scene.emitters.get(e as usize))
        {
            ids.push(texture + 1);
        }
        ids.iter()
            .filter(|&&id| id != 0)
            .filter_map(|&id| names.get(id as usize - 1).copied().flatten())
            .collect()
    };
    for mesh in &scene.meshes {
        for name in read(mesh.bsdf, mesh.emitter) {
            let attr = mesh.attributes.iter().find(|a| a.name == name);
            match attr {
                Some(a) if a.dim == 1 || a.dim == 3 => {}
                Some(a) => {
                    return Err(Error::file(
                        std::path::Path::new(&mesh.name),
                        format!(
                            "mesh attribute '{name}' has {} channels; a texture reads 1 or 3",
                            a.dim
                        ),
                    ))
                }
                None => {
                    let have: Vec<&str> = mesh.attributes.iter().map(|a| a.name.as_str()).collect();
                    let have = if have.is_empty() {
                        "it has none".to_string()
                    } else {
                        format!("it has {}", have.join(", "))
                    };
                    return Err(Error::file(
                        std::path::Path::new(&mesh.name),
                        format!("mesh has no attribute '{name}' read by a mesh_attribute texture ({have})"),
                    ));
                }
            }
        }
    }
    for q in &scene.quadrics {
        if let Some(name) = read(q.bsdf, q.emitter).first() {
            let kind = format!("{:?}", q.kind).to_lowercase();
            return Err(Error::file(
                std::path::Path::new(&scene.path),
                format!("a {kind} has no mesh attributes (mesh_attribute '{name}' is read on one)"),
            ));
        }
    }
    Ok(())
}

/// The textures (id + 1) that `b` reads: its leaves' textured parameters and normal
/// maps, and through composites (blendbsdf, mask, twosided, bumpmap) their weights,
/// height fields and both children.
fn bsdf_texture_ids(b: &crate::scene::Bsdf, ids: &mut Vec<u32>) {
    use crate::scene::Bsdf;
    match b {
        Bsdf::Blend { weight, bsdfs } => {
            ids.extend(weight.texture.map(|t| t + 1));
            bsdfs.iter().for_each(|c| bsdf_texture_ids(c, ids));
        }
        Bsdf::Mask { opacity, bsdf } => {
            ids.extend(opacity.texture.map(|t| t + 1));
            bsdf_texture_ids(bsdf, ids);
        }
        Bsdf::TwoSidedPair(bsdfs) => bsdfs.iter().for_each(|c| bsdf_texture_ids(c, ids)),
        Bsdf::BumpMap { params, bsdf } => {
            ids.push(params.texture + 1);
            bsdf_texture_ids(bsdf, ids);
        }
        Bsdf::TwoSided(inner) => bsdf_texture_ids(inner, ids),
        leaf => {
            let r = crate::gpu::layout::BsdfRecord::from(leaf);
            ids.extend([
                r.tex_reflectance,
                r.tex_specular,
                r.tex_transmittance,
                r.tex_alpha_u,
                r.tex_alpha_v,
                r.normal_map,
                r.tex_cond_eta,
                r.tex_cond_k,
                r.tex_eta,
            ]);
        }
    }
}

/// The GPU side of `scene`'s mesh_attribute textures: each one's record (`records[i]`
/// for texture i) gets a table of one word per shape (meshes, then `quadrics` more),
/// appended to `texels` with the attribute values it points at. `vertex_base[k]`:
/// the global number of mesh k's vertex 0 in the triangle records
/// (`render::scene_buffers`); a mesh's triangles are numbered from the sum of the
/// triangle counts before it.
pub fn records(
    scene: &Scene,
    vertex_base: &[u32],
    records: &mut [TextureRecord],
    texels: &mut Vec<f32>,
) {
    for (t, rec) in scene.textures.iter().zip(records.iter_mut()) {
        let Texture::MeshAttribute { name, scale } = t else {
            continue;
        };
        let face = name.starts_with("face_");
        let dim = scene
            .meshes
            .iter()
            .flat_map(|m| m.attributes.iter())
            .find(|a| &a.name == name)
            .map_or(3, |a| a.dim);
        let table = texels.len();
        let shapes = scene.meshes.len() + scene.quadrics.len();
        texels.resize(table + shapes, f32::from_bits(NONE));
        let mut first_triangle = 0u32;
        for (k, mesh) in scene.meshes.iter().enumerate() {
            if let Some(a) = mesh
                .attributes
                .iter()
                .find(|a| &a.name == name && a.dim == dim)
            {
                let start = texels.len() as u32;
                texels.extend_from_slice(&a.values);
                // Indexed by the global vertex or triangle number.
                let first = if face { first_triangle } else { vertex_base[k] };
                texels[table + k] = f32::from_bits(start.wrapping_sub(dim.wrapping_mul(first)));
            }
            first_triangle += mesh.indices.len() as u32;
        }
        *rec = TextureRecord {
            kind: TEXTURE_MESH_ATTRIBUTE,
            offset: table as u32,
            width: dim,
            flags: if face { TEXTURE_ATTRIBUTE_FACE } else { 0 },
            frequency: *scale,
            ..Default::default()
        };
    }
}

/// Whether a texture of `scene` reads vertex attributes: the kernels then need the
/// triangle records (a hit's vertex numbers).
pub fn reads_vertices(scene: &Scene) -> bool {
    scene
        .textures
        .iter()
        .any(|t| matches!(t, Texture::MeshAttribute { name, .. } if name.starts_with("vertex_")))
}

/// The attribute's value at barycentrics (u, v) of triangle `k` of `mesh` (the CPU
/// reference of texture.glsl's lookup), or None without the attribute.
pub fn eval(mesh: &Mesh, name: &str, scale: f32, k: usize, u: f32, v: f32) -> Option<Vec3> {
    let a = mesh.attributes.iter().find(|a| a.name == name)?;
    let d = a.dim as usize;
    let at = |i: usize| {
        if d == 1 {
            Vec3::splat(a.values[i])
        } else {
            Vec3::new(a.values[d * i], a.values[d * i + 1], a.values[d * i + 2])
        }
    };
    let value = if a.is_face() {
        at(k)
    } else {
        let t = mesh.indices[k];
        at(t[0] as usize) * (1.0 - u - v) + at(t[1] as usize) * u + at(t[2] as usize) * v
    };
    Some(value * scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::scene::testutil::{error_at, load, mitsuba};

    /// An ASCII PLY quad (two triangles of one polygon) with vertex colors as uchar
    /// `red green blue` and a face property `weight_0`.
    const QUAD: &str = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement face 1\nproperty list uchar int vertex_indices\nproperty float weight_0\nend_header\n0 0 0 255 0 0\n1 0 0 0 128 0\n1 1 0 0 0 3\n0 1 0 1 2 3\n4 0 1 2 3 0.25\n";

    fn scene(texture: &str, extra: &str) -> String {
        mitsuba(&format!(
            "<texture type=\"mesh_attribute\" id=\"t\">{texture}</texture>\n<shape type=\"ply\"><string name=\"filename\" value=\"q.ply\"/>\n<bsdf type=\"diffuse\"><ref name=\"reflectance\" id=\"t\"/></bsdf></shape>{extra}"
        ))
    }

    #[test]
    fn ascii_ply_attributes_and_lookups() {
        let s = load(
            &[
                (
                    "s.xml",
                    &scene(r#"<string name="name" value="vertex_color"/>"#, ""),
                ),
                ("q.ply", QUAD),
            ],
            &[],
        )
        .unwrap();
        let m = &s.meshes[0];
        let names: Vec<&str> = m.attributes.iter().map(|a| a.name.as_str()).collect();
        assert_eq!(names, ["vertex_color", "face_weight"]);
        assert_eq!(
            m.attributes[0].values[..6],
            [255.0, 0.0, 0.0, 0.0, 128.0, 0.0]
        );
        // The polygon's value on both triangles of its fan.
        assert_eq!(m.attributes[1].values, [0.25, 0.25]);
        // Barycentric interpolation on triangle 0 (vertices 0, 1, 2).
        let c = eval(m, "vertex_color", 2.0, 0, 0.5, 0.25).unwrap();
        assert_eq!(
            c,
            2.0 * (Vec3::new(255.0, 0.0, 0.0) * 0.25
                + Vec3::new(0.0, 128.0, 0.0) * 0.5
                + Vec3::new(0.0, 0.0, 3.0) * 0.25)
        );
        assert_eq!(
            eval(m, "face_weight", 1.0, 1, 0.3, 0.3),
            Some(Vec3::splat(0.25))
        );
    }

    #[test]
    fn errors_name_the_mesh_and_the_attribute() {
        let r = load(
            &[
                (
                    "s.xml",
                    &scene(r#"<string name="name" value="vertex_albedo"/>"#, ""),
                ),
                ("q.ply", QUAD),
            ],
            &[],
        );
        let e = r.unwrap_err().to_string();
        assert!(
            e.contains("q.ply")
                && e.contains("'vertex_albedo'")
                && e.contains("vertex_color, face_weight"),
            "{e}"
        );
        // On a sphere.
        let sphere = r#"<shape type="sphere"><ref id="t"/></shape>"#;
        let xml = mitsuba(&format!(
            "<texture type=\"mesh_attribute\" id=\"t\"><string name=\"name\" value=\"face_weight\"/></texture>\n<bsdf type=\"diffuse\" id=\"b\"><ref name=\"reflectance\" id=\"t\"/></bsdf>{}",
            sphere.replace("<ref id=\"t\"/>", "<ref id=\"b\"/>")
        ));
        let e = load(&[("s.xml", &xml)], &[]).unwrap_err().to_string();
        assert!(e.contains("sphere has no mesh attributes"), "{e}");
        let cases: &[(&str, u32, &str)] = &[
            ("<texture type=\"mesh_attribute\" id=\"t\">\n</texture>", 3, "needs a 'name'"),
            ("<texture type=\"mesh_attribute\" id=\"t\">\n<string name=\"name\" value=\"color\"/></texture>", 4, "must start with 'vertex_' or 'face_'"),
        ];
        for (body, line, msg) in cases {
            let e = error_at(load(&[("s.xml", &mitsuba(body))], &[]), "s.xml", *line);
            assert!(e.contains(msg), "{e}\n  wanted: {msg}");
        }
    }

    #[test]
    fn attributes_read_inside_composites_are_checked() {
        // A blendbsdf's weight, and its second child: both read on the quad.
        let blend = |weight: &str, second: &str| {
            mitsuba(&format!(
                "<shape type=\"ply\"><string name=\"filename\" value=\"q.ply\"/>\n<bsdf type=\"blendbsdf\"><texture type=\"mesh_attribute\" name=\"weight\"><string name=\"name\" value=\"{weight}\"/></texture><bsdf type=\"diffuse\"/><bsdf type=\"diffuse\"><texture type=\"mesh_attribute\" name=\"reflectance\"><string name=\"name\" value=\"{second}\"/></texture></bsdf></bsdf></shape>"
            ))
        };
        let ok = load(
            &[
                ("s.xml", &blend("face_weight", "vertex_color")),
                ("q.ply", QUAD),
            ],
            &[],
        );
        assert!(ok.is_ok(), "{:?}", ok.err());
        for (weight, second, missing) in [
            ("face_wait", "vertex_color", "face_wait"),
            ("face_weight", "vertex_colour", "vertex_colour"),
        ] {
            let e = load(&[("s.xml", &blend(weight, second)), ("q.ply", QUAD)], &[])
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("q.ply") && e.contains(&format!("no attribute '{missing}'")),
                "{e}"
            );
        }
    }

    fn names(element: &str, props: &[&str]) -> Vec<(String, Vec<String>)> {
        ply_attributes(element, props)
    }

    /// Names as Mitsuba 3.9.1 gives them (checked with `mi.traverse` of a PLY mesh,
    /// and the file Mitsuba's `write_ply` writes for the regression suite's
    /// sphere_attribute.ply).
    #[test]
    fn ply_names_as_mitsuba() {
        let v = names(
            "vertex",
            &[
                "x", "y", "z", "nx", "ny", "nz", "u", "v", "color_0", "color_1", "color_2",
            ],
        );
        assert_eq!(
            v,
            vec![(
                "vertex_color".into(),
                vec!["color_0".into(), "color_1".into(), "color_2".into()]
            )]
        );
        let f = names(
            "face",
            &[
                "vertex_indices",
                "color_0",
                "color_1",
                "color_2",
                "weight_0",
            ],
        );
        assert_eq!(f.len(), 2);
        assert_eq!(f[0].0, "face_color");
        assert_eq!(f[1], ("face_weight".into(), vec!["weight_0".into()]));
        let v = names("vertex", &["x", "y", "z", "red", "green", "blue", "temp_x"]);
        assert_eq!(
            v[0],
            (
                "vertex_color".into(),
                vec!["red".into(), "green".into(), "blue".into()]
            )
        );
        assert_eq!(v[1], ("vertex_temp".into(), vec!["temp_x".into()]));
        let v = names(
            "vertex",
            &[
                "x", "y", "z", "albedo_r", "albedo_g", "albedo_b", "n_1", "n_2", "n_3", "q_x",
                "q_y", "plain",
            ],
        );
        let got: Vec<&str> = v.iter().map(|a| a.0.as_str()).collect();
        // Two fields (q_x, q_y) are neither 1 nor 3: dropped, as Mitsuba does.
        assert_eq!(got, ["vertex_albedo_color", "vertex_n"]);
        let v = names("vertex", &["x", "y", "z", "r", "g", "b", "a"]);
        assert_eq!(v[0].1.len(), 4);
    }
}
