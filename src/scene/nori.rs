//! The Nori dialect's tree walker: `<scene>` (no version) with `camera`, `sampler`,
//! `integrator`, `mesh` (with a nested `bsdf` and area `emitter`), `emitter` and
//! `medium`.
//!
//! Each object's type and parameters are read by its plugin family (the camera by
//! `super::sensor`, meshes by `super::shape`, emitters by `super::emitter`, ...), whose
//! registries list every Nori type with the parameters it reads (`docs/plugins.md`).
//! Nori has only the `independent` sampler; wavetrace's others may be named too.
//! A top-level `medium` fills the axis-aligned box `bounds_min` .. `bounds_max`: an
//! invisible index-matched box with the medium inside, as the volume-with-bounding-box
//! form of Nori course renderers.

use super::bsdf;
use super::builder::{Builder, MeshOptions};
use super::emitter;
use super::integrator;
use super::properties::Properties;
use super::sensor;
use super::shape;
use super::xml::{Dialect, Document, Element};
use super::{Error, Medium, Sampler, Scene};

/// Loads a Nori scene read by [`super::xml::read`].
pub fn load(doc: &Document) -> Result<Scene, Error> {
    let mut b = Builder::default();
    let mut camera = None;
    let mut sampler_spp = None;
    let mut integrator = None;
    for el in &doc.root.children {
        match el.tag.as_str() {
            "camera" => {
                if camera.is_some() {
                    return Err(el.err("more than one <camera>"));
                }
                camera = Some(sensor::nori(el)?);
            }
            "sampler" => {
                if sampler_spp.is_some() {
                    return Err(el.err("more than one <sampler>"));
                }
                sampler_spp = Some(super::sampler::read(el, Dialect::Nori, "sampleCount", 1)?);
            }
            "integrator" => {
                if integrator.is_some() {
                    return Err(el.err("more than one <integrator>"));
                }
                integrator = Some(integrator::spec(el, Dialect::Nori)?);
            }
            "mesh" => mesh(el, &mut b)?,
            "emitter" => top_emitter(el, &mut b)?,
            "test" => return Err(el.err("Nori <test> scenes are not supported yet")),
            "medium" => medium(el, &mut b)?,
            t => return Err(el.err(format!("unexpected <{t}> in a Nori <scene>"))),
        }
    }
    let (camera, film) = camera.ok_or_else(|| doc.root.err("the scene has no <camera>"))?;
    let integrator = integrator.ok_or_else(|| doc.root.err("the scene has no <integrator>"))?;
    let (sampler, spp) = sampler_spp.unwrap_or((Sampler::default(), 1));
    let sensors = vec![super::sensor::SceneSensor {
        camera: camera.clone(),
        sampler,
        spp,
        film: film.clone(),
        medium: None,
    }];
    Ok(Scene {
        sensors,
        path: doc.root.file.as_ref().clone(),
        camera,
        film,
        spp,
        sampler,
        integrator,
        meshes: b.meshes,
        quadrics: b.quadrics,
        sdfgrids: b.sdfgrids,
        groups: Vec::new(),
        instances: Vec::new(),
        bsdfs: b.bsdfs,
        emitters: b.emitters,
        emitter_weights: b.emitter_weights,
        media: b.media,
        camera_medium: None,
        textures: b.textures,
    })
}

fn mesh(el: &Element, b: &mut Builder) -> Result<(), Error> {
    el.check_attrs(&["type"])?;
    if el.require("type")? != "obj" {
        return Err(shape::unsupported(el, Dialect::Nori));
    }
    let (props, nested) = Properties::read(el, Dialect::Nori, false)?;
    let mut bsdf = None;
    let mut radiance = None;
    for n in nested {
        match n.tag.as_str() {
            "bsdf" if bsdf.is_none() => bsdf = Some(nori_bsdf(n, b)?),
            "emitter" if radiance.is_none() => radiance = Some(emitter::area::nori(n)?),
            "bsdf" | "emitter" => {
                return Err(n.err(format!("a mesh can have only one <{}>", n.tag)))
            }
            "medium" => return Err(n.err("media are not supported yet")),
            t => return Err(n.err(format!("unexpected <{t}> in <mesh>"))),
        }
    }
    let (m, to_world) = shape::obj::nori(el, &props)?;
    let bsdf = match bsdf {
        Some(i) => i,
        None => b.default_bsdf(),
    };
    let emitter = radiance.map(|e| b.add_emitter(e));
    let options = MeshOptions {
        to_world,
        ..MeshOptions::default()
    };
    b.add_mesh(el, m, &options, bsdf, emitter)
}

/// A medium filling an axis-aligned box: a null-BSDF cube with the medium inside.
fn medium(el: &Element, b: &mut Builder) -> Result<(), Error> {
    let (m, (lo, hi)) = Medium::read(el, Dialect::Nori, |props| {
        let lo = props.point_opt("bounds_min")?;
        let hi = props.point_opt("bounds_max")?;
        match (lo, hi) {
            (Some(lo), Some(hi)) if lo.cmplt(hi).all() && lo.is_finite() && hi.is_finite() => {
                Ok((lo, hi))
            }
            (Some(_), Some(_)) => Err(props.error(
                "bounds_max",
                "the medium's bounds_max must exceed bounds_min on every axis",
            )),
            _ => Err(props.object_error(
                "a Nori medium needs 'bounds_min' and 'bounds_max' (the box it fills)",
            )),
        }
    })?;
    if b.media.len() >= 0xfffe {
        return Err(el.err("more than 65534 media"));
    }
    b.media.push(m);
    let index = (b.media.len() - 1) as u32;
    let to_world =
        glam::Mat4::from_translation(0.5 * (lo + hi)) * glam::Mat4::from_scale(0.5 * (hi - lo));
    let bsdf = b.default_bsdf();
    let options = MeshOptions {
        to_world,
        ..MeshOptions::default()
    };
    b.add_mesh(el, super::mesh::cube(), &options, bsdf, None)?;
    if let Some(mesh) = b.meshes.last_mut() {
        mesh.interior = Some(index);
        mesh.null_bsdf = true;
    }
    Ok(())
}

fn nori_bsdf(el: &Element, b: &mut Builder) -> Result<u32, Error> {
    el.check_attrs(&["type"])?;
    let t = el.require("type")?;
    let plugin =
        bsdf::plugin(Dialect::Nori, t).ok_or_else(|| bsdf::unsupported(el, Dialect::Nori))?;
    let (props, nested) = Properties::read(el, Dialect::Nori, false)?;
    if let Some(n) = nested.first() {
        return Err(n.err(format!("unexpected <{}> in <bsdf>", n.tag)));
    }
    let bsdf = plugin
        .read(&props)
        .expect("Nori's BSDFs read their parameters")?;
    props.finish()?;
    Ok(b.add_bsdf(bsdf))
}

fn top_emitter(el: &Element, b: &mut Builder) -> Result<(), Error> {
    el.check_attrs(&["type"])?;
    let t = el.require("type")?;
    let (props, nested) = Properties::read(el, Dialect::Nori, true)?;
    if let Some(n) = nested.first() {
        return Err(n.err(format!("unexpected <{}> in <emitter>", n.tag)));
    }
    let e = emitter::nori(t, el, &props)?;
    props.finish()?;
    b.add_emitter(e);
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::scene::bsdf::{Bsdf, Conductor, Dielectric, Diffuse, NoriMicrofacet};
    use crate::scene::testutil::{error_at, load, TRI_OBJ};
    use crate::scene::Emitter;
    use glam::Vec3;

    const SCENE: &str = r#"<scene>
  <integrator type="path_mis"><integer name="maxDepth" value="5"/></integrator>
  <sampler type="independent"><integer name="sampleCount" value="32"/></sampler>
  <camera type="perspective">
    <transform name="toWorld"><scale value="-1,1,1"/><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
    <float name="fov" value="45"/>
    <integer name="width" value="64"/><integer name="height" value="48"/>
  </camera>
  <mesh type="obj">
    <string name="filename" value="t.obj"/>
    <transform name="toWorld"><translate value="0,0,1"/></transform>
    <bsdf type="diffuse"><color name="albedo" value="0.2,0.4,0.6"/></bsdf>
    <emitter type="area"><color name="radiance" value="3,3,3"/></emitter>
  </mesh>
  <mesh type="obj"><string name="filename" value="t.obj"/></mesh>
  <emitter type="point"><point name="position" value="1,2,3"/><color name="power" value="100,100,100"/></emitter>
  <emitter type="distantdisk"><color name="radiance" value="0.6,0.6,0.6"/><float name="thetaA" value="180"/>
    <transform name="toWorld"><rotate axis="1,0,0" angle="0"/></transform></emitter>
</scene>"#;

    /// Nori's volume-with-bounding-box form: the same medium and boundary as a Mitsuba
    /// null cube with an interior medium.
    #[test]
    fn medium_in_a_box() {
        let nori = r#"<scene>
  <integrator type="vol_path_mis"/>
  <camera type="perspective"/>
  <medium type="homogeneous">
    <color name="sigma_a" value="0.5"/><color name="sigma_s" value="1.5"/>
    <point name="bounds_min" value="-1, 0, 2"/><point name="bounds_max" value="3, 1, 4"/>
    <phase type="hg"><float name="g" value="0.4"/></phase>
  </medium>
</scene>"#;
        let s = load(&[("s.xml", nori)], &[]).unwrap();
        assert_eq!(s.media.len(), 1);
        let m = &s.media[0];
        assert_eq!((m.albedo, m.g), (Vec3::splat(0.75), 0.4));
        let mesh = &s.meshes[0];
        assert!(mesh.null_bsdf && mesh.interior == Some(0) && mesh.exterior.is_none());
        let lo = mesh.positions.iter().fold(Vec3::INFINITY, |a, &p| a.min(p));
        let hi = mesh
            .positions
            .iter()
            .fold(Vec3::NEG_INFINITY, |a, &p| a.max(p));
        assert!(
            (lo - Vec3::new(-1.0, 0.0, 2.0)).abs().max_element() < 1e-6,
            "{lo}"
        );
        assert!(
            (hi - Vec3::new(3.0, 1.0, 4.0)).abs().max_element() < 1e-6,
            "{hi}"
        );
        let bad = nori.replace(r#"<point name="bounds_max" value="3, 1, 4"/>"#, "");
        let text = error_at(load(&[("s.xml", &bad)], &[]), "s.xml", 4);
        assert!(text.contains("bounds_min' and 'bounds_max'"), "{text}");
    }

    #[test]
    fn nori_scene() {
        let s = load(&[("s.xml", SCENE), ("t.obj", TRI_OBJ)], &[]).unwrap();
        assert_eq!(s.integrator.name, "path_mis");
        assert_eq!(s.spp, 32);
        assert_eq!(
            (s.camera.width, s.camera.height, s.camera.fov_x_deg),
            (64, 48, 45.0)
        );
        assert_eq!((s.camera.near_clip, s.camera.far_clip), (1e-4, 1e4));
        // The scene's scale -1 on x then lookat gives a camera x axis of -left = +x;
        // Nori's image x runs along -x, so in our (Mitsuba) frame the axis is -x.
        assert!((s.camera.to_world.x_axis.truncate() + Vec3::X).length() < 1e-6);
        assert_eq!(s.meshes[0].positions[0], Vec3::new(0.0, 0.0, 1.0));
        // Nori does not flip texture coordinates.
        assert_eq!(s.meshes[0].uvs[2], glam::Vec2::new(0.0, 1.0));
        assert_eq!(
            s.bsdfs[s.meshes[0].bsdf as usize],
            Bsdf::Diffuse(Diffuse {
                reflectance: Vec3::new(0.2, 0.4, 0.6)
            })
        );
        assert_eq!(s.bsdfs[s.meshes[1].bsdf as usize], Bsdf::default());
        assert_eq!(
            s.emitters[s.meshes[0].emitter.unwrap() as usize],
            Emitter::Area {
                radiance: Vec3::splat(3.0)
            }
        );
        // Nori power (W) -> intensity (W/sr) = power / 4π, as Mitsuba's intensity.
        let Emitter::Point {
            position,
            intensity,
        } = s.emitters[1]
        else {
            panic!()
        };
        assert_eq!(position, Vec3::new(1.0, 2.0, 3.0));
        assert!((intensity.x - 100.0 / (4.0 * std::f32::consts::PI)).abs() < 1e-5);
        assert_eq!(
            s.emitters[2],
            Emitter::Constant {
                radiance: Vec3::splat(0.6)
            }
        );
    }

    #[test]
    fn nori_defaults() {
        let s = load(
            &[(
                "s.xml",
                "<scene><integrator type=\"normals\"/><camera type=\"perspective\"/></scene>",
            )],
            &[],
        )
        .unwrap();
        assert_eq!(
            (s.camera.width, s.camera.height, s.camera.fov_x_deg, s.spp),
            (1280, 720, 30.0, 1)
        );
        let e = load(
            &[("s.xml", "<scene><camera type=\"perspective\"/></scene>")],
            &[("a", "b")],
        )
        .unwrap_err();
        assert!(e.to_string().contains("Nori"), "{e}");
    }

    #[test]
    fn nori_bsdfs() {
        let mesh = |bsdf: &str| {
            format!("<mesh type=\"obj\"><string name=\"filename\" value=\"t.obj\"/>{bsdf}</mesh>")
        };
        let xml = format!(
            "<scene><integrator type=\"path_mis\"/><camera type=\"perspective\"/>{}{}{}{}</scene>",
            mesh("<bsdf type=\"mirror\"/>"),
            mesh("<bsdf type=\"dielectric\"/>"),
            mesh("<bsdf type=\"dielectric\"><float name=\"intIOR\" value=\"1.33\"/><float name=\"extIOR\" value=\"1.0\"/></bsdf>"),
            mesh("<bsdf type=\"microfacet\"><float name=\"alpha\" value=\"0.28\"/><color name=\"kd\" value=\"0.2,0.2,0.4\"/></bsdf>"),
        );
        let s = load(&[("s.xml", &xml), ("t.obj", TRI_OBJ)], &[]).unwrap();
        assert_eq!(
            s.bsdfs[0],
            Bsdf::Conductor(Conductor {
                eta: Vec3::ZERO,
                k: Vec3::ONE,
                specular_reflectance: Vec3::ONE
            })
        );
        assert!(
            matches!(s.bsdfs[1], Bsdf::Dielectric(Dielectric { eta, .. }) if (eta - 1.5046 / 1.000277).abs() < 1e-6)
        );
        assert!(matches!(s.bsdfs[2], Bsdf::Dielectric(Dielectric { eta, .. }) if eta == 1.33));
        assert_eq!(
            s.bsdfs[3],
            Bsdf::NoriMicrofacet(NoriMicrofacet {
                alpha: 0.28,
                eta: 1.5046 / 1.000277,
                kd: Vec3::new(0.2, 0.2, 0.4)
            })
        );
        let r = crate::gpu::layout::BsdfRecord::from(&s.bsdfs[3]);
        assert!((r.specular_weight - 0.6).abs() < 1e-6, "ks = 1 - max(kd)");
    }

    #[test]
    fn nori_errors() {
        let cam = "<integrator type=\"ao\"/><camera type=\"perspective\"/>";
        let cases: &[(&str, u32, &str)] = &[
            ("<emitter type=\"distantdisk\">\n<float name=\"thetaA\" value=\"30\"/><color name=\"radiance\" value=\"1,1,1\"/></emitter>", 3, "thetaA = 30 is not supported yet"),
            ("<mesh type=\"obj\"><string name=\"filename\" value=\"t.obj\"/>\n<bsdf type=\"polarizer\"/></mesh>", 3, "bsdf type 'polarizer' is not supported yet"),
            ("<mesh type=\"obj\"><string name=\"filename\" value=\"t.obj\"/>\n<bsdf type=\"microfacet\">\n<float name=\"alpha\" value=\"-1\"/></bsdf></mesh>", 4, "must be a finite number >= 0"),
            ("<mesh type=\"obj\"><string name=\"filename\" value=\"t.obj\"/>\n<bsdf type=\"microfacet\">\n<float name=\"int_ior\" value=\"1.5\"/></bsdf></mesh>", 4, "unknown parameter 'int_ior' for bsdf 'microfacet'"),
            ("<mesh type=\"obj\"><string name=\"filename\" value=\"t.obj\"/>\n<bsdf type=\"dielectric\">\n<float name=\"intIOR\" value=\"0\"/></bsdf></mesh>", 4, "'intIOR' must be positive"),
            ("<mesh type=\"obj\"><string name=\"filename\" value=\"t.obj\"/>\n<bsdf type=\"mirror\">\n<float name=\"alpha\" value=\"1\"/></bsdf></mesh>", 4, "unknown parameter 'alpha' for bsdf 'mirror'"),
            ("<mesh type=\"obj\"><string name=\"filename\" value=\"t.obj\"/>\n<bsdf type=\"diffuse\"><color name=\"reflectance\" value=\"1,1,1\"/></bsdf></mesh>", 3, "unknown parameter 'reflectance' for bsdf 'diffuse'"),
            ("<mesh type=\"obj\">\n<string name=\"filename\" value=\"../../pa1/plane.obj\"/></mesh>", 3, "pa1/plane.obj' not found"),
            ("\n<mesh type=\"ply\"/>", 3, "unknown mesh type 'ply'"),
            ("\n<emitter type=\"area\"/>", 3, "nested in a <mesh>"),
            ("\n<rgb name=\"x\" value=\"1\"/>", 3, "unexpected <rgb>"),
            ("\n<test type=\"ttest\"/>", 3, "not supported yet"),
        ];
        for (body, line, msg) in cases {
            let xml = format!("<scene>{cam}\n{body}</scene>");
            let e = error_at(
                load(&[("s.xml", &xml), ("t.obj", TRI_OBJ)], &[]),
                "s.xml",
                *line,
            );
            assert!(e.contains(msg), "{e}\n  wanted: {msg}");
        }
    }
}
