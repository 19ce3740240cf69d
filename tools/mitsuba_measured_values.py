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
import json
import math
import random
import struct

import mitsuba as mi

mi.set_variant("scalar_rgb")

FILES = ["tests/data/measured_iso.bsdf", "tests/data/measured_aniso.bsdf"]


def f32(x):
    return struct.unpack("f", struct.pack("f", x))[0]


def unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return [f32(c / n) for c in v]


def direction(rng):
    mu = rng.uniform(0.03, 1.0)
    phi = rng.uniform(-math.pi, math.pi)
    s = math.sqrt(1.0 - mu * mu)
    return unit([s * math.cos(phi), s * math.sin(phi), mu])


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
    ctx = mi.BSDFContext()
    cases = []
    for f in FILES:
        d = {"type": "measured", "filename": f}
        bsdf = mi.load_dict(d)
        values = []
        for wo, wi in pairs(rng):
            si = mi.SurfaceInteraction3f()
            si.wi = mi.Vector3f(wo)
            e = bsdf.eval(ctx, si, mi.Vector3f(wi))
            p = bsdf.pdf(ctx, si, mi.Vector3f(wi))
            values.append({"wo": wo, "wi": wi, "eval": [float(e[0]), float(e[1]), float(e[2])],
                           "pdf": float(p)})
        cases.append({"mitsuba": d, "values": values})
    print(json.dumps({"mitsuba": mi.__version__, "variant": mi.variant(), "cases": cases},
                     indent=0))


if __name__ == "__main__":
    main()
