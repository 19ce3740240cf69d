#!/usr/bin/env python3
"""Write the ambient-occlusion test scene: OBJ meshes plus the same scene in two dialects.

    python3 tools/make_ao_scene.py            # writes scenes/ao/{ao.xml,ao_nori.xml,meshes/}

The scene is made only of triangle meshes (Nori has no analytic shapes), every mesh
closed or facing the camera, with explicit per-vertex normals everywhere:

* ground.obj   a 48 x 48 quad at y = 0, normal +y, large enough to fill the view;
* box.obj      a 1.2 x 2.0 x 1.2 box turned 30 degrees about y (flat faces);
* cubes.obj    four 0.6-unit cubes with 0.08-unit gaps and one stacked on top:
               narrow crevices, the hardest case for occlusion;
* torus.obj    a torus lying on the ground (contact crease), smooth vertex normals;
* sphere.obj   a UV sphere resting on the ground, smooth vertex normals.

Flat meshes get explicit face normals too. Mitsuba 3's OBJ loader computes smooth
vertex normals for a mesh that has none, while Nori uses the geometric normal: writing
them removes the ambiguity, so all three renderers shade the same surface.

The output is deterministic (no randomness), so rerunning it reproduces the committed
files byte for byte.
"""

import math
import os

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
OUT = os.path.join(ROOT, "scenes", "ao")

# Camera, shared by both dialects. Mitsuba's default fov_axis is x, and Nori's fov is
# horizontal, so the same number means the same camera (the film is square anyway).
ORIGIN = (0.0, 3.8, 5.0)
TARGET = (0.0, 0.5, -0.1)
UP = (0.0, 1.0, 0.0)
FOV = 45.0
RES = 128
SPP = 64


class Obj:
    """A mesh being written: positions, normals and triangles as (v, n) index pairs."""

    def __init__(self):
        self.v = []
        self.n = []
        self.f = []

    def vertex(self, p):
        self.v.append(p)
        return len(self.v)

    def normal(self, n):
        self.n.append(normalize(n))
        return len(self.n)

    def tri(self, a, b, c):
        self.f.append((a, b, c))

    def write(self, path, comment):
        with open(path, "w") as out:
            out.write("# %s\n# written by tools/make_ao_scene.py\n" % comment)
            for p in self.v:
                out.write("v %.6f %.6f %.6f\n" % p)
            for n in self.n:
                out.write("vn %.6f %.6f %.6f\n" % n)
            for tri in self.f:
                out.write("f %s\n" % " ".join("%d//%d" % vn for vn in tri))


def normalize(v):
    length = math.sqrt(sum(c * c for c in v))
    return tuple(c / length for c in v)


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def flat_quad(obj, corners, outward):
    """Two triangles over a planar quad, wound counter-clockwise seen from `outward`."""
    p = list(corners)
    if dot(cross(sub(p[1], p[0]), sub(p[2], p[0])), outward) < 0:
        p.reverse()
    n = obj.normal(outward)
    i = [obj.vertex(q) for q in p]
    obj.tri((i[0], n), (i[1], n), (i[2], n))
    obj.tri((i[0], n), (i[2], n), (i[3], n))


def add_box(obj, center, size, yaw_deg=0.0):
    """An axis-aligned box (bottom face at center.y), then turned `yaw_deg` about y."""
    cx, y0, cz = center
    sx, sy, sz = (s / 2 for s in size)
    c, s = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))

    def turn(x, y, z):  # rotate about the y axis, then move to the centre
        return (cx + c * x + s * z, y0 + y, cz - s * x + c * z)

    def turn_dir(x, y, z):
        return (c * x + s * z, y, -s * x + c * z)

    h = 2 * sy
    faces = [  # (outward normal, four corners) in box-local coordinates
        ((1, 0, 0), [(sx, 0, -sz), (sx, 0, sz), (sx, h, sz), (sx, h, -sz)]),
        ((-1, 0, 0), [(-sx, 0, -sz), (-sx, 0, sz), (-sx, h, sz), (-sx, h, -sz)]),
        ((0, 1, 0), [(-sx, h, -sz), (sx, h, -sz), (sx, h, sz), (-sx, h, sz)]),
        ((0, -1, 0), [(-sx, 0, -sz), (sx, 0, -sz), (sx, 0, sz), (-sx, 0, sz)]),
        ((0, 0, 1), [(-sx, 0, sz), (sx, 0, sz), (sx, h, sz), (-sx, h, sz)]),
        ((0, 0, -1), [(-sx, 0, -sz), (sx, 0, -sz), (sx, h, -sz), (-sx, h, -sz)]),
    ]
    for n, quad in faces:
        flat_quad(obj, [turn(*q) for q in quad], turn_dir(*n))


def add_smooth_grid(obj, rows, cols, point_normal, wrap_rows):
    """A (rows x cols) parametric surface; point_normal(i, j) -> (position, normal).

    Columns always wrap; rows wrap when `wrap_rows` (a torus), else the first and last
    rows are poles where all columns collapse into one vertex (a sphere).
    """
    index = {}
    for i in range(rows + (0 if wrap_rows else 1)):
        for j in range(cols):
            p, n = point_normal(i, j)
            index[i, j] = (obj.vertex(p), obj.normal(n))
    last = rows if wrap_rows else rows - 1
    for i in range(last + (0 if wrap_rows else 1)):
        for j in range(cols):
            a = index[i % rows if wrap_rows else i, j]
            b = index[i % rows if wrap_rows else i, (j + 1) % cols]
            i1 = (i + 1) % rows if wrap_rows else i + 1
            c = index[i1, (j + 1) % cols]
            d = index[i1, j]
            # Wind counter-clockwise about the outward normal.
            n_avg = obj.n[a[1] - 1]
            tris = [(a, b, c), (a, c, d)]
            if not wrap_rows and i == 0:
                tris = [(a, c, d)]  # a, b are the same pole vertex position
            if not wrap_rows and i == rows - 1:
                tris = [(a, b, c)]  # c, d are the pole
            for t in tris:
                p0, p1, p2 = (obj.v[k[0] - 1] for k in t)
                if dot(cross(sub(p1, p0), sub(p2, p0)), n_avg) < 0:
                    t = (t[0], t[2], t[1])
                obj.tri(*t)


def torus(center, major, minor, rows=32, cols=64):
    obj = Obj()
    cx, cy, cz = center

    def point_normal(i, j):
        # i: around the tube, j: around the main ring; axis of symmetry is y.
        u = 2 * math.pi * j / cols
        v = 2 * math.pi * i / rows
        ring = (math.cos(u), 0.0, math.sin(u))
        n = (ring[0] * math.cos(v), math.sin(v), ring[2] * math.cos(v))
        p = (cx + major * ring[0] + minor * n[0], cy + minor * n[1], cz + major * ring[2] + minor * n[2])
        return p, n

    add_smooth_grid(obj, rows, cols, point_normal, wrap_rows=True)
    return obj


def sphere(center, radius, rows=32, cols=64):
    obj = Obj()
    cx, cy, cz = center

    def point_normal(i, j):
        theta = math.pi * i / rows  # from the top pole down
        phi = 2 * math.pi * j / cols
        n = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
        return (cx + radius * n[0], cy + radius * n[1], cz + radius * n[2]), n

    add_smooth_grid(obj, rows, cols, point_normal, wrap_rows=False)
    return obj


SHAPES = [
    ("ground", "ground quad, 48 x 48 at y = 0"),
    ("box", "box 1.2 x 2.0 x 1.2 turned 30 degrees"),
    ("cubes", "four 0.6 cubes with 0.08 gaps, one stacked"),
    ("torus", "torus R = 0.9, r = 0.3 lying on the ground, smooth normals"),
    ("sphere", "UV sphere r = 0.55 on the ground, smooth normals"),
]


def build_meshes():
    ground = Obj()
    flat_quad(ground, [(-24, 0, -24), (24, 0, -24), (24, 0, 24), (-24, 0, 24)], (0, 1, 0))

    box = Obj()
    add_box(box, (-1.7, 0.0, -0.7), (1.2, 2.0, 1.2), yaw_deg=30.0)

    cubes = Obj()
    a, g = 0.6, 0.08
    x0, z0 = 0.3, -1.9
    for dx, dz in [(0, 0), (1, 0), (0, 1)]:
        add_box(cubes, (x0 + dx * (a + g), 0.0, z0 + dz * (a + g)), (a, a, a))
    # Resting on the first two, bridging the gap between them: a roofed crevice.
    add_box(cubes, (x0 + (a + g) / 2, a, z0), (a, a, a))

    return {
        "ground": ground,
        "box": box,
        "cubes": cubes,
        "torus": torus((1.5, 0.3, 1.0), 0.9, 0.3),
        "sphere": sphere((-0.9, 0.55, 1.7), 0.55),
    }


def fmt(v):
    return ", ".join("%g" % c for c in v)


def mitsuba_xml():
    shapes = "\n".join(
        """    <shape type="obj">
        <string name="filename" value="meshes/%s.obj"/>
        <ref id="white"/>
    </shape>""" % name
        for name, _ in SHAPES
    )
    return """<!-- Ambient-occlusion test scene (Mitsuba 3 dialect); written by tools/make_ao_scene.py.
     The same scene in Nori's dialect is ao_nori.xml. -->
<scene version="3.0.0">
    <integrator type="ao"/>

    <sensor type="perspective">
        <float name="fov" value="%(fov)g"/>
        <transform name="to_world">
            <lookat origin="%(origin)s" target="%(target)s" up="%(up)s"/>
        </transform>
        <sampler type="independent">
            <integer name="sample_count" value="%(spp)d"/>
        </sampler>
        <film type="hdrfilm">
            <integer name="width" value="%(res)d"/>
            <integer name="height" value="%(res)d"/>
            <rfilter type="box"/>
        </film>
    </sensor>

    <bsdf type="diffuse" id="white">
        <rgb name="reflectance" value="1"/>
    </bsdf>

%(shapes)s
</scene>
""" % dict(fov=FOV, origin=fmt(ORIGIN), target=fmt(TARGET), up=fmt(UP), spp=SPP, res=RES, shapes=shapes)


def nori_xml():
    shapes = "\n".join(
        """    <mesh type="obj">
        <string name="filename" value="meshes/%s.obj"/>
        <bsdf type="diffuse">
            <color name="albedo" value="1, 1, 1"/>
        </bsdf>
    </mesh>""" % name
        for name, _ in SHAPES
    )
    return """<!-- Ambient-occlusion test scene (Nori dialect); written by tools/make_ao_scene.py.
     The same scene as ao.xml (Mitsuba 3 dialect). -->
<scene>
    <integrator type="ao"/>

    <sampler type="independent">
        <integer name="sampleCount" value="%(spp)d"/>
    </sampler>

    <camera type="perspective">
        <transform name="toWorld">
            <!-- Nori's image x runs along camera -x, Mitsuba's along +x. -->
            <scale value="-1,1,1"/>
            <lookat origin="%(origin)s" target="%(target)s" up="%(up)s"/>
        </transform>
        <float name="fov" value="%(fov)g"/>
        <integer name="width" value="%(res)d"/>
        <integer name="height" value="%(res)d"/>
        <!-- The box filter of its Mitsuba twin (Nori's default is a Gaussian). -->
        <rfilter type="box"/>
    </camera>

%(shapes)s
</scene>
""" % dict(fov=FOV, origin=fmt(ORIGIN), target=fmt(TARGET), up=fmt(UP), spp=SPP, res=RES, shapes=shapes)


def main():
    os.makedirs(os.path.join(OUT, "meshes"), exist_ok=True)
    meshes = build_meshes()
    for name, comment in SHAPES:
        meshes[name].write(os.path.join(OUT, "meshes", name + ".obj"), comment)
    with open(os.path.join(OUT, "ao.xml"), "w") as f:
        f.write(mitsuba_xml())
    with open(os.path.join(OUT, "ao_nori.xml"), "w") as f:
        f.write(nori_xml())
    tris = sum(len(m.f) for m in meshes.values())
    print("wrote %s: %d meshes, %d triangles" % (os.path.relpath(OUT, ROOT), len(meshes), tris))


if __name__ == "__main__":
    main()
