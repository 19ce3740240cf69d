#!/usr/bin/env python3
"""Write an instancing stress scene: one mesh of about 100,000 triangles (a bumpy
latitude-longitude rock, binary PLY) placed N times (default 10,000: 10^9 triangles
seen) by Mitsuba 3 `shapegroup` / `instance`, on a grid with turns and scales drawn
from a fixed seed; or, with --flatten, the same placements written as N separate
`ply` shapes (each loaded and stored on its own), to compare against as far as
memory allows.

    python3 tools/make_instances.py OUT_DIR [--instances N] [--flatten] [--res W]

Writes OUT_DIR/rock.ply (once) and OUT_DIR/instances_N.xml or flat_N.xml. Then:

    wavetrace info OUT_DIR/instances_10000.xml       # triangles, build time, memory
    wavetrace render OUT_DIR/instances_10000.xml --spp 4 -o out.exr

Deterministic: running it again writes the same bytes. Nothing here is committed but
this script (the scene is large).
"""

import argparse
import math
import os
import random
import struct

# 317 x 159 quads, less the poles' degenerate halves: 100,172 triangles.
NU, NV = 317, 159


def rock_ply(path):
    """A sphere of radius ~1 with a few low-frequency bumps, (NU+1) x (NV+1)
    vertices, two triangles per quad (degenerate ones at the poles dropped)."""
    verts = []
    for j in range(NV + 1):
        theta = math.pi * j / NV
        for i in range(NU + 1):
            phi = 2.0 * math.pi * i / NU
            r = 1.0 + 0.08 * math.sin(5 * phi) * math.sin(3 * theta) + 0.05 * math.cos(7 * theta)
            verts.append((r * math.sin(theta) * math.cos(phi),
                          r * math.cos(theta),
                          r * math.sin(theta) * math.sin(phi)))
    faces = []
    row = NU + 1
    for j in range(NV):
        for i in range(NU):
            a, b = j * row + i, j * row + i + 1
            c, d = a + row, b + row
            if j > 0:
                faces.append((a, b, c))
            if j < NV - 1:
                faces.append((b, d, c))
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(verts)}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    with open(path, "wb") as f:
        f.write(header.encode())
        f.write(b"".join(struct.pack("<3f", *v) for v in verts))
        f.write(b"".join(struct.pack("<B3i", 3, *t) for t in faces))
    return len(faces)


def placements(n):
    """n (translate, rotate-y degrees, scale) on a square grid, spacing 3."""
    rng = random.Random(7)
    side = math.ceil(math.sqrt(n))
    out = []
    for k in range(n):
        x, z = k % side, k // side
        out.append(((x - side / 2) * 3.0, (z - side / 2) * 3.0,
                    rng.uniform(0, 360), rng.uniform(0.6, 1.3)))
    return out, side


def transform(x, z, angle, s):
    return (f'<transform name="to_world"><scale value="{s:.4f}"/>'
            f'<rotate y="1" angle="{angle:.3f}"/><translate x="{x:.3f}" z="{z:.3f}"/></transform>')


def scene(n, flatten, res):
    pl, side = placements(n)
    half = side * 1.5
    parts = [f"""<scene version="3.0.0">
<integrator type="path"><integer name="max_depth" value="3"/></integrator>
<sensor type="perspective"><float name="fov" value="60"/>
  <transform name="to_world"><lookat origin="{-half * 0.9:.2f}, {half * 0.35 + 4:.2f}, {-half * 0.9:.2f}" target="0, 0, 0" up="0, 1, 0"/></transform>
  <film type="hdrfilm"><integer name="width" value="{res}"/><integer name="height" value="{res}"/></film>
  <sampler type="independent"><integer name="sample_count" value="4"/></sampler></sensor>
<emitter type="constant"><rgb name="radiance" value="1"/></emitter>
<bsdf type="diffuse" id="stone"><rgb name="reflectance" value="0.5 0.45 0.4"/></bsdf>
<shape type="rectangle"><transform name="to_world"><scale value="{half + 3:.1f}"/><rotate x="1" angle="-90"/><translate y="-1"/></transform><ref id="stone"/></shape>
"""]
    rock = '<shape type="ply"><string name="filename" value="rock.ply"/>{}<ref id="stone"/></shape>\n'
    if flatten:
        for p in pl:
            parts.append(rock.format(transform(*p)))
    else:
        parts.append('<shape type="shapegroup" id="rock">' + rock.format("") + "</shape>\n")
        for p in pl:
            parts.append(f'<shape type="instance"><ref id="rock"/>{transform(*p)}</shape>\n')
    parts.append("</scene>\n")
    return "".join(parts)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out")
    ap.add_argument("--instances", type=int, default=10000)
    ap.add_argument("--flatten", action="store_true")
    ap.add_argument("--res", type=int, default=128)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    ply = os.path.join(a.out, "rock.ply")
    if not os.path.isfile(ply):
        tris = rock_ply(ply)
        print(f"wrote {ply}: {tris} triangles")
    name = f"{'flat' if a.flatten else 'instances'}_{a.instances}.xml"
    with open(os.path.join(a.out, name), "w") as f:
        f.write(scene(a.instances, a.flatten, a.res))
    print(f"wrote {os.path.join(a.out, name)}")


if __name__ == "__main__":
    main()
