#!/usr/bin/env python3
"""Write the Cornell box scene: OBJ meshes from the published measurements, and cbox.xml.

    python3 tools/make_cbox.py     # writes scenes/cbox/{cbox.xml,cbox_path.xml,meshes/}

Geometry is the Cornell Program of Computer Graphics' measured data ("Cornell Box
Data", https://www.graphics.cornell.edu/online/box/data.html), in millimetres, with
the camera at (278, 273, -800) looking down +z. The light quad is lowered 0.5 mm
below the ceiling so the two are not coplanar.

Each quad is written as two triangles wound counter-clockwise about an explicit face
normal (`vn`): walls face the inside of the room, block faces point out of the
blocks, the light faces down. Explicit normals keep Mitsuba 3's OBJ loader from
computing smoothed vertex normals across the blocks' edges.

Reflectances are plain RGB diffuse values (the usual RGB stand-ins for the measured
spectra); the light's radiance is (17, 12, 4).

cbox.xml renders ambient occlusion at 256x256. cbox_path.xml is the same geometry
with Mitsuba's `path` integrator (max_depth 6) and scene parameters `res` (default
128, the size of the reference and the tests; `-D res=256` for the full picture),
`spp` (64) and `max_depth` (6).
"""

import os

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
OUT = os.path.join(ROOT, "scenes", "cbox")

ROOM_CENTER = (278.0, 274.4, 279.6)
LIGHT_Y = 548.8 - 0.5

# name -> list of quads (4 corners each), from the Cornell data.
QUADS = {
    "floor": [[(552.8, 0, 0), (0, 0, 0), (0, 0, 559.2), (549.6, 0, 559.2)]],
    "ceiling": [[(556.0, 548.8, 0), (556.0, 548.8, 559.2), (0, 548.8, 559.2), (0, 548.8, 0)]],
    "back": [[(549.6, 0, 559.2), (0, 0, 559.2), (0, 548.8, 559.2), (556.0, 548.8, 559.2)]],
    "greenwall": [[(0, 0, 559.2), (0, 0, 0), (0, 548.8, 0), (0, 548.8, 559.2)]],
    "redwall": [[(552.8, 0, 0), (549.6, 0, 559.2), (556.0, 548.8, 559.2), (556.0, 548.8, 0)]],
    "light": [[(343.0, LIGHT_Y, 227.0), (343.0, LIGHT_Y, 332.0), (213.0, LIGHT_Y, 332.0), (213.0, LIGHT_Y, 227.0)]],
    "shortbox": [
        [(130.0, 165.0, 65.0), (82.0, 165.0, 225.0), (240.0, 165.0, 272.0), (290.0, 165.0, 114.0)],
        [(290.0, 0.0, 114.0), (290.0, 165.0, 114.0), (240.0, 165.0, 272.0), (240.0, 0.0, 272.0)],
        [(130.0, 0.0, 65.0), (130.0, 165.0, 65.0), (290.0, 165.0, 114.0), (290.0, 0.0, 114.0)],
        [(82.0, 0.0, 225.0), (82.0, 165.0, 225.0), (130.0, 165.0, 65.0), (130.0, 0.0, 65.0)],
        [(240.0, 0.0, 272.0), (240.0, 165.0, 272.0), (82.0, 165.0, 225.0), (82.0, 0.0, 225.0)],
    ],
    "tallbox": [
        [(423.0, 330.0, 247.0), (265.0, 330.0, 296.0), (314.0, 330.0, 456.0), (472.0, 330.0, 406.0)],
        [(423.0, 0.0, 247.0), (423.0, 330.0, 247.0), (472.0, 330.0, 406.0), (472.0, 0.0, 406.0)],
        [(472.0, 0.0, 406.0), (472.0, 330.0, 406.0), (314.0, 330.0, 456.0), (314.0, 0.0, 456.0)],
        [(314.0, 0.0, 456.0), (314.0, 330.0, 456.0), (265.0, 330.0, 296.0), (265.0, 0.0, 296.0)],
        [(265.0, 0.0, 296.0), (265.0, 330.0, 296.0), (423.0, 330.0, 247.0), (423.0, 0.0, 247.0)],
    ],
}

# name -> (bsdf id, what the normals should face)
ROLES = {
    "floor": ("white", "inside"),
    "ceiling": ("white", "inside"),
    "back": ("white", "inside"),
    "greenwall": ("green", "inside"),
    "redwall": ("red", "inside"),
    "light": ("light", "down"),
    "shortbox": ("white", "outside"),
    "tallbox": ("white", "outside"),
}

BSDFS = [
    ("white", "0.725, 0.71, 0.68"),
    ("red", "0.63, 0.065, 0.05"),
    ("green", "0.14, 0.45, 0.091"),
    ("light", "0.78, 0.78, 0.78"),
]


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def normalize(v):
    length = dot(v, v) ** 0.5
    return tuple(c / length for c in v)


def centroid(points):
    return tuple(sum(p[i] for p in points) / len(points) for i in range(3))


def write_obj(name, quads, facing):
    solid_center = centroid([p for q in quads for p in q])
    lines = ["# Cornell box: %s (Cornell measured data, mm)" % name, "# written by tools/make_cbox.py"]
    normals, faces = [], []
    vcount = 0
    for quad in quads:
        # Newell's method: robust for the slightly non-planar measured quads.
        n = [0.0, 0.0, 0.0]
        for i, p in enumerate(quad):
            q = quad[(i + 1) % 4]
            n[0] += (p[1] - q[1]) * (p[2] + q[2])
            n[1] += (p[2] - q[2]) * (p[0] + q[0])
            n[2] += (p[0] - q[0]) * (p[1] + q[1])
        n = normalize(n)
        if facing == "inside":
            want = sub(ROOM_CENTER, centroid(quad))
        elif facing == "outside":
            want = sub(centroid(quad), solid_center)
        else:
            want = (0.0, -1.0, 0.0)
        if dot(n, want) < 0:
            quad = list(reversed(quad))
            n = tuple(-c for c in n)
        for p in quad:
            lines.append("v %g %g %g" % p)
        normals.append(n)
        k = len(normals)
        a, b, c, d = (vcount + i for i in (1, 2, 3, 4))
        faces.append("f %d//%d %d//%d %d//%d" % (a, k, b, k, c, k))
        faces.append("f %d//%d %d//%d %d//%d" % (a, k, c, k, d, k))
        vcount += 4
    lines += ["vn %.6f %.6f %.6f" % n for n in normals] + faces
    with open(os.path.join(OUT, "meshes", name + ".obj"), "w") as f:
        f.write("\n".join(lines) + "\n")


HEADERS = {
    "ao": ("Cornell box (Mitsuba 3 dialect, RGB)", "", '<integrator type="ao"/>', "64", "256"),
    "path": (
        "Cornell box lit by its ceiling light, path traced (Mitsuba 3 dialect, RGB)",
        """
    <default name="res" value="128"/>
    <default name="spp" value="64"/>
    <default name="max_depth" value="6"/>
""",
        """<integrator type="path">
        <integer name="max_depth" value="$max_depth"/>
    </integrator>""",
        "$spp",
        "$res",
    ),
}


def scene_xml(kind):
    bsdfs = "\n".join(
        """    <bsdf type="diffuse" id="%s">
        <rgb name="reflectance" value="%s"/>
    </bsdf>""" % b
        for b in BSDFS
    )
    shapes = []
    for name in QUADS:
        bsdf = ROLES[name][0]
        emitter = ""
        if name == "light":
            emitter = """
        <emitter type="area">
            <rgb name="radiance" value="17, 12, 4"/>
        </emitter>"""
        shapes.append(
            """    <shape type="obj">
        <string name="filename" value="meshes/%s.obj"/>
        <ref id="%s"/>%s
    </shape>""" % (name, bsdf, emitter)
        )
    title, defaults, integrator, spp, res = HEADERS[kind]
    return """<!-- %s; written by tools/make_cbox.py. -->
<scene version="3.0.0">%s
    %s

    <sensor type="perspective">
        <string name="fov_axis" value="smaller"/>
        <float name="near_clip" value="10"/>
        <float name="far_clip" value="2800"/>
        <float name="fov" value="39.3077"/>
        <transform name="to_world">
            <lookat origin="278, 273, -800" target="278, 273, -799" up="0, 1, 0"/>
        </transform>
        <sampler type="independent">
            <integer name="sample_count" value="%s"/>
        </sampler>
        <film type="hdrfilm">
            <integer name="width" value="%s"/>
            <integer name="height" value="%s"/>
            <rfilter type="box"/>
        </film>
    </sensor>

%s

%s
</scene>
""" % (title, defaults, integrator, spp, res, res, bsdfs, "\n".join(shapes))


def main():
    os.makedirs(os.path.join(OUT, "meshes"), exist_ok=True)
    for name, quads in QUADS.items():
        write_obj(name, quads, ROLES[name][1])
    for kind, name in (("ao", "cbox.xml"), ("path", "cbox_path.xml")):
        with open(os.path.join(OUT, name), "w") as f:
            f.write(scene_xml(kind))
    print("wrote %s: %d meshes" % (os.path.relpath(OUT, ROOT), len(QUADS)))


if __name__ == "__main__":
    main()
