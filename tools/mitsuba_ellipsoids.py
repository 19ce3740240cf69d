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


def read_ply():
    """The rows of scenes/ellipsoids/ellipsoids.ply as `write_ply` returns them."""
    text = open(PLY).read().split("end_header\n")[1]
    return [[float(x) for x in line.split()] for line in text.strip().split("\n")]


def hit_cases(shape_type, cases, rows, rng, rays, aimed=0.5, inside=0.2, outside=None,
              to_world_scale=1.0):
    """Mitsuba's hits and misses on each of `cases` (name, XML, the dictionary's
    parameters) of a `shape_type` shape made of the ellipsoids `rows`: until `rays`
    of each, a ray is aimed from 3 units away at a point inside a random ellipsoid
    (probability `aimed`), starts at its centre (`inside`), or goes from the cube
    [-3, 3]^3 through the box of the ellipsoids. With `outside`, rays start farther
    than `outside` times the largest semi-axis from every centre; the semi-axes are
    taken `to_world_scale` times larger under a to_world."""
    out = []
    for name, xml, extra in cases:
        d = {"type": shape_type, "filename": PLY}
        d.update(extra)
        scene = mi.load_dict({"type": "scene", "e": d})
        tw = extra.get("to_world")
        k = extra.get("extent", 3.0) * extra.get("scale_factor", 1.0)
        if tw is not None:
            k *= to_world_scale
        centres = [list(tw @ mi.ScalarPoint3f(r[:3])) if tw is not None else r[:3] for r in rows]
        size = [k * max(math.exp(x) for x in r[7:10]) for r in rows]
        hits, misses = [], []

        def trace(o, dvec):
            o, dvec = rounded(o, dvec)
            if outside is not None and any(
                    math.dist(o, c) <= outside * s for c, s in zip(centres, size)):
                return
            si = scene.ray_intersect(mi.Ray3f(o, dvec))
            if si.is_valid():
                if not grazing(si, dvec) and len(hits) < rays:
                    hits.append(record(si, o, dvec, frame_s=False))
            elif len(misses) < rays and clear_miss(scene, o, dvec):
                misses.append({"o": o, "d": dvec})

        while len(hits) < rays or len(misses) < rays:
            j = rng.randrange(len(rows))
            kind = rng.random()
            if kind < aimed:
                target = [centres[j][i] + 0.5 * size[j] * x for i, x in enumerate(rand_dir(rng))]
                o = [target[i] + 3.0 * x for i, x in enumerate(rand_dir(rng))]
                trace(o, unit([target[i] - o[i] for i in range(3)]))
            elif kind < aimed + inside:
                trace(centres[j], rand_dir(rng))
            else:
                o = [rng.uniform(-3, 3) for _ in range(3)]
                target = [rng.uniform(-1.6, 1.6), rng.uniform(-1.1, 1.1), rng.uniform(-0.9, 0.9)]
                trace(o, unit([target[i] - o[i] for i in range(3)]))
        out.append({"name": name, "shape": xml, "hits": hits, "misses": misses})
    return out


def main():
    args = arguments("ellipsoids_hits.json")
    rng = random.Random(40)
    rows = write_ply(rng)
    write(args.out, hit_cases("ellipsoids", CASES, rows, rng, args.rays))


if __name__ == "__main__":
    main()
