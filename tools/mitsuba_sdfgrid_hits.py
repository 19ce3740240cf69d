#!/usr/bin/env python3
"""Record where Mitsuba 3's `sdfgrid` is hit, for tests/sdfgrid_vs_mitsuba.rs: wavetrace
must find the same distances, points and normals on the GPU, and miss where Mitsuba
misses.

    python3 tools/mitsuba_sdfgrid_hits.py [--out tests/data/sdfgrid_hits.json] [--rays 400]

The grid is the torus of Mitsuba's regression suite (mitsuba-data
docs/scenes/sdfgrid/torus_sdfgrid.vol, read from ../shared/scenes/mitsuba/regression),
with smooth and analytic normals, unplaced, scaled non-uniformly and moved, and rotated
(recorded through an instance: see `instanced`). Rays start on a sphere around the placed unit
cube and aim at random points inside it; for every hit the JSON keeps the ray, t, p,
n (geometric normal) and sh_frame.n; of the misses the first 100 (rounded to 7 digits
as written, and still missing so). Fixed seed: the same file for the same Mitsuba.
"""

import argparse
import json
import os
import random

import mitsuba as mi

mi.set_variant("scalar_rgb")

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), ".."))
GRID_DIR = os.path.join(ROOT, "..", "shared", "scenes", "mitsuba", "regression", "docs",
                        "scenes", "sdfgrid")


def tf(body):
    return '<transform name="to_world">%s</transform>' % body


def sdf(normals, transform=""):
    return ('<shape type="sdfgrid"><string name="filename" value="torus_sdfgrid.vol"/>'
            '<string name="normals" value="%s"/>%s</shape>' % (normals, transform))


ROTATE = tf('<translate value="-0.5, -0.5, -0.5"/><scale value="3"/>'
            '<rotate x="0.6" y="0.8" z="0" angle="50"/>')

CASES = [
    ("smooth", sdf("smooth")),
    ("analytic", sdf("analytic")),
    ("scaled_smooth", sdf("smooth", tf('<scale value="2, 1.5, 0.8"/><translate value="-1, 0.3, 2"/>'))),
    ("scaled_analytic", sdf("analytic", tf('<scale value="2, 1.5, 0.8"/><translate value="-1, 0.3, 2"/>'))),
    ("rotated_smooth", sdf("smooth", ROTATE)),
    ("rotated_analytic", sdf("analytic", ROTATE)),
]


def instanced(shape):
    """The same shape with its to_world moved to an instance of a group holding it:
    Mitsuba's sdfgrid bounds its voxels by the images of their lower and upper
    corners alone, which a rotation makes too small (the reason it warns against
    rotations and points to instancing), so its own hits of a rotated grid are
    recorded through an instance, which traces the grid unrotated."""
    start = shape.index('<transform name="to_world">')
    end = shape.index("</transform>") + len("</transform>")
    return ('<shape type="shapegroup" id="g">%s</shape>'
            '<shape type="instance"><ref id="g"/>%s</shape>'
            % (shape[:start] + shape[end:], shape[start:end]))


def r7(v):
    return [round(float(x), 7) for x in v]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(ROOT, "tests", "data", "sdfgrid_hits.json"))
    ap.add_argument("--rays", type=int, default=400)
    args = ap.parse_args()
    rng = random.Random(40)
    cases = []
    for name, shape in CASES:
        rotated = name.startswith("rotated")
        xml = ('<scene version="3.0.0"><path value="%s"/>%s</scene>'
               % (GRID_DIR, instanced(shape) if rotated else shape))
        scene = mi.load_string(xml)
        box = scene.bbox()
        lo, hi = mi.ScalarPoint3f(box.min), mi.ScalarPoint3f(box.max)
        c = (lo + hi) * 0.5
        radius = sum((hi[k] - lo[k]) ** 2 for k in range(3)) ** 0.5
        hits, misses = [], []
        for _ in range(args.rays):
            while True:
                u = [rng.gauss(0, 1) for _ in range(3)]
                n = sum(x * x for x in u) ** 0.5
                if n > 1e-3:
                    break
            o = [c[k] + radius * u[k] / n for k in range(3)]
            target = [lo[k] + rng.random() * (hi[k] - lo[k]) for k in range(3)]
            d = [target[k] - o[k] for k in range(3)]
            dn = sum(x * x for x in d) ** 0.5
            d = r7([x / dn for x in d])
            o = r7(o)
            si = scene.ray_intersect(mi.Ray3f(mi.ScalarPoint3f(o), mi.ScalarVector3f(d)))
            if si.is_valid():
                hits.append({"o": o, "d": d, "t": float(si.t), "p": r7(si.p),
                             "n": r7(si.n), "sh_n": r7(si.sh_frame.n)})
            elif len(misses) < 100:
                misses.append({"o": o, "d": d})
        cases.append({"name": name, "shape": shape, "hits": hits, "misses": misses})
        print(name, len(hits), "hits", len(misses), "misses")
    with open(args.out, "w") as f:
        json.dump({"mitsuba": mi.__version__, "grid": "torus_sdfgrid.vol", "cases": cases}, f,
                  indent=0)
        f.write("\n")


if __name__ == "__main__":
    main()
