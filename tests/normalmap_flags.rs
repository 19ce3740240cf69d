//! `normalmap`'s two flags told apart on the GPU: a plane under two directional lights
//! with a constant normal map tilted 72° towards +x, seen by a radiancemeter from the
//! -x side (where the mapped normal faces away from the viewer, so only
//! `flip_invalid_normals` lets light through) and from the +x side (where the tilt's
//! shadowing term of `use_shadowing_function` takes 8%). Directional lights and a
//! constant map make every value exact: each of the eight (view, flip, shadow) renders
//! equals Mitsuba 3.9.1's (tools/mitsuba_normalmap_flags.py) to 1e-4 of the value, and
//! the settings that differ in Mitsuba differ here by at least 50 times that, so a
//! flag read wrongly, ignored or swapped fails.

mod common;

/// Mitsuba 3.9.1's radiance per (view, flip_invalid_normals, use_shadowing_function).
const MITSUBA: [([f32; 3], bool, bool, f64); 8] = [
    ([-0.8, 0.3, 0.52], false, false, 0.0),
    ([-0.8, 0.3, 0.52], false, true, 0.0),
    ([-0.8, 0.3, 0.52], true, false, 0.1373157),
    ([-0.8, 0.3, 0.52], true, true, 0.1260212),
    ([0.6, 0.3, 0.74], false, false, 0.1068011),
    ([0.6, 0.3, 0.74], false, true, 0.0980165),
    ([0.6, 0.3, 0.74], true, false, 0.1068011),
    ([0.6, 0.3, 0.74], true, true, 0.0980165),
];

fn scene_text(view: [f32; 3], flip: bool, shadow: bool) -> String {
    let map = common::repo("tests/data/normalmap_flags/tilted.exr");
    let [x, y, z] = view;
    format!(
        r#"<scene version="3.0.0">
    <integrator type="direct"/>
    <sensor type="radiancemeter">
        <point name="origin" x="{x}" y="{y}" z="{z}"/>
        <vector name="direction" x="{}" y="{}" z="{}"/>
        <film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/>
            <rfilter type="box"/></film>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><scale value="10"/></transform>
        <bsdf type="normalmap">
            <boolean name="flip_invalid_normals" value="{flip}"/>
            <boolean name="use_shadowing_function" value="{shadow}"/>
            <texture name="normalmap" type="bitmap">
                <string name="filename" value="{}"/>
                <boolean name="raw" value="true"/>
                <string name="filter_type" value="nearest"/>
            </texture>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
        </bsdf>
    </shape>
    <emitter type="directional"><vector name="direction" x="0.5" y="0" z="-0.8"/></emitter>
    <emitter type="directional"><vector name="direction" x="-0.5" y="0" z="-0.8"/></emitter>
</scene>"#,
        -x,
        -y,
        -z,
        map.display()
    )
}

#[test]
fn normalmap_flags_render_as_in_mitsuba() {
    // The settings must be distinguishable at the tolerance: every pair of Mitsuba's
    // values that differ, differs by far more than it.
    let tolerance = |v: f64| 1e-4 * v.max(1e-3);
    for a in &MITSUBA {
        for b in &MITSUBA {
            if a.0 == b.0 && a.3 != b.3 {
                assert!((a.3 - b.3).abs() > 50.0 * tolerance(a.3.max(b.3)));
            }
        }
    }
    let device = common::device();
    for (i, &(view, flip, shadow, expected)) in MITSUBA.iter().enumerate() {
        let path = common::temp_file(
            "normalmap_flags",
            &format!("scene{i}.xml"),
            &scene_text(view, flip, shadow),
        );
        let scene = common::load(&path);
        let value = common::mean(&common::render(&device, &scene, &Default::default(), 16));
        println!("view {view:?} flip {flip} shadow {shadow}: {value:.7} (Mitsuba {expected:.7})");
        assert!(
            (value - expected).abs() <= tolerance(expected),
            "view {view:?}, flip_invalid_normals {flip}, use_shadowing_function {shadow}: {value} against Mitsuba's {expected}"
        );
    }
}
