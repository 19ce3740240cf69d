//! Meshes handed to the loader in memory by a program that embeds wavetrace (the
//! Python package's `Mesh`, Mitsuba 3's `mi.Mesh`): [`load`] loads a scene file in
//! which `<shape type="mesh">` with `<integer name="provided" value="i"/>` stands for
//! the i-th of the meshes it was given. The shape is otherwise a Mitsuba mesh like a
//! `ply` (`to_world`, `face_normals`, `flip_normals`, a nested BSDF, area emitter and
//! media), except that, as for Mitsuba's `mi.Mesh`, a mesh without vertex normals is
//! flat-shaded (none are computed for it).
//!
//! Not a Mitsuba plugin type, so not in the catalogue: outside [`load`] the type is
//! unknown, as before. No file is written: the loader reads the mesh from a
//! thread-local list for the length of the call.

use std::cell::RefCell;
use std::path::Path;

use super::{Geometry, Mesh};
use crate::scene::properties::Properties;
use crate::scene::xml::{Dialect, Element};
use crate::scene::{Error, Scene};

thread_local! {
    /// The meshes of the [`load`] running on this thread.
    static PROVIDED: RefCell<Option<Vec<Mesh>>> = const { RefCell::new(None) };
}

/// The shape type that names a provided mesh.
pub const TYPE: &str = "mesh";

/// Loads the scene file `path` (as [`crate::scene::load`]) in which
/// `<shape type="mesh">` shapes name `meshes` by their index (`provided`). Each mesh
/// is checked first ([`check`]): the error names the mesh.
pub fn load(path: &Path, defines: &[(String, String)], meshes: Vec<Mesh>) -> Result<Scene, Error> {
    for m in &meshes {
        check(m).map_err(|message| Error::file(&m.name, message))?;
    }
    /// Clears the list however the load ends (a panic included).
    struct Clear;
    impl Drop for Clear {
        fn drop(&mut self) {
            PROVIDED.with(|p| p.borrow_mut().take());
        }
    }
    PROVIDED.with(|p| *p.borrow_mut() = Some(meshes));
    let _clear = Clear;
    crate::scene::load(path, defines)
}

/// Whether a [`load`] with provided meshes runs on this thread.
pub fn active() -> bool {
    PROVIDED.with(|p| p.borrow().is_some())
}

/// The problem with `m`, if any: buffers of the wrong length, a value that is not
/// finite, a face index past the vertices, an attribute that is not `vertex_...` or
/// `face_...` or whose values do not fill its vertices or faces.
pub fn check(m: &Mesh) -> Result<(), String> {
    let n = m.positions.len();
    if !m.normals.is_empty() && m.normals.len() != n {
        return Err(format!(
            "{} vertex normals for {n} vertices",
            m.normals.len()
        ));
    }
    if !m.uvs.is_empty() && m.uvs.len() != n {
        return Err(format!("{} vertex texcoords for {n} vertices", m.uvs.len()));
    }
    if let Some(i) = m.positions.iter().position(|p| !p.is_finite()) {
        return Err(format!(
            "vertex position {i} is not finite: {:?}",
            m.positions[i]
        ));
    }
    if let Some(i) = m.normals.iter().position(|p| !p.is_finite()) {
        return Err(format!(
            "vertex normal {i} is not finite: {:?}",
            m.normals[i]
        ));
    }
    if let Some(i) = m.uvs.iter().position(|p| !p.is_finite()) {
        return Err(format!("vertex texcoord {i} is not finite: {:?}", m.uvs[i]));
    }
    for (f, t) in m.indices.iter().enumerate() {
        if let Some(&i) = t.iter().find(|&&i| i as usize >= n) {
            return Err(format!(
                "face {f} {t:?} names vertex {i}, past the {n} vertices"
            ));
        }
    }
    for a in &m.attributes {
        let count = if a.name.starts_with("vertex_") {
            n
        } else if a.name.starts_with("face_") {
            m.indices.len()
        } else {
            return Err(format!(
                "attribute '{}': its name must start with 'vertex_' or 'face_'",
                a.name
            ));
        };
        if a.dim == 0 || a.values.len() != count * a.dim as usize {
            return Err(format!(
                "attribute '{}' holds {} values: {count} of {} channels need {}",
                a.name,
                a.values.len(),
                a.dim,
                count * a.dim as usize
            ));
        }
        if let Some(i) = a.values.iter().position(|v| !v.is_finite()) {
            return Err(format!(
                "attribute '{}': value {i} is not finite ({})",
                a.name, a.values[i]
            ));
        }
    }
    Ok(())
}

/// A provided mesh's geometry (`<integer name="provided">` picks it), in object
/// space; `face_normals` also where it has no vertex normals (Mitsuba computes none
/// for an `mi.Mesh`).
pub fn mitsuba(el: &Element, props: &Properties) -> Result<Geometry, Error> {
    let index = props.integer_opt("provided")?.ok_or_else(|| {
        props.object_error("a mesh shape needs the index of a provided mesh ('provided')")
    })?;
    let mesh = PROVIDED.with(|p| {
        p.borrow().as_ref().and_then(|list| {
            usize::try_from(index)
                .ok()
                .and_then(|i| list.get(i))
                .cloned()
        })
    });
    let Some(mesh) = mesh else {
        if !active() {
            return Err(super::unsupported(el, Dialect::Mitsuba));
        }
        return Err(props.error("provided", format!("no provided mesh {index}")));
    };
    let to_world = props.transform("to_world")?;
    let face_normals = props.boolean("face_normals", false)? || mesh.normals.is_empty();
    Ok(Geometry::Mesh {
        mesh,
        to_world,
        face_normals,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::texture::mesh_attribute::MeshAttribute;
    use glam::Vec3;

    fn quad() -> Mesh {
        Mesh {
            name: "quad".into(),
            positions: vec![
                Vec3::new(-1.0, -1.0, 0.0),
                Vec3::new(1.0, -1.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(-1.0, 1.0, 0.0),
            ],
            indices: vec![[0, 1, 2], [0, 2, 3]],
            attributes: vec![
                MeshAttribute {
                    name: "vertex_color".into(),
                    dim: 3,
                    values: vec![0.5; 12],
                },
                MeshAttribute {
                    name: "face_weight".into(),
                    dim: 1,
                    values: vec![0.25, 0.75],
                },
            ],
            ..Mesh::default()
        }
    }

    fn load_quad(mesh: Mesh, texture: &str) -> Result<Scene, Error> {
        let dir = crate::scene::testutil::write(
            "provided",
            &[(
                "s.xml",
                &crate::scene::testutil::mitsuba(&format!(
                    r#"<shape type="mesh" id="m"><integer name="provided" value="0"/>
<bsdf type="diffuse"><texture type="mesh_attribute" name="reflectance"><string name="name" value="{texture}"/></texture></bsdf>
</shape>"#
                )),
            )],
        );
        let r = load(&dir.join("s.xml"), &[], vec![mesh]);
        let _ = std::fs::remove_dir_all(&dir);
        r
    }

    #[test]
    fn provided_mesh_keeps_its_attributes_and_stays_flat() {
        let s = load_quad(quad(), "vertex_color").unwrap();
        assert_eq!(s.meshes.len(), 1);
        let m = &s.meshes[0];
        assert_eq!(m.indices, [[0, 1, 2], [0, 2, 3]]);
        assert!(
            m.normals.is_empty(),
            "no vertex normals computed for a provided mesh"
        );
        assert_eq!(m.attributes, quad().attributes);
        assert!(!active(), "the list is cleared after the load");
    }

    #[test]
    fn bad_meshes_are_named() {
        let mut m = quad();
        m.indices[1] = [0, 2, 4];
        let e = load_quad(m, "vertex_color").unwrap_err().to_string();
        assert!(
            e.starts_with("quad: face 1 [0, 2, 4] names vertex 4, past the 4 vertices"),
            "{e}"
        );
        let mut m = quad();
        m.positions[2].y = f32::NAN;
        let e = load_quad(m, "vertex_color").unwrap_err().to_string();
        assert!(e.contains("quad: vertex position 2 is not finite"), "{e}");
        let mut m = quad();
        m.attributes[1].values.pop();
        let e = load_quad(m, "vertex_color").unwrap_err().to_string();
        assert!(
            e.contains("attribute 'face_weight' holds 1 values: 2 of 1 channels need 2"),
            "{e}"
        );
        let e = load_quad(quad(), "vertex_missing").unwrap_err().to_string();
        assert!(
            e.contains("quad: mesh has no attribute 'vertex_missing'"),
            "{e}"
        );
    }

    #[test]
    fn mesh_type_is_unknown_without_provided_meshes() {
        let r = crate::scene::testutil::load(
            &[(
                "s.xml",
                &crate::scene::testutil::mitsuba(
                    r#"<shape type="mesh"><integer name="provided" value="0"/></shape>"#,
                ),
            )],
            &[],
        );
        let e = r.err().map(|e| e.to_string()).unwrap_or_default();
        assert!(e.contains("shape type 'mesh'"), "{e}");
    }
}
