#!/usr/bin/env python3
"""Mitsuba 3's eval and pdf of conductors whose `eta` and `k` are bitmap textures, the
reference of tests/textured_conductor_vs_mitsuba.rs, and the two textures themselves.

    python3 tools/mitsuba_textured_conductor.py   # writes tests/data/textured_conductor/

Writes tests/data/textured_conductor/eta.exr and k.exr (8 x 8 linear RGB, smooth ramps
with a hash, eta in 0.15 .. 1.75 and k in 1.2 .. 4.6: metal-like indices), then
evaluates `roughconductor` (GGX and anisotropic Beckmann) with those textures at random
uv and (wo, wi) pairs in Mitsuba 3.9.1 `scalar_rgb` (single precision). Directions as
tools/mitsuba_bsdf_values.py: `wo` towards the viewer (Mitsuba's `si.wi`), `wi`
towards the light, in the local frame, rounded to f32. Mitsuba's own texture values at
each uv (`eval` of the `eta` and `k` textures) are stored beside, so a failing test
says whether the lookup or the BSDF differs. (Mitsuba warns that the textures exceed
[0, 1]: that matters only to spectral variants, which upsample RGB as reflectances.)
"""
import json
import os
import random

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")

from mitsuba_pairs import textured_query  # noqa: E402

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data",
                    "textured_conductor")


def write_textures():
    n = 8
    eta = np.zeros((n, n, 3), dtype=np.float32)
    k = np.zeros((n, n, 3), dtype=np.float32)
    for y in range(n):
        for x in range(n):
            h = ((x * 73856093) ^ (y * 19349663)) % 1000 / 1000.0
            for c in range(3):
                eta[y, x, c] = 0.15 + 1.6 * ((x / (n - 1)) * (0.3 + 0.35 * c) + 0.3 * h) / 1.4
                k[y, x, c] = 1.2 + 3.4 * ((y / (n - 1)) * (0.9 - 0.3 * c) + 0.1 * h)
    mi.Bitmap(eta).write(os.path.join(HERE, "eta.exr"))
    mi.Bitmap(k).write(os.path.join(HERE, "k.exr"))


def textured(d):
    d = dict(d)
    d["eta"] = {"type": "bitmap", "filename": os.path.join(HERE, "eta.exr")}
    d["k"] = {"type": "bitmap", "filename": os.path.join(HERE, "k.exr")}
    return d


CASES = [
    ("roughconductor ggx α 0.3", {"type": "roughconductor", "distribution": "ggx",
                                   "alpha": 0.3}),
    ("roughconductor beckmann 0.1 / 0.4, tinted", {
        "type": "roughconductor", "distribution": "beckmann", "alpha_u": 0.1,
        "alpha_v": 0.4, "sample_visible": False,
        "specular_reflectance": {"type": "rgb", "value": [0.9, 0.8, 0.7]}}),
]


def main():
    write_textures()
    rng = random.Random(3939)
    ctx = mi.BSDFContext()
    cases = []
    for name, d in CASES:
        bsdf = mi.load_dict(textured(d))
        eta_tex = mi.load_dict(textured(d)["eta"])
        k_tex = mi.load_dict(textured(d)["k"])
        values = []
        for _ in range(48):
            uv, wo, wi, si, e, p = textured_query(rng, bsdf, ctx, mu_min=0.05)
            te, tk = eta_tex.eval(si), k_tex.eval(si)
            values.append({"uv": uv, "wo": wo, "wi": wi, "eval": e, "pdf": p,
                           "eta": [float(te[i]) for i in range(3)],
                           "k": [float(tk[i]) for i in range(3)]})
        cases.append({"name": name, "mitsuba": d, "values": values})
    with open(os.path.join(HERE, "values.json"), "w") as f:
        json.dump({"mitsuba": mi.__version__, "variant": mi.variant(), "cases": cases}, f,
                  indent=1)


if __name__ == "__main__":
    main()
