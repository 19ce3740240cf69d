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

import random

import mitsuba as mi

mi.set_variant("scalar_rgb")

from mitsuba_ellipsoids import hit_cases, read_ply  # noqa: E402
from mitsuba_hits import TO_WORLD_XML, arguments, to_world, write  # noqa: E402

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


def main():
    args = arguments("ellipsoidsmesh_hits.json")
    rng = random.Random(41)
    # No inside rays; semi-axes taken 1.3 times larger (the to_world's largest scale)
    # where one applies.
    cases = hit_cases("ellipsoidsmesh", CASES, read_ply(), rng, args.rays, aimed=0.6,
                      inside=0.0, outside=1.6, to_world_scale=1.3)
    write(args.out, cases)


if __name__ == "__main__":
    main()
