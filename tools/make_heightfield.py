#!/usr/bin/env python3
"""Writes a large height-field mesh as a binary PLY, and a scene that renders it in
both wavetrace and Mitsuba 3: the input of the large-scene benchmark
(tools/bench_large.py, docs/performance.md "Large scenes").

    python3 tools/make_heightfield.py --triangles 8M -o target/large/hf8m [--obj]

writes hf8m.ply (binary little endian: vertex float x, y, z; face list uchar int
vertex_indices, the layout Mitsuba and most exporters write) and hf8m.xml; with --obj,
hf8m.obj (text) and hf8m_obj.xml instead. The grid
has N x N vertices over [-1, 1]^2 with N = 1 + round(sqrt(triangles / 2)), each quad
cut into two triangles; z = 0.08 (sin 13x cos 17y + 0.5 sin(41x + 29y)). Only the
Python standard library is needed (a 30 M-triangle file takes about a minute).
"""

import argparse
import math
import os
import struct
import sys

SCENE = """<!-- Height field of {triangles} triangles ({n} x {n} vertices); written by tools/make_heightfield.py. -->
<scene version="3.0.0">
    <default name="res" value="256"/>
    <default name="spp" value="16"/>
    <default name="max_depth" value="4"/>
    <integrator type="path">
        <integer name="max_depth" value="$max_depth"/>
    </integrator>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world">
            <lookat origin="0, -2.2, 1.6" target="0, 0, 0" up="0, 0, 1"/>
        </transform>
        <sampler type="independent">
            <integer name="sample_count" value="$spp"/>
        </sampler>
        <film type="hdrfilm">
            <integer name="width" value="$res"/>
            <integer name="height" value="$res"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <shape type="ply">
        <string name="filename" value="{ply}"/>
        <bsdf type="diffuse">
            <rgb name="reflectance" value="0.6, 0.55, 0.5"/>
        </bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" value="1.5, -1.0, 2.5"/>
        <float name="radius" value="0.4"/>
        <emitter type="area">
            <rgb name="radiance" value="20, 19, 17"/>
        </emitter>
    </shape>
    <emitter type="constant">
        <rgb name="radiance" value="0.2, 0.25, 0.3"/>
    </emitter>
</scene>
"""


def count(text):
    """'8M', '500k' or '1000' as an integer."""
    scale = {"k": 10**3, "m": 10**6}.get(text[-1:].lower(), 1)
    digits = text[:-1] if scale != 1 else text
    try:
        return int(float(digits) * scale)
    except ValueError:
        sys.exit("make_heightfield.py: --triangles expects a count such as 8M, got %r" % text)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--triangles", default="1M", help="about this many triangles (8M, 500k, ...)")
    ap.add_argument("-o", "--output", required=True, help="output path without extension")
    ap.add_argument("--obj", action="store_true", help="write a Wavefront OBJ instead")
    args = ap.parse_args()
    n = 1 + max(1, round(math.sqrt(count(args.triangles) / 2)))
    triangles = 2 * (n - 1) ** 2
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    step = 2.0 / (n - 1)
    xs = [-1.0 + i * step for i in range(n)]
    sx13 = [math.sin(13 * x) for x in xs]

    def height(i, y, c17):
        return 0.08 * (sx13[i] * c17 + 0.5 * math.sin(41 * xs[i] + 29 * y))

    if args.obj:
        mesh = args.output + ".obj"
        with open(mesh, "w") as f:
            f.write("# tools/make_heightfield.py\n")
            for j in range(n):
                y = -1.0 + j * step
                c17 = math.cos(17 * y)
                f.write("".join("v %.7g %.7g %.7g\n" % (x, y, height(i, y, c17))
                                for i, x in enumerate(xs)))
            for j in range(n - 1):
                f.write("".join("f %d %d %d\nf %d %d %d\n" % (v, v + 1, v + n + 1, v, v + n + 1, v + n)
                                for v in range(j * n + 1, j * n + n)))
        with open(args.output + "_obj.xml", "w") as f:
            f.write(SCENE.format(triangles=triangles, n=n, ply=os.path.basename(mesh))
                    .replace('type="ply"', 'type="obj"'))
        print("wrote %s (%d triangles, %.0f MB) and %s_obj.xml"
              % (mesh, triangles, os.path.getsize(mesh) / 1e6, args.output))
        return
    ply = args.output + ".ply"
    with open(ply, "wb") as f:
        f.write(("ply\nformat binary_little_endian 1.0\ncomment tools/make_heightfield.py\n"
                 "element vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
                 "element face %d\nproperty list uchar int vertex_indices\nend_header\n"
                 % (n * n, triangles)).encode())
        row = struct.Struct("<%df" % (3 * n))
        for j in range(n):
            y = -1.0 + j * step
            c17 = math.cos(17 * y)
            values = []
            for i, x in enumerate(xs):
                values += (x, y, height(i, y, c17))
            f.write(row.pack(*values))
        faces = struct.Struct("<" + "Biii" * (2 * (n - 1)))
        for j in range(n - 1):
            values = []
            for i in range(n - 1):
                v = j * n + i
                values += (3, v, v + 1, v + n + 1, 3, v, v + n + 1, v + n)
            f.write(faces.pack(*values))
    with open(args.output + ".xml", "w") as f:
        f.write(SCENE.format(triangles=triangles, n=n, ply=os.path.basename(ply)))
    print("wrote %s (%d triangles, %d vertices, %.0f MB) and %s.xml"
          % (ply, triangles, n * n, os.path.getsize(ply) / 1e6, args.output))


if __name__ == "__main__":
    main()
