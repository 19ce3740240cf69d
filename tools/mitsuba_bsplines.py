#!/usr/bin/env python3
"""Record what Mitsuba 3 computes where rays hit its `bsplinecurve` shape, for
tests/bspline_hits_vs_mitsuba.rs: wavetrace must find the same points, normals, uvs
and shading frames on the GPU, and miss where Mitsuba misses.

    python3 tools/mitsuba_bsplines.py [--out tests/data/bspline_hits.json] [--rays 200]

The curves are scenes/curves/bsplines.txt (a wave of nine points with varying radii,
a curve whose radius swells and shrinks, a strand along z, where Mitsuba's frame
turns to +y, and a thin hair), plain and under a to_world (which moves the control
points and keeps the radii). Rays start at random points around the curves and aim
at random points inside the tube (the centre c(u) of a random segment pushed out by
0.7 r(u)); hits at grazing angles (|cos| < 0.1) are left out, where a last-bit
difference decides between hit and miss. Misses: random rays through the curves' box
that Mitsuba misses, kept where parallel rays moved by 1e-3 miss too. Rays come from
a fixed seed: running it again gives the same file.
"""

import argparse
import json
import math
import os
import random

import mitsuba as mi

mi.set_variant("scalar_rgb")

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), ".."))
CURVES = os.path.join(ROOT, "scenes", "curves", "bsplines.txt")

TO_WORLD = (mi.ScalarTransform4f().translate([-0.4, 0.1, 0.2])
            @ mi.ScalarTransform4f().rotate([0.6917145, -0.6917145, 0.2075144], 61)
            @ mi.ScalarTransform4f().scale([1.3, 0.8, 1.1]))
CASES = [
    ("bsplinecurve", '<shape type="bsplinecurve"><string name="filename" value="bsplines.txt"/></shape>', None),
    ("bsplinecurve_to_world",
     '<shape type="bsplinecurve"><string name="filename" value="bsplines.txt"/>'
     '<transform name="to_world"><scale value="1.3, 0.8, 1.1"/>'
     '<rotate x="0.6917145" y="-0.6917145" z="0.2075144" angle="61"/>'
     '<translate value="-0.4, 0.1, 0.2"/></transform></shape>',
     TO_WORLD),
]


def curves():
    """The curves of the file: lists of ([x, y, z], radius)."""
    out, cur = [], []
    for line in open(CURVES):
        v = line.split()
        if len(v) >= 4:
            cur.append(([float(x) for x in v[:3]], float(v[3])))
        elif cur:
            out.append(cur)
            cur = []
    if cur:
        out.append(cur)
    return out


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def rand_dir(rng):
    return unit([rng.gauss(0, 1) for _ in range(3)])


def bspline(points, u):
    """Centre and radius of the uniform cubic B-spline of four (p, r) at u."""
    u2, u3 = u * u, u * u * u
    b = [(-u3 + 3 * u2 - 3 * u + 1) / 6, (3 * u3 - 6 * u2 + 4) / 6,
         (-3 * u3 + 3 * u2 + 3 * u + 1) / 6, u3 / 6]
    c = [sum(b[k] * points[k][0][i] for k in range(4)) for i in range(3)]
    return c, sum(b[k] * points[k][1] for k in range(4))


def record(si, o, d):
    return {
        "o": list(o), "d": list(d), "t": si.t, "p": list(si.p), "n": list(si.n),
        "sh_n": list(si.sh_frame.n), "sh_s": list(si.sh_frame.s), "uv": list(si.uv),
        "prim_index": int(si.prim_index),
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(ROOT, "tests", "data", "bspline_hits.json"))
    ap.add_argument("--rays", type=int, default=200)
    args = ap.parse_args()
    rng = random.Random(41)
    cs = curves()
    cases = []
    for name, xml, to_world in CASES:
        d = {"type": "bsplinecurve", "filename": CURVES}
        if to_world is not None:
            d["to_world"] = to_world
        scene = mi.load_dict({"type": "scene", "c": d})
        segments = []
        for c in cs:
            world = [(list(to_world @ mi.ScalarPoint3f(p)) if to_world is not None else p, r)
                     for p, r in c]
            segments += [world[j:j + 4] for j in range(len(world) - 3)]
        hits, misses = [], []
        while len(hits) < args.rays:
            c, r = bspline(rng.choice(segments), rng.random())
            target = [c[i] + 0.7 * r * x for i, x in enumerate(rand_dir(rng))]
            o = [target[i] + 3.0 * x for i, x in enumerate(rand_dir(rng))]
            dvec = unit([target[i] - o[i] for i in range(3)])
            o = [round(x, 6) for x in o]
            dvec = [round(x, 6) for x in dvec]
            si = scene.ray_intersect(mi.Ray3f(o, dvec))
            if not si.is_valid():
                continue
            cos = abs(sum(a * b for a, b in zip(si.n, dvec)))
            if cos < 0.1:
                continue
            hits.append(record(si, o, dvec))
        while len(misses) < args.rays:
            o = [rng.uniform(-3, 3) for _ in range(3)]
            target = [rng.uniform(-1.3, 1.3), rng.uniform(-0.9, 0.9), rng.uniform(-0.7, 0.7)]
            dvec = unit([target[i] - o[i] for i in range(3)])
            o = [round(x, 6) for x in o]
            dvec = [round(x, 6) for x in dvec]
            near = False
            for dx in [(0, 0, 0), (1e-3, 0, 0), (-1e-3, 0, 0), (0, 1e-3, 0), (0, -1e-3, 0), (0, 0, 1e-3), (0, 0, -1e-3)]:
                oo = [o[i] + dx[i] for i in range(3)]
                if scene.ray_intersect(mi.Ray3f(oo, dvec)).is_valid():
                    near = True
            if not near:
                misses.append({"o": o, "d": dvec})
        cases.append({"name": name, "shape": xml, "hits": hits, "misses": misses})
    with open(args.out, "w") as f:
        json.dump({"mitsuba": mi.__version__, "cases": cases}, f, indent=0)
    print("wrote", args.out, sum(len(c["hits"]) for c in cases), "hits")


if __name__ == "__main__":
    main()
