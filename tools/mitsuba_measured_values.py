#!/usr/bin/env python3
"""Mitsuba 3's own `measured` eval and pdf at fixed (wo, wi) pairs on the test files
tests/data/measured_{iso,aniso}.bsdf (tools/make_measured_bsdf.py), the reference of
tests/measured_vs_mitsuba.rs.

    python3 tools/mitsuba_measured_values.py > tests/data/measured_values.json

As tools/mitsuba_principled_values.py: Mitsuba 3.9.1 `scalar_rgb`, directions in
wavetrace's convention (`wo` towards the viewer = Mitsuba's `si.wi`, `wi` = the
argument of Mitsuba's `eval`/`pdf`), rounded to f32. Pairs: anywhere in the upper
hemisphere, near the mirror direction (where the lobe is), and a few below (zero).
"""
import math
import random

import mitsuba as mi

import mitsuba_pairs
from mitsuba_pairs import print_cases, unit, values

mi.set_variant("scalar_rgb")

FILES = ["tests/data/measured_iso.bsdf", "tests/data/measured_aniso.bsdf"]


def direction(rng):
    return mitsuba_pairs.direction(rng, mu_min=0.03, phi_range=(-math.pi, math.pi))


def pairs(rng):
    out = []
    for _ in range(100):
        out.append((direction(rng), direction(rng)))
    for _ in range(140):
        wo = direction(rng)
        wi = unit([-wo[0] + rng.gauss(0, 0.25), -wo[1] + rng.gauss(0, 0.25), wo[2]])
        if wi[2] > 0.01:
            out.append((wo, wi))
    for _ in range(6):
        wo = direction(rng)
        wi = direction(rng)
        out.append((wo, [wi[0], wi[1], -wi[2]]))
    out.append(([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]))
    return out


def main():
    rng = random.Random(39)
    cases = []
    for f in FILES:
        d = {"type": "measured", "filename": f}
        cases.append({"mitsuba": d, "values": values(mi.load_dict(d), pairs(rng))})
    print_cases(cases, indent=0)


if __name__ == "__main__":
    main()
