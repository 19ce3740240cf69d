"""Rays against a Mitsuba 3 scene and what Mitsuba computes where they hit: what the
tools/mitsuba_curves.py, mitsuba_bsplines.py and mitsuba_ellipsoids.py scripts share
(each builds its own shapes and aims its own rays with these helpers, and writes the
JSON that tests/common's `hits_both_found` compares with wavetrace's hits).

Rays are rounded to 6 decimals before Mitsuba sees them (the JSON holds exactly what
was traced). Hits at grazing angles (|cos| < 0.1) are left out, where a last-bit
difference decides between hit and miss; misses are kept only where parallel rays
moved by 1e-3 along each axis miss too. The scripts set the variant (`scalar_rgb`)
before calling these.
"""
import argparse
import json
import math
import os

import mitsuba as mi

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), ".."))

# The to_world the scripts' transformed cases share, as XML (what the test scenes
# hold) and as the transform Mitsuba's dictionaries take.
TO_WORLD_XML = ('<transform name="to_world"><scale value="1.3, 0.8, 1.1"/>'
                '<rotate x="0.6917145" y="-0.6917145" z="0.2075144" angle="61"/>'
                '<translate value="-0.4, 0.1, 0.2"/></transform>')


def to_world():
    """TO_WORLD_XML as a Mitsuba transform (after the variant is set)."""
    return (mi.ScalarTransform4f().translate([-0.4, 0.1, 0.2])
            @ mi.ScalarTransform4f().rotate([0.6917145, -0.6917145, 0.2075144], 61)
            @ mi.ScalarTransform4f().scale([1.3, 0.8, 1.1]))


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def rand_dir(rng):
    """A uniformly random unit vector."""
    return unit([rng.gauss(0, 1) for _ in range(3)])


def rounded(o, d):
    """The ray as traced: origin and direction rounded to 6 decimals."""
    return [round(x, 6) for x in o], [round(x, 6) for x in d]


def grazing(si, d):
    return abs(sum(a * b for a, b in zip(si.n, d))) < 0.1


def record(si, o, d, frame_s=True):
    """A hit as the JSON holds it (with the shading frame's s unless `frame_s` is off)."""
    r = {"o": list(o), "d": list(d), "t": si.t, "p": list(si.p), "n": list(si.n),
         "sh_n": list(si.sh_frame.n)}
    if frame_s:
        r["sh_s"] = list(si.sh_frame.s)
    r["uv"] = list(si.uv)
    r["prim_index"] = int(si.prim_index)
    return r


def clear_miss(scene, o, d):
    """Whether the ray and the six parallel to it, moved by 1e-3, all miss."""
    for dx in [(0, 0, 0), (1e-3, 0, 0), (-1e-3, 0, 0), (0, 1e-3, 0), (0, -1e-3, 0),
               (0, 0, 1e-3), (0, 0, -1e-3)]:
        oo = [o[i] + dx[i] for i in range(3)]
        if scene.ray_intersect(mi.Ray3f(oo, d)).is_valid():
            return False
    return True


def aimed_hits(scene, rng, count, pick):
    """`count` hits of rays from 3 units away aimed at points inside the tube or
    ball around `pick(rng)`'s centre c with radius r (c pushed out by 0.7 r)."""
    hits = []
    while len(hits) < count:
        c, r = pick(rng)
        target = [c[i] + 0.7 * r * x for i, x in enumerate(rand_dir(rng))]
        o = [target[i] + 3.0 * x for i, x in enumerate(rand_dir(rng))]
        o, d = rounded(o, unit([target[i] - o[i] for i in range(3)]))
        si = scene.ray_intersect(mi.Ray3f(o, d))
        if si.is_valid() and not grazing(si, d):
            hits.append(record(si, o, d))
    return hits


def box_misses(scene, rng, count, half):
    """`count` clear misses of rays from the cube [-3, 3]^3 aimed at random points
    of the box [-half, half]."""
    misses = []
    while len(misses) < count:
        o = [rng.uniform(-3, 3) for _ in range(3)]
        target = [rng.uniform(-h, h) for h in half]
        o, d = rounded(o, unit([target[i] - o[i] for i in range(3)]))
        if clear_miss(scene, o, d):
            misses.append({"o": o, "d": d})
    return misses


def arguments(default_out):
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(ROOT, "tests", "data", default_out))
    ap.add_argument("--rays", type=int, default=200)
    return ap.parse_args()


def write(path, cases):
    with open(path, "w") as f:
        json.dump({"mitsuba": mi.__version__, "cases": cases}, f, indent=0)
    print("wrote", path, sum(len(c["hits"]) for c in cases), "hits")
