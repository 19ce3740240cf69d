#!/usr/bin/env python3
"""Mitsuba 3.9.1's radiance for tests/normalmap_flags.rs: a plane under two directional
lights with a constant, strongly tilted normal map (tests/data/normalmap_flags/tilted.exr,
which this script writes), seen by a radiancemeter from two sides, for each setting of
`flip_invalid_normals` and `use_shadowing_function`. Deterministic (directional lights,
a constant map): prints one value per (view, flip, shadow)."""
import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")
OUT = "tests/data/normalmap_flags/tilted.exr"
n = np.array([0.95, 0.0, 0.31])
n /= np.linalg.norm(n)
mi.Bitmap(np.tile(((n + 1) / 2).astype(np.float32), (2, 2, 1))).write(OUT)


def render(flip, shadow, view):
    scene = {
        "type": "scene",
        "integrator": {"type": "direct"},
        "sensor": {
            "type": "radiancemeter",
            "origin": view,
            "direction": [-v for v in view],
            "film": {"type": "hdrfilm", "width": 1, "height": 1, "rfilter": {"type": "box"}},
            "sampler": {"type": "independent", "sample_count": 16},
        },
        "plane": {
            "type": "rectangle",
            "to_world": mi.ScalarTransform4f().scale(10),
            "bsdf": {
                "type": "normalmap",
                "flip_invalid_normals": flip,
                "use_shadowing_function": shadow,
                "normalmap": {"type": "bitmap", "filename": OUT, "raw": True, "filter_type": "nearest"},
                "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": 0.5}},
            },
        },
        "light_a": {"type": "directional", "direction": [0.5, 0.0, -0.8]},
        "light_b": {"type": "directional", "direction": [-0.5, 0.0, -0.8]},
    }
    return float(np.array(mi.render(mi.load_dict(scene))).reshape(-1)[0])


for view in ([-0.8, 0.3, 0.52], [0.6, 0.3, 0.74]):
    for flip in (False, True):
        for shadow in (False, True):
            print(f"view {view} flip {flip} shadow {shadow}: {render(flip, shadow, view):.7f}")
