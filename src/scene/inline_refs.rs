//! Mitsuba scenes may declare an object once, at the top level with an `id`, and use it
//! by `<ref id="..."/>` anywhere its type is expected: a sampler or film in a sensor,
//! an rfilter in a film, a volume in a medium, a phase function in a medium (a
//! `<spectrum>` cannot carry an `id` in Mitsuba, nor here). Mitsuba's parser instantiates the object once and passes it where
//! it is referenced. For these objects, plain values without identity of their own,
//! the same meaning is had by copying the declaration to where each reference stands
//! ([`inline`]) before the scene is loaded; BSDFs, textures, media and emitters,
//! which are built once and shared, keep their references (the loader resolves them).

use std::collections::HashMap;

use super::error::Error;
use super::xml::Element;

/// Tags whose top-level declarations are copied to their references.
const VALUE_TAGS: &[&str] = &["sampler", "film", "rfilter", "volume", "phase"];

/// Where Mitsuba 3.9.1 takes each [`VALUE_TAGS`] object: the tags of the elements a
/// reference to it may stand in (elsewhere Mitsuba's parser reports the object as an
/// unreferenced property, or the plugin as taking no such object).
fn parents(tag: &str) -> &'static [&'static str] {
    match tag {
        "sampler" | "film" => &["sensor"],
        "rfilter" => &["film"],
        "volume" => &["medium", "texture"],
        "phase" => &["medium", "phase"],
        _ => &[],
    }
}

/// `root` with every `<ref>` to a top-level declaration of a [`VALUE_TAGS`] object
/// replaced by a copy of it (its `name` attribute taken from the reference, which says
/// which parameter it fills), and those declarations removed from the top level. A
/// declaration without an `id` cannot be referenced and is left where it is (the
/// loader then says it is misplaced).
pub fn inline(root: &Element) -> Result<Element, Error> {
    refuse_spectrum_ids(root)?;
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

/// Mitsuba's parser refuses an `id` on a `<spectrum>` (it is a value, not an object
/// that can be referenced): so do we, rather than accept a scene Mitsuba refuses.
fn refuse_spectrum_ids(el: &Element) -> Result<(), Error> {
    for c in &el.children {
        if c.tag == "spectrum" && c.attr("id").is_some() {
            return Err(c.err(
                "unexpected attribute \"id\" in <spectrum>: Mitsuba does not let a spectrum be declared once and referenced; write it where it is used",
            ));
        }
        refuse_spectrum_ids(c)?;
    }
    Ok(())
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
            if let Some((id, target)) = c.attr("id").and_then(|id| declared.get_key_value(id)) {
                if !parents(&target.tag).contains(&el.tag.as_str()) {
                    let takes = parents(&target.tag)
                        .iter()
                        .map(|t| format!("<{t}>"))
                        .collect::<Vec<_>>()
                        .join(" or ");
                    return Err(c.err(format!(
                        "<ref id=\"{id}\"> names the <{}> declared at {}:{}, which a <{}> does not take (as in Mitsuba, a <{}> goes in a {takes})",
                        target.tag,
                        target.file.display(),
                        target.line,
                        el.tag,
                        target.tag
                    )));
                }
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

    /// A scene around `body`: a sphere lit by a constant environment, seen by a
    /// perspective sensor unless `body` has one.
    fn scene(body: &str) -> String {
        let sensor = if body.contains("<sensor") {
            ""
        } else {
            r#"<sensor type="perspective"/>"#
        };
        format!(
            r#"<scene version="3.0.0">{sensor}<emitter type="constant"/>
{body}
</scene>"#
        )
    }

    /// Loads `declared` (objects declared once at the top level and referenced) and
    /// `inline` (the same objects written where they are used); the two scenes must
    /// be equal in everything but the file they came from.
    fn same(declared: &str, inline: &str) {
        let load = |body: &str| {
            let mut s = testutil::load(&[("scene.xml", &scene(body))], &[])
                .unwrap_or_else(|e| panic!("{e}\n{body}"));
            s.path = Default::default();
            format!("{s:?}")
        };
        assert_eq!(load(declared), load(inline));
    }

    /// The error loading `body`, which must name the reference's line, its id and
    /// each of `words`.
    fn refused(body: &str, id: &str, words: &[&str]) -> String {
        let e = testutil::load(&[("scene.xml", &scene(body))], &[])
            .err()
            .unwrap_or_else(|| panic!("loaded, but Mitsuba refuses:\n{body}"))
            .to_string();
        assert!(e.contains("scene.xml:"), "{e}");
        assert!(e.contains(&format!("\"{id}\"")), "{e}");
        for w in words {
            assert!(e.contains(w), "'{w}' not in: {e}");
        }
        e
    }

    const SPHERE: &str = r#"<shape type="sphere"><bsdf type="diffuse"/></shape>"#;

    #[test]
    fn a_referenced_sampler_in_a_sensor_is_the_inline_one() {
        same(
            &format!(
                r#"<sampler type="stratified" id="s"><integer name="sample_count" value="16"/></sampler>
                <sensor type="perspective"><ref id="s"/></sensor>{SPHERE}"#
            ),
            &format!(
                r#"<sensor type="perspective"><sampler type="stratified"><integer name="sample_count" value="16"/></sampler></sensor>{SPHERE}"#
            ),
        );
    }

    #[test]
    fn a_referenced_film_in_a_sensor_is_the_inline_one() {
        same(
            &format!(
                r#"<film type="hdrfilm" id="f"><integer name="width" value="20"/><integer name="height" value="10"/></film>
                <sensor type="perspective"><ref id="f"/></sensor>{SPHERE}"#
            ),
            &format!(
                r#"<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="20"/><integer name="height" value="10"/></film></sensor>{SPHERE}"#
            ),
        );
    }

    #[test]
    fn a_referenced_rfilter_in_a_film_is_the_inline_one() {
        same(
            &format!(
                r#"<rfilter type="tent" id="r"><float name="radius" value="1.5"/></rfilter>
                <sensor type="perspective"><film type="hdrfilm"><ref id="r"/></film></sensor>{SPHERE}"#
            ),
            &format!(
                r#"<sensor type="perspective"><film type="hdrfilm"><rfilter type="tent"><float name="radius" value="1.5"/></rfilter></film></sensor>{SPHERE}"#
            ),
        );
    }

    #[test]
    fn a_referenced_texture_in_a_bsdf_is_the_inline_one() {
        same(
            r#"<texture type="checkerboard" id="t"><rgb name="color0" value="0.1, 0.2, 0.3"/></texture>
            <shape type="sphere"><bsdf type="diffuse"><ref name="reflectance" id="t"/></bsdf></shape>"#,
            r#"<shape type="sphere"><bsdf type="diffuse"><texture type="checkerboard" name="reflectance"><rgb name="color0" value="0.1, 0.2, 0.3"/></texture></bsdf></shape>"#,
        );
    }

    #[test]
    fn a_referenced_volume_and_phase_in_a_medium_and_the_medium_in_a_shape_are_the_inline_ones() {
        same(
            r#"<volume type="constvolume" id="v"><rgb name="value" value="0.6"/></volume>
            <phase type="hg" id="p"><float name="g" value="0.4"/></phase>
            <medium type="homogeneous" id="m"><ref name="albedo" id="v"/><ref id="p"/><float name="sigma_t" value="2"/></medium>
            <shape type="sphere"><bsdf type="null"/><ref name="interior" id="m"/></shape>"#,
            r#"<shape type="sphere"><bsdf type="null"/><medium type="homogeneous" name="interior" id="m">
                <volume type="constvolume" name="albedo"><rgb name="value" value="0.6"/></volume>
                <phase type="hg"><float name="g" value="0.4"/></phase><float name="sigma_t" value="2"/></medium></shape>"#,
        );
    }

    #[test]
    fn a_referenced_shape_in_a_shapegroup_joins_it_and_stays_where_declared() {
        same(
            r#"<shape type="sphere" id="sp"><float name="radius" value="0.5"/></shape>
            <shape type="shapegroup" id="g"><ref id="sp"/></shape>
            <shape type="instance"><ref id="g"/></shape>"#,
            r#"<shape type="sphere"><float name="radius" value="0.5"/></shape>
            <shape type="shapegroup" id="g"><shape type="sphere"><float name="radius" value="0.5"/></shape></shape>
            <shape type="instance"><ref id="g"/></shape>"#,
        );
    }

    // Each refusal below is one Mitsuba 3.9.1 refuses as well (checked with
    // `mi.load_string` in scalar_rgb).

    #[test]
    fn an_rfilter_referenced_in_a_sensor_is_refused() {
        refused(
            &format!(
                r#"<rfilter type="box" id="r"/><sensor type="perspective"><ref id="r"/></sensor>{SPHERE}"#
            ),
            "r",
            &["<rfilter>", "<sensor>", "<film>"],
        );
    }

    #[test]
    fn a_film_or_sampler_referenced_outside_a_sensor_is_refused() {
        refused(
            r#"<film type="hdrfilm" id="f"/><shape type="sphere"><ref id="f"/></shape>"#,
            "f",
            &["<film>", "<shape>", "<sensor>"],
        );
        refused(
            r#"<sampler type="independent" id="s"/><shape type="sphere"><bsdf type="diffuse"><ref id="s"/></bsdf></shape>"#,
            "s",
            &["<sampler>", "<bsdf>"],
        );
    }

    #[test]
    fn a_medium_referenced_in_a_medium_is_refused() {
        refused(
            r#"<medium type="homogeneous" id="m0"/><medium type="homogeneous" id="m"><ref id="m0"/></medium>
            <sensor type="perspective"><ref id="m"/></sensor>"#,
            "m0",
            &["<medium type=\"homogeneous\">", "a <medium> does not take"],
        );
    }

    #[test]
    fn a_volume_referenced_in_a_bsdf_is_refused() {
        refused(
            r#"<volume type="constvolume" id="v"/><shape type="sphere"><bsdf type="diffuse"><ref name="reflectance" id="v"/></bsdf></shape>"#,
            "v",
            &["<volume>", "<bsdf>"],
        );
    }

    #[test]
    fn a_bsdf_or_texture_referenced_in_a_sensor_is_refused() {
        refused(
            &format!(
                r#"<bsdf type="diffuse" id="b"/><sensor type="perspective"><ref id="b"/></sensor>{SPHERE}"#
            ),
            "b",
            &["<bsdf type=\"diffuse\">", "<sensor>"],
        );
        refused(
            &format!(
                r#"<texture type="checkerboard" id="t"/><sensor type="perspective"><ref id="t"/></sensor>{SPHERE}"#
            ),
            "t",
            &["<texture type=\"checkerboard\">", "<sensor>"],
        );
    }

    #[test]
    fn a_shape_referenced_in_a_shape_is_refused() {
        refused(
            r#"<shape type="sphere" id="sp"/><shape type="cube"><ref id="sp"/></shape>"#,
            "sp",
            &["<shape type=\"sphere\">", "a <shape> does not take"],
        );
    }

    #[test]
    fn an_area_emitter_referenced_by_two_shapes_is_refused() {
        refused(
            r#"<emitter type="area" id="e"><rgb name="radiance" value="1"/></emitter>
            <shape type="sphere"><ref id="e"/></shape><shape type="cube"><ref id="e"/></shape>"#,
            "e",
            &["single shape"],
        );
    }

    #[test]
    fn a_spectrum_with_an_id_is_refused() {
        refused(
            r#"<spectrum id="s" value="0.3"/><shape type="sphere"><bsdf type="diffuse"><ref name="reflectance" id="s"/></bsdf></shape>"#,
            "id",
            &["<spectrum>"],
        );
    }
}
