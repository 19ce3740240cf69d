#!/usr/bin/env python3
"""Write the test meshes of scenes/shapes/meshes/: the same few surfaces in every mesh
format wavetrace and Mitsuba 3 read, for the shape-convention tests.

    python3 tools/make_shape_meshes.py [--out scenes/shapes/meshes]

* uvsphere.obj            a latitude-longitude sphere (16 x 8) with v, vt, vn; quads,
                          triangles at the poles, the seam's vertices duplicated
* uvsphere_nonormals.obj  the same without vn (the loaders compute vertex normals)
* wave.ply                an ascii PLY height field (9 x 7 vertices), x y z u v, no
                          normals
* wave_binary.ply         the same, binary little endian, with nx ny nz, uvs named s t,
                          double positions, uchar/int face lists
* shapes.serialized       Mitsuba's zlib mesh format (version 4), two meshes: the wave
                          with normals and uvs in single precision, then the sphere's
                          positions in double precision without normals or uvs

Deterministic: running it again writes the same bytes.
"""

import argparse
import math
import os
import struct
import zlib


def uv_sphere(nu=16, nv=8):
    """Vertices (position, uv) on a (nu+1) x (nv+1) grid and faces as index lists,
    outward counter-clockwise; poles as triangles."""
    verts = []
    for j in range(nv + 1):
        theta = math.pi * j / nv
        for i in range(nu + 1):
            phi = 2 * math.pi * i / nu
            p = (math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta))
            verts.append((p, (i / nu, j / nv)))
    idx = lambda i, j: j * (nu + 1) + i
    faces = []
    for j in range(nv):
        for i in range(nu):
            a, b, c, d = idx(i, j), idx(i, j + 1), idx(i + 1, j + 1), idx(i + 1, j)
            if j == 0:
                faces.append([a, b, c])
            elif j == nv - 1:
                faces.append([a, b, d])
            else:
                faces.append([a, b, c, d])
    return verts, faces


def wave(nx=9, ny=7):
    """A height field over [-1, 1]^2 as triangles, with analytic normals."""
    verts = []
    for j in range(ny):
        for i in range(nx):
            x, y = -1 + 2 * i / (nx - 1), -1 + 2 * j / (ny - 1)
            z = 0.25 * math.sin(2.1 * x + 0.7) * math.cos(1.3 * y)
            dzdx = 0.25 * 2.1 * math.cos(2.1 * x + 0.7) * math.cos(1.3 * y)
            dzdy = -0.25 * 1.3 * math.sin(2.1 * x + 0.7) * math.sin(1.3 * y)
            n = (-dzdx, -dzdy, 1.0)
            ln = math.sqrt(sum(c * c for c in n))
            verts.append(((x, y, z), (i / (nx - 1), j / (ny - 1)), tuple(c / ln for c in n)))
    faces = []
    for j in range(ny - 1):
        for i in range(nx - 1):
            a, b = j * nx + i, j * nx + i + 1
            c, d = (j + 1) * nx + i + 1, (j + 1) * nx + i
            # Alternate the diagonal so the tangents differ between neighbours.
            if (i + j) % 2 == 0:
                faces += [[a, b, c], [a, c, d]]
            else:
                faces += [[a, b, d], [b, c, d]]
    return verts, faces


def fmt(x):
    return "%.9g" % x


def write_obj(path, verts, faces, normals):
    with open(path, "w") as f:
        f.write("# written by tools/make_shape_meshes.py\n")
        for p, _ in verts:
            f.write("v %s\n" % " ".join(fmt(c) for c in p))
        for _, uv in verts:
            f.write("vt %s\n" % " ".join(fmt(c) for c in uv))
        if normals:
            for p, _ in verts:
                f.write("vn %s\n" % " ".join(fmt(c) for c in p))
        for face in faces:
            if normals:
                f.write("f %s\n" % " ".join("%d/%d/%d" % (k + 1, k + 1, k + 1) for k in face))
            else:
                f.write("f %s\n" % " ".join("%d/%d" % (k + 1, k + 1) for k in face))


def write_ply_ascii(path, verts, faces):
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\ncomment written by tools/make_shape_meshes.py\n")
        f.write("element vertex %d\n" % len(verts))
        for name in "x y z u v".split():
            f.write("property float %s\n" % name)
        f.write("element face %d\nproperty list uchar int vertex_indices\nend_header\n" % len(faces))
        for p, uv, _ in verts:
            f.write(" ".join(fmt(c) for c in p + uv) + "\n")
        for face in faces:
            f.write("%d %s\n" % (len(face), " ".join(str(k) for k in face)))


def write_ply_binary(path, verts, faces):
    header = (
        "ply\nformat binary_little_endian 1.0\ncomment written by tools/make_shape_meshes.py\n"
        "element vertex %d\nproperty double x\nproperty double y\nproperty double z\n"
        "property float nx\nproperty float ny\nproperty float nz\nproperty float s\nproperty float t\n"
        "element face %d\nproperty list uchar int vertex_indices\nend_header\n"
    ) % (len(verts), len(faces))
    with open(path, "wb") as f:
        f.write(header.encode())
        for p, uv, n in verts:
            f.write(struct.pack("<3d3f2f", *p, *n, *uv))
        for face in faces:
            f.write(struct.pack("<B%di" % len(face), len(face), *face))


def serialized_mesh(name, positions, normals, uvs, triangles, double):
    flags = (0x2000 if double else 0x1000) | (0x1 if normals else 0) | (0x2 if uvs else 0)
    real = "d" if double else "f"
    raw = struct.pack("<I", flags) + name.encode() + b"\0"
    raw += struct.pack("<QQ", len(positions), len(triangles))
    for arr in (positions, normals, uvs):
        for v in arr or []:
            raw += struct.pack("<%d%s" % (len(v), real), *v)
    for t in triangles:
        raw += struct.pack("<3I", *t)
    return struct.pack("<HH", 0x041C, 4) + zlib.compress(raw, 9)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "scenes", "shapes", "meshes"))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    out = lambda name: os.path.join(args.out, name)

    sphere_v, sphere_f = uv_sphere()
    write_obj(out("uvsphere.obj"), sphere_v, sphere_f, normals=True)
    write_obj(out("uvsphere_nonormals.obj"), sphere_v, sphere_f, normals=False)
    wave_v, wave_f = wave()
    write_ply_ascii(out("wave.ply"), wave_v, wave_f)
    write_ply_binary(out("wave_binary.ply"), wave_v, wave_f)

    # The sphere fan-triangulated as the OBJ loaders do, for the serialized file.
    sphere_tris = [[f[0], f[k], f[k + 1]] for f in sphere_f for k in range(1, len(f) - 1)]
    a = serialized_mesh("wave", [p for p, _, _ in wave_v], [n for _, _, n in wave_v],
                        [uv for _, uv, _ in wave_v], wave_f, double=False)
    b = serialized_mesh("sphere", [p for p, _ in sphere_v], None, None, sphere_tris, double=True)
    with open(out("shapes.serialized"), "wb") as f:
        f.write(a + b + struct.pack("<QQI", 0, len(a), 2))
    print("wrote", ", ".join(sorted(os.listdir(args.out))), "in", os.path.normpath(args.out))


if __name__ == "__main__":
    main()
