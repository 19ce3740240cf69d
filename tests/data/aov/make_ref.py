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
