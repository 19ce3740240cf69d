#!/usr/bin/env python3
"""Mitsuba 3's own BSDF eval and pdf at fixed (wo, wi) pairs, the reference of
tests/pplastic_vs_mitsuba.rs.

    python3 tools/mitsuba_bsdf_values.py > tests/data/pplastic_values.json
    python3 tools/mitsuba_bsdf_values.py roughplastic > tests/data/roughplastic_values.json

(the second: tests/roughplastic_vs_mitsuba.rs, the cases ROUGHPLASTIC_CASES).

Runs Mitsuba 3.9.1 (pip `mitsuba`) in `scalar_rgb` (single precision, as the GPU).
Directions follow wavetrace's convention: `wo` towards the viewer (Mitsuba's
`si.wi`), `wi` towards the light (the `wo` argument of Mitsuba's `eval`/`pdf`), both
in the local frame, rounded to f32 before Mitsuba sees them. Each case stores its
Mitsuba dictionary and the parameters Mitsuba resolved (`eta` read back with
`mi.traverse`), which the test packs into wavetrace's record directly.

Beckmann cases set `sample_visible` false: wavetrace samples Beckmann's full normal
distribution (shaders/bsdf/microfacet.glsl), whose pdf is Mitsuba's with that flag;
eval does not depend on it.
"""
import random
import sys

import mitsuba as mi

from mitsuba_pairs import direction, print_cases, unit, values

mi.set_variant("scalar_rgb")

CASES = [
    ("defaults", {"type": "pplastic", "sample_visible": False}),
    ("ggx α 0.3, purple, 1.5 / 1.0", {
        "type": "pplastic", "distribution": "ggx", "alpha": 0.3,
        "diffuse_reflectance": {"type": "rgb", "value": [0.05, 0.03, 0.1]},
        "int_ior": 1.5, "ext_ior": 1.0}),
    ("ggx anisotropic, bk7, tinted specular", {
        "type": "pplastic", "distribution": "ggx", "alpha_u": 0.1, "alpha_v": 0.4,
        "diffuse_reflectance": {"type": "rgb", "value": [0.6, 0.3, 0.2]},
        "specular_reflectance": {"type": "rgb", "value": [0.8, 0.9, 1.0]},
        "int_ior": "bk7"}),
    ("beckmann α 0.5, eta 1.33", {
        "type": "pplastic", "distribution": "beckmann", "alpha": 0.5, "eta": 1.33,
        "sample_visible": False,
        "diffuse_reflectance": {"type": "rgb", "value": [0.9, 0.9, 0.9]}}),
    ("beckmann anisotropic 0.05 / 0.2", {
        "type": "pplastic", "distribution": "beckmann", "alpha_u": 0.05, "alpha_v": 0.2,
        "sample_visible": False, "int_ior": 1.9}),
    ("ggx α 0.03", {
        "type": "pplastic", "distribution": "ggx", "alpha": 0.03,
        "diffuse_reflectance": {"type": "rgb", "value": [0.2, 0.5, 0.1]}}),
]

# roughplastic: the regression suite's (GGX, bk7, diffuse (0.02, 0.2, 0.1), nonlinear
# both ways, alpha 0.1 / 0.4 / 1.0) and some Beckmann.
ROUGHPLASTIC_CASES = [
    ("defaults", {"type": "roughplastic", "sample_visible": False}),
] + [
    (f"ggx α {a}, bk7, green, nonlinear {nl}", {
        "type": "roughplastic", "distribution": "ggx", "alpha": a, "int_ior": "bk7",
        "diffuse_reflectance": {"type": "rgb", "value": [0.02, 0.2, 0.1]},
        "nonlinear": nl})
    for a in [0.1, 0.4, 1.0] for nl in [False, True]
] + [
    ("beckmann α 0.5, eta 1.33, grey, tinted specular", {
        "type": "roughplastic", "distribution": "beckmann", "alpha": 0.5,
        "int_ior": 1.33, "sample_visible": False,
        "diffuse_reflectance": {"type": "rgb", "value": [0.9, 0.9, 0.9]},
        "specular_reflectance": {"type": "rgb", "value": [0.8, 0.9, 1.0]}}),
    ("beckmann α 1.0, eta 1.9, nonlinear", {
        "type": "roughplastic", "distribution": "beckmann", "alpha": 1.0,
        "int_ior": 1.9, "sample_visible": False, "nonlinear": True,
        "diffuse_reflectance": {"type": "rgb", "value": [0.6, 0.3, 0.2]}}),
]


def pairs(rng, alpha):
    out = []
    for _ in range(24):  # anywhere over the hemisphere
        out.append((direction(rng), direction(rng)))
    for _ in range(24):  # near the mirror direction, within the lobe
        wo = direction(rng)
        r = [-wo[0], -wo[1], wo[2]]
        spread = 1.5 * alpha
        wi = unit([r[0] + rng.gauss(0, spread), r[1] + rng.gauss(0, spread), r[2]])
        if wi[2] > 0:
            out.append((wo, wi))
    out.append((direction(rng), direction(rng, lower=True)))  # below: zero
    out.append(([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]))  # normal incidence
    return out


def main():
    rng = random.Random(39)
    cases = []
    rough = sys.argv[1:] == ["roughplastic"]
    for name, d in ROUGHPLASTIC_CASES if rough else CASES:
        bsdf = mi.load_dict(d)
        params = mi.traverse(bsdf)
        if "alpha.value" in params:
            au = av = float(params["alpha.value"])
        elif "alpha" in params:  # roughplastic: a plain float
            au = av = float(params["alpha"])
        else:
            au, av = float(params["alpha_u.value"]), float(params["alpha_v.value"])

        def rgb(key, default):
            k = key + ".value"
            if k not in params:
                return default
            v = params[k]
            return [float(c) for c in v] if hasattr(v, "__len__") else [float(v)] * 3

        case = {
            "name": name,
            "mitsuba": d,
            "distribution": d.get("distribution", "beckmann"),
            "alpha_u": au,
            "alpha_v": av,
            "diffuse_reflectance": rgb("diffuse_reflectance", [0.5, 0.5, 0.5]),
            "specular_reflectance": rgb("specular_reflectance", [1.0, 1.0, 1.0]),
            "eta": float(params["eta.value"] if "eta.value" in params else params["eta"]),
        }
        if rough:  # (pplastic_values.json has no such key)
            case["nonlinear"] = bool(d.get("nonlinear", False))
        case["values"] = values(bsdf, pairs(rng, max(au, av)))
        cases.append(case)
    print_cases(cases)


if __name__ == "__main__":
    main()
