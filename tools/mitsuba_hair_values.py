#!/usr/bin/env python3
"""Mitsuba 3's own `hair` eval and pdf at fixed (wo, wi) pairs, the reference of
tests/hair_vs_mitsuba.rs.

    python3 tools/mitsuba_hair_values.py > tests/data/hair_values.json

As tools/mitsuba_principled_values.py: Mitsuba 3.9.1 `scalar_rgb`, directions in
wavetrace's convention (`wo` towards the viewer = Mitsuba's `si.wi`, `wi` = the
argument of Mitsuba's `eval`/`pdf`), rounded to f32, over the whole sphere (the fiber
runs along local y; hair has no hemisphere test). Mitsuba's hair takes its offset h
from `si.wi` alone (sin γ_i), not from `si.uv`: the script checks that two uv give
the same values. Each case stores its Mitsuba dictionary; the test reads the same
dictionary as a scene.
"""
import math
import random

import mitsuba as mi

from mitsuba_pairs import RGB, eval_pdf, print_cases, unit

mi.set_variant("scalar_rgb")

CASES = [
    {"type": "hair"},
    {"type": "hair", "eumelanin": 0.2, "pheomelanin": 0.4},
    {"type": "hair", "sigma_a": RGB(0.2, 0.25, 0.7), "scale": 2.0},
    {"type": "hair", "sigma_a": RGB(0.0, 0.0, 0.0)},
    {"type": "hair", "eumelanin": 0.05, "pheomelanin": 0.0, "longitudinal_roughness": 0.1,
     "azimuthal_roughness": 0.15, "scale_tilt": 0.0},
    {"type": "hair", "eumelanin": 0.5, "longitudinal_roughness": 0.7,
     "azimuthal_roughness": 0.9, "scale_tilt": -5.0, "int_ior": 1.33},
    {"type": "hair", "sigma_a": 0.3, "longitudinal_roughness": 0.2,
     "azimuthal_roughness": 0.5, "scale_tilt": 6.0, "int_ior": "water", "ext_ior": 1.1},
]


def sphere(rng):
    z = rng.uniform(-1.0, 1.0)
    phi = rng.uniform(0.0, 2.0 * math.pi)
    s = math.sqrt(max(0.0, 1.0 - z * z))
    return unit([s * math.cos(phi), z, s * math.sin(phi)])


def pairs(rng, beta_m):
    out = []
    for _ in range(40):  # anywhere
        out.append((sphere(rng), sphere(rng)))
    spread = max(beta_m, 0.05)
    for _ in range(40):  # near the specular cone: sin θi ≈ -sin θo, any azimuth
        wo = sphere(rng)
        wi = sphere(rng)
        y = -wo[1] + rng.gauss(0.0, spread)
        y = max(-0.999, min(0.999, y))
        r = math.sqrt(wi[0] ** 2 + wi[2] ** 2) or 1.0
        c = math.sqrt(1.0 - y * y)
        out.append((wo, unit([wi[0] / r * c, y, wi[2] / r * c])))
    out.append(([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]))
    out.append(([0.0, 0.0, 1.0], [0.0, 0.0, -1.0]))
    out.append(([0.6, 0.0, 0.8], [-0.6, 0.0, -0.8]))
    return out


def main():
    rng = random.Random(39)
    ctx = mi.BSDFContext()
    cases = []
    for d in CASES:
        bsdf = mi.load_dict(d)
        values = []
        for wo, wi in pairs(rng, d.get("longitudinal_roughness", 0.3)):
            res = [eval_pdf(bsdf, ctx, wo, wi, uv) for uv in ((0.5, 0.5), (0.1, 0.9))]
            assert res[0] == res[1], (d, wo, wi, res)
            values.append({"wo": wo, "wi": wi, "eval": res[0][0], "pdf": res[0][1]})
        cases.append({"mitsuba": d, "values": values})
    print_cases(cases)


if __name__ == "__main__":
    main()
