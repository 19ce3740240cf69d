#!/usr/bin/env python3
"""Record what Mitsuba 3 computes where rays hit its curve shapes, for
tests/curve_hits_vs_mitsuba.rs: wavetrace must find the same points, normals, uvs and
shading frames on the GPU, and miss where Mitsuba misses.

    python3 tools/mitsuba_curves.py [--out tests/data/curve_hits.json] [--rays 200]

The curves are scenes/curves/curves.txt (varying radii, a sharp bend, a strand along
z, a thin hair, a cone whose end sphere nearly holds the other), plain and under a
to_world (which moves the control points and keeps the radii). Rays start at random
points around the curves and aim at random points on them (a control point's sphere
pushed out to its surface); hits at grazing angles (|cos| < 0.1) are left out, where
a last-bit difference decides between hit and miss. Misses: random rays through the
curves' box that Mitsuba misses, kept where parallel rays moved by 1e-3 miss too.
Rays come from a fixed seed: running it again gives the same file.
"""

import os
import random

import mitsuba as mi

mi.set_variant("scalar_rgb")

from mitsuba_hits import (ROOT, TO_WORLD_XML, aimed_hits, arguments, box_misses,  # noqa: E402
                          to_world, write)

CURVES = os.path.join(ROOT, "scenes", "curves", "curves.txt")

CASES = [
    ("linearcurve", '<shape type="linearcurve"><string name="filename" value="curves.txt"/></shape>', None),
    ("linearcurve_to_world",
     f'<shape type="linearcurve"><string name="filename" value="curves.txt"/>{TO_WORLD_XML}</shape>',
     to_world()),
]


def control_points():
    pts = []
    for line in open(CURVES):
        v = line.split()
        if len(v) >= 4:
            pts.append(([float(x) for x in v[:3]], float(v[3])))
    return pts


def main():
    args = arguments("curve_hits.json")
    rng = random.Random(40)
    pts = control_points()
    cases = []
    for name, xml, tw in CASES:
        d = {"type": "linearcurve", "filename": CURVES}
        if tw is not None:
            d["to_world"] = tw
        scene = mi.load_dict({"type": "scene", "c": d})
        world = [list(tw @ mi.ScalarPoint3f(p)) if tw is not None else p for p, _ in pts]

        def pick(rng):
            # A point on the segment from control point k to a neighbour's sphere.
            k = rng.randrange(len(pts))
            j = min(k + 1, len(pts) - 1)
            s = rng.random()
            c = [world[k][i] * (1 - s) + world[j][i] * s for i in range(3)]
            return c, pts[k][1] * (1 - s) + pts[j][1] * s

        hits = aimed_hits(scene, rng, args.rays, pick)
        misses = box_misses(scene, rng, args.rays, (1.3, 0.9, 0.7))
        cases.append({"name": name, "shape": xml, "hits": hits, "misses": misses})
    write(args.out, cases)


if __name__ == "__main__":
    main()
