#!/usr/bin/env python3
"""Record where rays hit Mitsuba 3's `ellipsoids` shape, for
tests/ellipsoids_hits_vs_mitsuba.rs: wavetrace must find the same points and normals
on the GPU, and miss where Mitsuba misses (rays starting inside an ellipsoid too:
Mitsuba culls its back faces).

    python3 tools/mitsuba_ellipsoids.py [--out tests/data/ellipsoids_hits.json] [--rays 200]

Writes scenes/ellipsoids/ellipsoids.ply first (16 ellipsoids, ASCII, with an
`opacity` attribute between the geometry's properties as Mitsuba's files have
them): random centres in a box, log-scales in [-2.3, -1.2] (semi-axes of 0.1 to 0.3
times the extent, 3), random unit quaternions written (w, x, y, z). Cases: the file
plain, with `extent` 1.5 and `scale_factor` 1.2, and under a to_world. Rays: aimed at
points inside random ellipsoids from 3 units away (hits at |cos| < 0.1 left out,
where a last bit decides), from the centres of ellipsoids (inside: Mitsuba misses
that one) and random rays through the box; misses kept where rays moved by 1e-3
miss too. A fixed seed: running it again gives the same files.
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
    ("ellipsoids", f'<shape type="ellipsoids">{FILE}</shape>', {}),
    ("ellipsoids_extent",
     f'<shape type="ellipsoids">{FILE}<float name="extent" value="1.5"/>'
     '<float name="scale_factor" value="1.2"/></shape>',
     {"extent": 1.5, "scale_factor": 1.2}),
    ("ellipsoids_to_world", f'<shape type="ellipsoids">{FILE}{TO_WORLD_XML}</shape>',
     {"to_world": to_world()}),
]


def write_ply(rng, n=16):
    rows = []
    for _ in range(n):
        c = [rng.uniform(-1.5, 1.5), rng.uniform(-1.0, 1.0), rng.uniform(-0.8, 0.8)]
        s = [rng.uniform(-2.3, -1.2) for _ in range(3)]
        q = unit([rng.gauss(0, 1) for _ in range(4)])
        rows.append(c + [0.0, 0.0, 1.0, rng.random()] + s + q)
    names = ["x", "y", "z", "nx", "ny", "nz", "opacity", "scale_0", "scale_1", "scale_2",
             "rot_0", "rot_1", "rot_2", "rot_3"]
    with open(PLY, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\n" % n)
        for name in names:
            f.write("property float %s\n" % name)
        f.write("end_header\n")
        for r in rows:
            f.write(" ".join("%.6f" % x for x in r) + "\n")
    return [[float("%.6f" % x) for x in r] for r in rows]


def main():
    args = arguments("ellipsoids_hits.json")
    rng = random.Random(40)
    rows = write_ply(rng)
    cases = []
    for name, xml, extra in CASES:
        d = {"type": "ellipsoids", "filename": PLY}
        d.update(extra)
        scene = mi.load_dict({"type": "scene", "e": d})
        tw = extra.get("to_world")
        k = extra.get("extent", 3.0) * extra.get("scale_factor", 1.0)
        centres = [list(tw @ mi.ScalarPoint3f(r[:3])) if tw is not None else r[:3] for r in rows]
        size = [k * max(math.exp(x) for x in r[7:10]) for r in rows]
        hits, misses = [], []

        def trace(o, dvec):
            o, dvec = rounded(o, dvec)
            si = scene.ray_intersect(mi.Ray3f(o, dvec))
            if si.is_valid():
                if not grazing(si, dvec) and len(hits) < args.rays:
                    hits.append(record(si, o, dvec, frame_s=False))
            elif len(misses) < args.rays and clear_miss(scene, o, dvec):
                misses.append({"o": o, "d": dvec})

        inside = 0
        while len(hits) < args.rays or len(misses) < args.rays:
            j = rng.randrange(len(rows))
            kind = rng.random()
            if kind < 0.5:
                target = [centres[j][i] + 0.5 * size[j] * x for i, x in enumerate(rand_dir(rng))]
                o = [target[i] + 3.0 * x for i, x in enumerate(rand_dir(rng))]
                trace(o, unit([target[i] - o[i] for i in range(3)]))
            elif kind < 0.7:
                inside += 1
                trace(centres[j], rand_dir(rng))
            else:
                o = [rng.uniform(-3, 3) for _ in range(3)]
                target = [rng.uniform(-1.6, 1.6), rng.uniform(-1.1, 1.1), rng.uniform(-0.9, 0.9)]
                trace(o, unit([target[i] - o[i] for i in range(3)]))
        cases.append({"name": name, "shape": xml, "hits": hits, "misses": misses})
    write(args.out, cases)


if __name__ == "__main__":
    main()
