#!/usr/bin/env python3
"""Renders tests/data/aov/aov_scene.xml with Mitsuba 3.9.1 (scalar_rgb) to
aov_scene_ref.exr (float32, every channel as Mitsuba names it): 1 spp of the
stratified sampler without jitter, so every camera ray goes through its pixel's
centre, as wavetrace's does (tests/aov.rs). Run from the repository root."""
import mitsuba as mi

mi.set_variant("scalar_rgb")
scene = mi.load_file("tests/data/aov/aov_scene.xml")
mi.render(scene)
scene.sensors()[0].film().write("tests/data/aov/aov_scene_ref.exr")

# moment_ref.exr: the same scene with Mitsuba's `moment` around the nested path
# integrator (the aov's `aovs` dropped), the independent sampler at 256 spp.
text = open("tests/data/aov/aov_scene.xml").read()
text = (
    text.replace('<integrator type="aov">', '<integrator type="moment">')
    .replace(
        '<string name="aovs" value="dd:depth,nn:sh_normal,gn:geo_normal,pp:position,aa:albedo,uv:uv,pi:prim_index"/>',
        "",
    )
    .replace('<sampler type="stratified">', '<sampler type="independent">')
    .replace('<boolean name="jitter" value="false"/>', "")
)
scene = mi.load_string(text, spp=256)
mi.render(scene)
scene.sensors()[0].film().write("tests/data/aov/moment_ref.exr")

# albedo_scene_ref.exr: the albedo AOV of five BSDFs, at pixel centres.
scene = mi.load_file("tests/data/aov/albedo_scene.xml")
mi.render(scene)
scene.sensors()[0].film().write("tests/data/aov/albedo_scene_ref.exr")

# partials_ref_<i>.exr: the dp_du, dp_dv, duv_dx and duv_dy AOVs of every shape kind
# through sensor i (0 pinhole, 1 orthographic, 2 thin lens) at pixel centres, and
# partials_ref_spp4.exr: the pinhole's at 4 spp (differentials scaled by 1/√spp).
# Mitsuba writes NaN in duv_dx and duv_dy where a ray meets nothing (0/0 on its zeroed
# interaction); wavetrace writes 0 there.
for i in range(3):
    scene = mi.load_file("tests/data/aov/partials_scene.xml")
    mi.render(scene, sensor=i)
    scene.sensors()[i].film().write(f"tests/data/aov/partials_ref_{i}.exr")
scene = mi.load_file("tests/data/aov/partials_scene.xml", spp=4)
mi.render(scene, sensor=0)
scene.sensors()[0].film().write("tests/data/aov/partials_ref_spp4.exr")
