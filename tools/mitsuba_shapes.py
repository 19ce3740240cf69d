#!/usr/bin/env python3
"""Record what Mitsuba 3 computes where rays hit each of its shapes, for
tests/shape_hits_vs_mitsuba.rs: wavetrace must find the same points, normals, uvs and tangent
frames on the GPU.

    python3 tools/mitsuba_shapes.py [--out tests/data/shape_hits.json] [--rays 24]

Each case is a Mitsuba `<shape>` snippet (the meshes are scenes/shapes/meshes/, made
by tools/make_shape_meshes.py): built-in shapes plain, transformed (rotation,
non-uniform scale, shear), mirrored and with flip_normals; OBJ, PLY and serialized
files with and without normals, face_normals and flip_tex_coords. For each, rays from
random points around the shape aimed at random points of its bounding box; for every
ray Mitsuba hits, the JSON keeps the ray and Mitsuba's surface interaction: t, p,
n (geometric normal), the shading frame sh_frame.n and sh_frame.s, uv and dp_du.
Rays are made with a fixed seed, so running it again gives the same file (for the
same Mitsuba version, which the file records).
"""

import argparse
import json
import os
import random

import mitsuba as mi

mi.set_variant("scalar_rgb")

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), ".."))
MESHES = os.path.join(ROOT, "scenes", "shapes", "meshes")


def tf(body):
    return '<transform name="to_world">%s</transform>' % body


# Transforms used on several shapes. Rotation axes are unit vectors: Mitsuba 3.9
# rotates about a non-unit axis by Rodrigues' formula unnormalized (so the shape is
# scaled and sheared) and turns normals by that same matrix rather than its inverse
# transpose; the "nonunit" case checks wavetrace's positions and uvs there.
AFFINE = tf('<scale value="1.5, 0.7, 1.2"/><rotate x="0.4364358" y="0.8728716" z="0.2182179" angle="37"/>'
            '<translate value="0.3, -0.2, 0.5"/>')
SIMILAR = tf('<scale value="1.3"/><rotate x="0.6917145" y="-0.6917145" z="0.2075144" angle="61"/>'
             '<translate value="-0.4, 0.1, 0.2"/>')
MIRROR = tf('<scale value="-1, 1, 1"/><rotate x="0.2873479" y="0.9578263" z="0" angle="25"/>')
NONUNIT = tf('<rotate x="1" y="0.5" z="0.2" angle="30"/>')
SHEAR = tf('<matrix value="1 0.4 0 0.1  0 1 0 0  0.2 0 1 0  0 0 0 1"/>')


def mesh(kind, filename, extra=""):
    return '<shape type="%s"><string name="filename" value="meshes/%s"/>%s</shape>' % (
        kind, filename, extra)


def boolean(name, value=True):
    return '<boolean name="%s" value="%s"/>' % (name, "true" if value else "false")


CASES = {
    "cube": '<shape type="cube"/>',
    "cube_affine": '<shape type="cube">%s</shape>' % AFFINE,
    "cube_shear": '<shape type="cube">%s</shape>' % SHEAR,
    "cube_mirror": '<shape type="cube">%s</shape>' % MIRROR,
    "cube_flip": '<shape type="cube">%s</shape>' % boolean("flip_normals"),
    "cube_nonunit_axis": '<shape type="cube">%s</shape>' % NONUNIT,
    "rectangle": '<shape type="rectangle"/>',
    "rectangle_affine": '<shape type="rectangle">%s</shape>' % AFFINE,
    "rectangle_mirror": '<shape type="rectangle">%s</shape>' % MIRROR,
    "rectangle_flip": '<shape type="rectangle">%s</shape>' % boolean("flip_normals"),
    "disk": '<shape type="disk"/>',
    "disk_affine": '<shape type="disk">%s</shape>' % AFFINE,
    "disk_mirror": '<shape type="disk">%s</shape>' % MIRROR,
    "disk_flip": '<shape type="disk">%s</shape>' % boolean("flip_normals"),
    "sphere": '<shape type="sphere"><point name="center" value="0.2, -0.1, 0.3"/>'
              '<float name="radius" value="0.8"/></shape>',
    "sphere_rotated": '<shape type="sphere">%s</shape>' % SIMILAR,
    "sphere_mirror": '<shape type="sphere">%s</shape>' % MIRROR,
    "sphere_flip": '<shape type="sphere">%s</shape>' % boolean("flip_normals"),
    "cylinder": '<shape type="cylinder"/>',
    "cylinder_params": '<shape type="cylinder"><point name="p0" value="0.1, -0.3, -0.5"/>'
                       '<point name="p1" value="0.4, 0.6, 0.7"/><float name="radius" value="0.4"/></shape>',
    "cylinder_rotated": '<shape type="cylinder">%s</shape>' % SIMILAR,
    "cylinder_mirror": '<shape type="cylinder">%s</shape>' % MIRROR,
    "cylinder_flip": '<shape type="cylinder">%s</shape>' % boolean("flip_normals"),
    "obj": mesh("obj", "uvsphere.obj"),
    "obj_affine": mesh("obj", "uvsphere.obj", AFFINE),
    "obj_mirror": mesh("obj", "uvsphere.obj", MIRROR),
    "obj_computed_normals": mesh("obj", "uvsphere_nonormals.obj"),
    "obj_computed_normals_mirror": mesh("obj", "uvsphere_nonormals.obj", MIRROR),
    "obj_face_normals": mesh("obj", "uvsphere.obj", boolean("face_normals")),
    "obj_no_flip_tex": mesh("obj", "uvsphere.obj", boolean("flip_tex_coords", False)),
    "obj_flip": mesh("obj", "uvsphere.obj", boolean("flip_normals")),
    "ply_ascii": mesh("ply", "wave.ply"),
    "ply_binary": mesh("ply", "wave_binary.ply", AFFINE),
    "ply_flip_tex": mesh("ply", "wave.ply", boolean("flip_tex_coords")),
    "ply_face_normals": mesh("ply", "wave_binary.ply", boolean("face_normals")),
    "serialized": mesh("serialized", "shapes.serialized"),
    "serialized_second": mesh("serialized", "shapes.serialized",
                              '<integer name="shape_index" value="1"/>'),
    "serialized_face_normals": mesh("serialized", "shapes.serialized", boolean("face_normals")),
}


def vec(v):
    return [float("%.7g" % x) for x in v]


def hits(xml, count, rng):
    mi.Thread.thread().file_resolver().prepend(os.path.join(ROOT, "scenes", "shapes"))
    scene = mi.load_string('<scene version="3.0.0">%s</scene>' % xml)
    bbox = scene.bbox()
    lo, hi = bbox.min, bbox.max
    center = (lo + hi) * 0.5
    radius = 2.0 * dr_norm(hi - lo) + 1.0
    out = []
    tries = 0
    while len(out) < count and tries < 100 * count:
        tries += 1
        # Origin on a sphere around the box, target inside the box.
        z = rng.uniform(-1, 1)
        phi = rng.uniform(0, 2 * 3.141592653589793)
        s = (1 - z * z) ** 0.5
        o = mi.ScalarPoint3f(center[0] + radius * s * __import__("math").cos(phi),
                             center[1] + radius * s * __import__("math").sin(phi),
                             center[2] + radius * z)
        target = mi.ScalarPoint3f(*[rng.uniform(lo[k], hi[k]) for k in range(3)])
        d = target - o
        d = d / dr_norm(d)
        si = scene.ray_intersect(mi.Ray3f(o, d))
        if not si.is_valid():
            continue
        rec = {
            "o": vec(o), "d": vec(d), "t": float("%.7g" % si.t),
            "p": vec(si.p), "n": vec(si.n), "sh_n": vec(si.sh_frame.n),
            "sh_s": vec(si.sh_frame.s), "uv": vec(si.uv), "dp_du": vec(si.dp_du),
        }
        # Mitsuba 3.9's sphere takes acos of a local z that rounding can push past 1
        # (v = NaN); such a hit says nothing about conventions.
        if any(x != x for v in rec.values() for x in (v if isinstance(v, list) else [v])):
            print("  skipped a hit with NaN in Mitsuba's interaction:", rec)
            continue
        out.append(rec)
    return out


def dr_norm(v):
    return float((v[0] ** 2 + v[1] ** 2 + v[2] ** 2) ** 0.5)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(ROOT, "tests", "data", "shape_hits.json"))
    ap.add_argument("--rays", type=int, default=24)
    args = ap.parse_args()
    rng = random.Random(17)
    cases = []
    for name, xml in CASES.items():
        h = hits(xml, args.rays, rng)
        print("%-28s %d hits" % (name, len(h)))
        cases.append({"name": name, "shape": xml, "hits": h})
    os.makedirs(os.path.dirname(args.out), exist_ok=True)
    with open(args.out, "w") as f:
        json.dump({"mitsuba": mi.__version__, "variant": "scalar_rgb",
                   "command": "python3 tools/mitsuba_shapes.py", "cases": cases}, f,
                  separators=(",", ":"))
        f.write("\n")
    print("wrote", os.path.relpath(args.out, ROOT))


if __name__ == "__main__":
    main()
