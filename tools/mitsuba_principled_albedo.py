#!/usr/bin/env python3
"""Mitsuba 3's directional albedo of `principled` and `principledthin`: the mean of
its own `sample` weights (f |cos| / pdf, radiance mode) over N samples at several
wo, per RGB channel with its standard error; the reference of tests/furnace.rs's
`principled_albedo_matches_mitsuba`.

    python3 tools/mitsuba_principled_albedo.py > tests/data/principled_albedo.json

Mitsuba 3.9.1 `scalar_rgb`; wo in wavetrace's convention (towards the viewer, Mitsuba's
`si.wi`), below the surface too (inside for principled, the other face for
principledthin).
"""
import json
import math
import random

import mitsuba as mi

mi.set_variant("scalar_rgb")

RGB = lambda *v: {"type": "rgb", "value": list(v)}
N = 200_000

CASES = [
    {"type": "principled", "base_color": RGB(0.2, 0.8, 0.1), "roughness": 0.15,
     "anisotropic": 0.8, "metallic": 0.1, "clearcoat": 0.9, "sheen": 0.9, "specular": 0.7},
    {"type": "principled", "base_color": RGB(0.3, 0.6, 0.8), "roughness": 0.3,
     "anisotropic": 0.2, "spec_trans": 0.7, "clearcoat": 0.6, "sheen": 0.2, "specular": 0.4},
    {"type": "principled", "base_color": RGB(0.9, 0.5, 0.2), "roughness": 0.6,
     "metallic": 0.7, "spec_tint": 0.4, "sheen": 0.3, "sheen_tint": 0.2,
     "clearcoat": 0.6, "clearcoat_gloss": 0.3, "spec_trans": 0.4, "flatness": 0.5,
     "eta": 1.33},
    {"type": "principled", "base_color": RGB(1.0, 1.0, 1.0), "roughness": 0.4, "metallic": 1.0},
    {"type": "principledthin", "base_color": RGB(0.7, 0.1, 0.1), "anisotropic": 0.8,
     "spec_trans": 0.8, "diff_trans": 1.4, "sheen": 0.8, "eta": 1.33},
    {"type": "principledthin", "base_color": RGB(0.2, 0.5, 0.9), "roughness": 0.25,
     "spec_trans": 0.5, "spec_tint": 0.6, "sheen": 0.4, "sheen_tint": 0.7,
     "flatness": 0.6, "diff_trans": 0.4, "eta": 1.6},
]

COS = [0.1, 0.5, 0.9, -0.3, -0.8]


def main():
    rng = random.Random(39)
    ctx = mi.BSDFContext()
    cases = []
    for d in CASES:
        bsdf = mi.load_dict(d)
        out = []
        for i, c in enumerate(COS):
            s = math.sqrt(1.0 - c * c)
            wo = [s * math.cos(0.7 * i), s * math.sin(0.7 * i), c]
            si = mi.SurfaceInteraction3f()
            si.wi = mi.Vector3f(wo)
            si.uv = mi.Point2f(0.5, 0.5)
            acc = [0.0] * 3
            acc2 = [0.0] * 3
            for _ in range(N):
                _, w = bsdf.sample(ctx, si, rng.random(), mi.Point2f(rng.random(), rng.random()))
                for k in range(3):
                    x = float(w[k])
                    acc[k] += x
                    acc2[k] += x * x
            mean = [a / N for a in acc]
            se = [math.sqrt(max(a2 / N - m * m, 0.0) / (N - 1)) for a2, m in zip(acc2, mean)]
            out.append({"wo": wo, "albedo": mean, "se": se})
        cases.append({"mitsuba": d, "albedos": out})
    print(json.dumps({"mitsuba": mi.__version__, "variant": mi.variant(), "samples": N,
                      "cases": cases}, indent=1))


if __name__ == "__main__":
    main()
