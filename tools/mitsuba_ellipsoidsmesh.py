#!/usr/bin/env python3
"""Record where rays hit Mitsuba 3's `ellipsoidsmesh` shape (each ellipsoid of a PLY
file a triangle shell: an icosahedron or a box, scaled to enclose the unit sphere),
for tests/ellipsoids_hits_vs_mitsuba.rs: wavetrace must find the same points and
(flat) normals on the GPU, and miss where Mitsuba misses.

    python3 tools/mitsuba_ellipsoidsmesh.py [--out tests/data/ellipsoidsmesh_hits.json] [--rays 200]

Reads scenes/ellipsoids/ellipsoids.ply (tools/mitsuba_ellipsoids.py writes it). Cases:
the `ico_sphere` shell plain, the `box` shell with `extent` 1.5 and `scale_factor` 1.2,
the `ico_sphere` shell under a to_world. Rays: aimed at points inside random
ellipsoids from 3 units away, and random rays through the box; none starts inside a
shell (Mitsuba culls the shells' back faces, wavetrace does not: rays from inside
would differ by design; the origin is kept 1.6 times the largest semi-axis, more than
either shell's circumradius, from every centre). Hits at |cos| < 0.1 are left out
and misses kept where rays moved by 1e-3 miss too (tools/mitsuba_hits.py). A fixed
seed: running it again gives the same file.
"""

import math
import os
import random

import mitsuba as mi

mi.set_variant("scalar_rgb")

from mitsuba_hits import (ROOT, TO_WORLD_XML, arguments, clear_miss, grazing,  # noqa: E402
                          rand_dir, record, rounded, to_world, unit, write)

PLY = os.path.join(ROOT, "scenes", "ellipsoids", "ellipsoids.ply")

FILE = '<string name="filename" value="ellipsoids.ply"/>'
CASES = [
    ("ellipsoidsmesh_ico", f'<shape type="ellipsoidsmesh">{FILE}</shape>', {}),
    ("ellipsoidsmesh_box_extent",
     f'<shape type="ellipsoidsmesh">{FILE}<string name="shell" value="box"/>'
     '<float name="extent" value="1.5"/><float name="scale_factor" value="1.2"/></shape>',
     {"shell": "box", "extent": 1.5, "scale_factor": 1.2}),
    ("ellipsoidsmesh_to_world", f'<shape type="ellipsoidsmesh">{FILE}{TO_WORLD_XML}</shape>',
     {"to_world": to_world()}),
]


def read_ply():
    text = open(PLY).read().split("end_header\n")[1]
    return [[float(x) for x in line.split()] for line in text.strip().split("\n")]


def main():
    args = arguments("ellipsoidsmesh_hits.json")
    rng = random.Random(41)
    rows = read_ply()
    cases = []
    for name, xml, extra in CASES:
        d = {"type": "ellipsoidsmesh", "filename": PLY}
        d.update(extra)
        scene = mi.load_dict({"type": "scene", "e": d})
        tw = extra.get("to_world")
        k = extra.get("extent", 3.0) * extra.get("scale_factor", 1.0)
        if tw is not None:
            k *= 1.3  # at most the to_world's largest scale
        centres = [list(tw @ mi.ScalarPoint3f(r[:3])) if tw is not None else r[:3] for r in rows]
        size = [k * max(math.exp(x) for x in r[7:10]) for r in rows]
        hits, misses = [], []

        def outside(o):
            return all(math.dist(o, c) > 1.6 * s for c, s in zip(centres, size))

        def trace(o, dvec):
            o, dvec = rounded(o, dvec)
            if not outside(o):
                return
            si = scene.ray_intersect(mi.Ray3f(o, dvec))
            if si.is_valid():
                if not grazing(si, dvec) and len(hits) < args.rays:
                    hits.append(record(si, o, dvec, frame_s=False))
            elif len(misses) < args.rays and clear_miss(scene, o, dvec):
                misses.append({"o": o, "d": dvec})

        while len(hits) < args.rays or len(misses) < args.rays:
            j = rng.randrange(len(rows))
            if rng.random() < 0.6:
                target = [centres[j][i] + 0.5 * size[j] * x for i, x in enumerate(rand_dir(rng))]
                o = [target[i] + 3.0 * x for i, x in enumerate(rand_dir(rng))]
                trace(o, unit([target[i] - o[i] for i in range(3)]))
            else:
                o = [rng.uniform(-3, 3) for _ in range(3)]
                target = [rng.uniform(-1.6, 1.6), rng.uniform(-1.1, 1.1), rng.uniform(-0.9, 0.9)]
                trace(o, unit([target[i] - o[i] for i in range(3)]))
        cases.append({"name": name, "shape": xml, "hits": hits, "misses": misses})
    write(args.out, cases)


if __name__ == "__main__":
    main()
