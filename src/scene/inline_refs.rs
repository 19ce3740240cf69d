//! Mitsuba scenes may declare an object once, at the top level with an `id`, and use it
//! by `<ref id="..."/>` anywhere its type is expected: a sampler or film in a sensor,
//! an rfilter in a film, a volume in a medium, a phase function in a medium, a spectrum
//! as a parameter. Mitsuba's parser instantiates the object once and passes it where
//! it is referenced. For these objects, plain values without identity of their own,
//! the same meaning is had by copying the declaration to where each reference stands
//! ([`inline`]) before the scene is loaded; BSDFs, textures, media and emitters,
//! which are built once and shared, keep their references (the loader resolves them).

use std::collections::HashMap;

use super::error::Error;
use super::xml::Element;

/// Tags whose top-level declarations are copied to their references.
const VALUE_TAGS: &[&str] = &["sampler", "film", "rfilter", "volume", "phase", "spectrum"];

/// `root` with every `<ref>` to a top-level declaration of a [`VALUE_TAGS`] object
/// replaced by a copy of it (its `name` attribute taken from the reference, which says
/// which parameter it fills), and those declarations removed from the top level. A
/// declaration without an `id` cannot be referenced and is left where it is (the
/// loader then says it is misplaced).
pub fn inline(root: &Element) -> Result<Element, Error> {
    let declared: HashMap<&str, &Element> = root
        .children
        .iter()
        .filter(|c| VALUE_TAGS.contains(&c.tag.as_str()))
        .filter_map(|c| c.attr("id").map(|id| (id, c)))
        .collect();
    let mut out = root.clone();
    if declared.is_empty() {
        return Ok(out);
    }
    out.children
        .retain(|c| !(VALUE_TAGS.contains(&c.tag.as_str()) && c.attr("id").is_some()));
    for c in &mut out.children {
        replace_refs(c, &declared, 0)?;
    }
    Ok(out)
}

/// Replaces, below `el`, each reference to a declared value object by its copy.
fn replace_refs(
    el: &mut Element,
    declared: &HashMap<&str, &Element>,
    depth: u32,
) -> Result<(), Error> {
    // A declaration referencing itself (through another) would copy forever.
    if depth > 64 {
        return Err(el.err("references nested more than 64 deep (a reference cycle?)"));
    }
    for c in &mut el.children {
        if c.tag == "ref" {
            if let Some(target) = c.attr("id").and_then(|id| declared.get(id)) {
                let mut copy = (*target).clone();
                copy.attrs.retain(|(k, _)| k != "id" && k != "name");
                if let Some(name) = c.attr("name") {
                    copy.attrs.push(("name".into(), name.into()));
                }
                copy.line = c.line;
                *c = copy;
                replace_refs(c, declared, depth + 1)?;
                continue;
            }
        }
        replace_refs(c, declared, depth)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{testutil, xml};

    fn read(text: &str) -> Element {
        let dir = testutil::write("inline-refs", &[("scene.xml", text)]);
        let root = xml::read(&dir.join("scene.xml"), &[]).unwrap().root;
        let _ = std::fs::remove_dir_all(&dir);
        root
    }

    #[test]
    fn a_referenced_sampler_and_film_move_into_the_sensor() {
        let root = read(
            r#"<scene version="3.0.0">
                <sampler type="independent" id="s"><integer name="sample_count" value="4"/></sampler>
                <film type="hdrfilm" id="f"><ref id="r"/></film>
                <rfilter type="gaussian" id="r"/>
                <sensor type="perspective"><ref id="s"/><ref id="f"/></sensor>
            </scene>"#,
        );
        let out = inline(&root).unwrap();
        assert_eq!(out.children.len(), 1, "declarations leave the top level");
        let sensor = &out.children[0];
        let tags: Vec<&str> = sensor.children.iter().map(|c| c.tag.as_str()).collect();
        assert_eq!(tags, ["sampler", "film"]);
        assert_eq!(sensor.children[0].attr("id"), None);
        assert_eq!(
            sensor.children[1].children[0].tag, "rfilter",
            "nested refs too"
        );
        assert_eq!(
            sensor.children[1].children[0].attr("type"),
            Some("gaussian")
        );
    }

    #[test]
    fn a_volume_takes_the_name_of_its_reference() {
        let root = read(
            r#"<scene version="3.0.0">
                <volume type="constvolume" id="v"><rgb name="value" value="0.5"/></volume>
                <medium type="heterogeneous"><ref name="albedo" id="v"/></medium>
            </scene>"#,
        );
        let out = inline(&root).unwrap();
        let albedo = &out.children[0].children[0];
        assert_eq!(albedo.tag, "volume");
        assert_eq!(albedo.attr("name"), Some("albedo"));
    }

    #[test]
    fn other_references_stay() {
        let root = read(
            r#"<scene version="3.0.0">
                <bsdf type="diffuse" id="b"/>
                <shape type="sphere"><ref id="b"/></shape>
            </scene>"#,
        );
        let out = inline(&root).unwrap();
        assert_eq!(out.children.len(), 2);
        assert_eq!(out.children[1].children[0].tag, "ref");
    }

    #[test]
    fn a_scene_declaring_its_sampler_film_and_volume_once_loads_as_written_inline() {
        let declared = testutil::load(
            &[(
                "scene.xml",
                r#"<scene version="3.0.0">
                <sampler type="stratified" id="smp"><integer name="sample_count" value="9"/></sampler>
                <film type="hdrfilm" id="flm"><integer name="width" value="12"/><integer name="height" value="8"/><ref id="rf"/></film>
                <rfilter type="gaussian" id="rf"><float name="stddev" value="0.3"/></rfilter>
                <volume type="constvolume" id="alb"><rgb name="value" value="0.25"/></volume>
                <medium type="homogeneous" id="fog"><float name="sigma_t" value="0.5"/><ref name="albedo" id="alb"/>
                    <boolean name="has_spectral_extinction" value="false"/></medium>
                <sensor type="perspective"><ref id="smp"/><ref id="flm"/><ref id="fog"/></sensor>
                </scene>"#,
            )],
            &[],
        )
        .unwrap();
        let inline = testutil::load(
            &[(
                "scene.xml",
                r#"<scene version="3.0.0">
                <sensor type="perspective">
                    <sampler type="stratified"><integer name="sample_count" value="9"/></sampler>
                    <film type="hdrfilm"><integer name="width" value="12"/><integer name="height" value="8"/>
                        <rfilter type="gaussian"><float name="stddev" value="0.3"/></rfilter></film>
                    <medium type="homogeneous"><float name="sigma_t" value="0.5"/>
                        <volume type="constvolume" name="albedo"><rgb name="value" value="0.25"/></volume></medium>
                </sensor>
                </scene>"#,
            )],
            &[],
        )
        .unwrap();
        assert_eq!(format!("{:?}", declared.film), format!("{:?}", inline.film));
        assert_eq!(
            format!("{:?}", declared.sampler),
            format!("{:?}", inline.sampler)
        );
        assert_eq!(declared.spp, inline.spp);
        assert_eq!(declared.media.len(), 1);
        assert_eq!(declared.media[0].albedo, inline.media[0].albedo);
    }
}
