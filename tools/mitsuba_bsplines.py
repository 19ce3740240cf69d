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

import os
import random

import mitsuba as mi

mi.set_variant("scalar_rgb")

from mitsuba_hits import (ROOT, TO_WORLD_XML, aimed_hits, arguments, box_misses,  # noqa: E402
                          to_world, write)

CURVES = os.path.join(ROOT, "scenes", "curves", "bsplines.txt")

TO_WORLD = to_world()
CASES = [
    ("bsplinecurve", '<shape type="bsplinecurve"><string name="filename" value="bsplines.txt"/></shape>', None),
    ("bsplinecurve_to_world",
     f'<shape type="bsplinecurve"><string name="filename" value="bsplines.txt"/>{TO_WORLD_XML}</shape>',
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


def bspline(points, u):
    """Centre and radius of the uniform cubic B-spline of four (p, r) at u."""
    u2, u3 = u * u, u * u * u
    b = [(-u3 + 3 * u2 - 3 * u + 1) / 6, (3 * u3 - 6 * u2 + 4) / 6,
         (-3 * u3 + 3 * u2 + 3 * u + 1) / 6, u3 / 6]
    c = [sum(b[k] * points[k][0][i] for k in range(4)) for i in range(3)]
    return c, sum(b[k] * points[k][1] for k in range(4))


def main():
    args = arguments("bspline_hits.json")
    rng = random.Random(41)
    cs = curves()
    cases = []
    for name, xml, tw in CASES:
        d = {"type": "bsplinecurve", "filename": CURVES}
        if tw is not None:
            d["to_world"] = tw
        scene = mi.load_dict({"type": "scene", "c": d})
        segments = []
        for c in cs:
            world = [(list(tw @ mi.ScalarPoint3f(p)) if tw is not None else p, r) for p, r in c]
            segments += [world[j:j + 4] for j in range(len(world) - 3)]
        hits = aimed_hits(scene, rng, args.rays,
                          lambda rng: bspline(rng.choice(segments), rng.random()))
        misses = box_misses(scene, rng, args.rays, (1.3, 0.9, 0.7))
        cases.append({"name": name, "shape": xml, "hits": hits, "misses": misses})
    write(args.out, cases)


if __name__ == "__main__":
    main()
