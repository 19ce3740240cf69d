#!/usr/bin/env python3
"""Mitsuba 3's own `principled` and `principledthin` eval and pdf at fixed (wo, wi)
pairs, the reference of tests/principled_vs_mitsuba.rs.

    python3 tools/mitsuba_principled_values.py > tests/data/principled_values.json

As tools/mitsuba_bsdf_values.py: Mitsuba 3.9.1 `scalar_rgb`, directions in
wavetrace's convention (`wo` towards the viewer = Mitsuba's `si.wi`, `wi` = the
argument of Mitsuba's `eval`/`pdf`), rounded to f32; both sides of the surface (the
models handle wo below: inside for principled, mirrored for principledthin). Each
case stores its Mitsuba dictionary; the test reads the same dictionary as a scene.
"""
import random

import mitsuba as mi

from mitsuba_pairs import RGB, direction, print_cases, unit, values

mi.set_variant("scalar_rgb")

CASES = [
    {"type": "principled"},
    {"type": "principled", "base_color": RGB(0.2, 0.8, 0.1), "roughness": 0.15,
     "anisotropic": 0.8, "metallic": 0.1, "clearcoat": 0.9, "sheen": 0.9, "specular": 0.7},
    {"type": "principled", "base_color": RGB(0.3, 0.6, 0.8), "roughness": 0.3,
     "anisotropic": 0.2, "spec_trans": 0.7, "clearcoat": 0.6, "sheen": 0.2, "specular": 0.4},
    {"type": "principled", "base_color": RGB(0.9, 0.5, 0.2), "roughness": 0.6,
     "metallic": 0.7, "spec_tint": 0.4, "sheen": 0.3, "sheen_tint": 0.2,
     "clearcoat": 0.6, "clearcoat_gloss": 0.3, "spec_trans": 0.4, "flatness": 0.5,
     "eta": 1.33},
    {"type": "principled", "base_color": RGB(0.7, 0.7, 0.9), "roughness": 0.05,
     "spec_trans": 1.0, "eta": 1.5, "main_specular_sampling_rate": 2.0,
     "clearcoat_sampling_rate": 0.5, "diffuse_reflectance_sampling_rate": 3.0},
    {"type": "principledthin"},
    {"type": "principledthin", "base_color": RGB(0.7, 0.1, 0.1), "anisotropic": 0.8,
     "spec_trans": 0.8, "diff_trans": 1.4, "sheen": 0.8, "eta": 1.33},
    {"type": "principledthin", "base_color": RGB(0.2, 0.5, 0.9), "roughness": 0.25,
     "spec_trans": 0.5, "spec_tint": 0.6, "sheen": 0.4, "sheen_tint": 0.7,
     "flatness": 0.6, "diff_trans": 0.4, "eta": 1.6,
     "specular_reflectance_sampling_rate": 2.0, "diffuse_transmittance_sampling_rate": 0.5},
]


def pairs(rng, roughness):
    out = []
    for below in (False, True):
        flip = (lambda v: [v[0], v[1], -v[2]]) if below else (lambda v: v)
        for _ in range(20):  # reflection, anywhere
            out.append((flip(direction(rng)), flip(direction(rng))))
        for _ in range(16):  # transmission, anywhere
            out.append((flip(direction(rng)), flip(direction(rng, lower=True))))
        spread = 1.5 * max(roughness * roughness, 0.02)
        for _ in range(16):  # near the mirror direction
            wo = direction(rng)
            wi = unit([-wo[0] + rng.gauss(0, spread), -wo[1] + rng.gauss(0, spread), wo[2]])
            if wi[2] > 0:
                out.append((flip(wo), flip(wi)))
        for _ in range(12):  # near the refracted / straight-through direction
            wo = direction(rng)
            wi = unit([-wo[0] * 0.7 + rng.gauss(0, spread), -wo[1] * 0.7 + rng.gauss(0, spread), -wo[2]])
            if wi[2] < 0:
                out.append((flip(wo), flip(wi)))
    out.append(([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]))
    return out


def main():
    rng = random.Random(39)
    cases = []
    for d in CASES:
        bsdf = mi.load_dict(d)
        cases.append({"mitsuba": d, "values": values(bsdf, pairs(rng, d.get("roughness", 0.5)))})
    print_cases(cases)


if __name__ == "__main__":
    main()
