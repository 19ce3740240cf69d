"""wavetrace.Mesh (Mitsuba 3's mi.Mesh): a mesh built in Python with a vertex and a
face attribute renders as the same mesh written as a PLY file and loaded from XML,
and as Mitsuba 3.9.1 renders it built with mi.Mesh + add_attribute; bad buffers are
errors naming the mesh. Small renders (lavapipe in CI)."""

import struct

import numpy as np
import pytest

import wavetrace as wt

RES, SPP = 24, 64
N = 5  # vertices per side of the grid


def grid():
    """A bumpy 5x5 grid of 32 triangles with normals (tilted three times as far as
    the surface's, so that they matter), texcoords, a vertex color and a face
    weight."""
    xs = np.linspace(-1.0, 1.0, N)
    x, y = np.meshgrid(xs, xs)
    z = 0.2 * np.sin(2 * x) * np.cos(2 * y)
    positions = np.stack([x, y, z], -1).reshape(-1, 3).astype(np.float32)
    normals = np.stack(
        [-1.2 * np.cos(2 * x) * np.cos(2 * y), 1.2 * np.sin(2 * x) * np.sin(2 * y), np.ones_like(x)], -1
    ).reshape(-1, 3)
    normals = (normals / np.linalg.norm(normals, axis=1)[:, None]).astype(np.float32)
    texcoords = ((positions[:, :2] + 1) / 2).astype(np.float32)
    faces = []
    for j in range(N - 1):
        for i in range(N - 1):
            a = j * N + i
            faces += [[a, a + 1, a + N + 1], [a, a + N + 1, a + N]]
    faces = np.array(faces, dtype=np.uint32)
    colors = np.stack([(x + 1) / 2, (y + 1) / 2, 0.2 + 0.6 * (z > 0)], -1).reshape(-1, 3)
    weights = np.linspace(0.0, 1.0, len(faces))
    return positions, faces, normals, texcoords, colors.astype(np.float32), weights.astype(np.float32)


BSDF = {
    "type": "blendbsdf",
    "weight": {"type": "mesh_attribute", "name": "face_weight"},
    "a": {"type": "diffuse", "reflectance": {"type": "mesh_attribute", "name": "vertex_color"}},
    # Not a delta BSDF: with a delta child wavetrace's blend differs from Mitsuba
    # 3.9.1's on purpose (src/scene/bsdf/composite.rs; 2.5 % in red with Au here).
    "b": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.9, 0.2, 0.1]}},
}


def scene_dict(shape):
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 3},
        "sensor": {
            "type": "perspective",
            "fov": 40.0,
            "to_world": wt.look_at([0, -1, 4], [0, 0, 0], [0, 1, 0]),
            "sampler": {"type": "independent", "sample_count": SPP},
            "film": {"type": "hdrfilm", "width": RES, "height": RES,
                     "rfilter": {"type": "box"}, "component_format": "float32"},
        },
        "env": {"type": "constant", "radiance": {"type": "rgb", "value": [0.5, 0.5, 0.5]}},
        "light": {"type": "point", "position": [1.0, -1.0, 3.0],
                  "intensity": {"type": "rgb", "value": [4.0, 4.0, 4.0]}},
        "grid": shape,
    }


def python_mesh(normals=True, **props):
    p, f, n, t, c, w = grid()
    mesh = wt.Mesh("grid", len(p), len(f), props={"bsdf": BSDF, **props},
                   has_vertex_normals=normals, has_vertex_texcoords=True)
    params = wt.traverse(mesh)
    params["vertex_positions"] = p.ravel()
    params["faces"] = f.ravel()
    if normals:
        params["vertex_normals"] = n
    params["vertex_texcoords"] = t
    params.update()
    mesh.add_attribute("vertex_color", 3, c.ravel())
    mesh.add_attribute("face_weight", 1, w)
    return mesh


def write_ply(path):
    """The grid as a binary PLY file: vertex_color from r, g, b and face_weight from
    weight_0 (as Mitsuba's PLY reader names them)."""
    p, f, n, t, c, w = grid()
    head = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(p)}\n"
        + "".join(f"property float {k}\n" for k in ("x", "y", "z", "nx", "ny", "nz", "u", "v", "r", "g", "b"))
        + f"element face {len(f)}\nproperty list uchar int vertex_indices\nproperty float weight_0\n"
        "end_header\n"
    )
    body = b"".join(struct.pack("<11f", *p[i], *n[i], *t[i], *c[i]) for i in range(len(p)))
    body += b"".join(struct.pack("<B3if", 3, *map(int, f[k]), w[k]) for k in range(len(f)))
    path.write_bytes(head.encode() + body)


def render(scene, spp=SPP):
    return np.asarray(wt.render(scene, spp=spp, seed=3))[:, :, :3]


TO_WORLD = np.array([[0.8, -0.3, 0.0, 0.1], [0.3, 0.8, 0.0, -0.2], [0.0, 0.0, 1.2, 0.3], [0, 0, 0, 1]])


# An area light whose radiance is the face attribute (Mitsuba 3.9.1's scalar_rgb
# crashes rendering an mi.Mesh given an area emitter in its props, so this is
# checked against the PLY file only).
GLOW = {"type": "area", "radiance": {"type": "mesh_attribute", "name": "face_weight"}}


@pytest.mark.parametrize(
    "extra", [{}, {"to_world": TO_WORLD}, {"emitter": GLOW}], ids=["plain", "to_world", "emitter"]
)
def test_mesh_renders_as_its_ply_file(tmp_path, extra):
    image = render(wt.load_dict(scene_dict(python_mesh(**extra))))
    ply = tmp_path / "grid.ply"
    write_ply(ply)
    from_file = render(wt.load_dict(scene_dict({"type": "ply", "filename": str(ply), "bsdf": BSDF, **extra})))
    assert image.mean() > 0.05
    # Bit for bit: the same float32 buffers reach the same mesh code.
    np.testing.assert_array_equal(image, from_file)
    # The face weight changes the image: the attributes are read, not defaults.
    mesh = python_mesh(**extra)
    mesh["face_weight"] = np.zeros(mesh.face_count)
    other = render(wt.load_dict(scene_dict(mesh)))
    assert np.abs(other - image).mean() > 0.01


def mitsuba_images(spp, normals, seeds):
    """The same mesh built with mi.Mesh + add_attribute, rendered by Mitsuba 3 once
    per seed."""
    mi = pytest.importorskip("mitsuba")
    mi.set_variant("scalar_rgb")
    p, f, n, t, c, w = grid()
    props = mi.Properties()
    props["bsdf"] = mi.load_dict(BSDF)
    mesh = mi.Mesh("grid", len(p), len(f), props, normals, True)
    params = mi.traverse(mesh)
    floats, ints = type(params["vertex_positions"]), type(params["faces"])
    params["vertex_positions"] = floats(p.ravel())
    params["faces"] = ints(f.ravel())
    if normals:
        params["vertex_normals"] = floats(n.ravel())
    params["vertex_texcoords"] = floats(t.ravel())
    params.update()
    mesh.add_attribute("vertex_color", 3, c.ravel().tolist())
    mesh.add_attribute("face_weight", 1, w.tolist())
    d = scene_dict(mesh)
    d["sensor"]["to_world"] = mi.ScalarTransform4f(wt.look_at([0, -1, 4], [0, 0, 0], [0, 1, 0]))
    d["sensor"]["sampler"]["sample_count"] = spp
    scene = mi.load_dict(d)
    return [np.asarray(mi.render(scene, seed=1000 + k))[:, :, :3] for k in range(seeds)]


def mean_and_variance(images):
    """Per pixel: the mean of independent renders and the variance of that mean."""
    a = np.stack(images).astype(np.float64)
    return a.mean(0), a.var(0, ddof=1) / len(images)


def block_z(a, b, block=4):
    """The largest |z| of a block's mean difference: `a`, `b` are (mean, variance of
    the mean) per pixel; a block sums both over its pixels (per channel)."""

    def blocks(x):
        return x.reshape(RES // block, block, RES // block, block, 3).sum(axis=(1, 3))

    d = blocks(a[0] - b[0])
    var = blocks(a[1] + b[1])
    return float(np.abs(d / np.sqrt(np.maximum(var, 1e-12))).max())


SEEDS, SEED_SPP = 8, 128


@pytest.mark.parametrize("normals", [True, False], ids=["vertex_normals", "flat"])
def test_mesh_renders_as_mitsuba(normals):
    ref = mean_and_variance(mitsuba_images(SEED_SPP, normals, SEEDS))
    scene = wt.load_dict(scene_dict(python_mesh(normals)))
    ours = mean_and_variance(
        [np.asarray(wt.render(scene, spp=SEED_SPP, seed=k))[:, :, :3] for k in range(SEEDS)]
    )
    # Whole-image means within half a percent, 4x4 blocks within noise; Mitsuba's
    # image at 0.95 fails both, and so does the other shading (flat for smooth).
    assert np.abs(ours[0].mean((0, 1)) / ref[0].mean((0, 1)) - 1).max() < 0.005
    z = block_z(ours, ref)
    assert z < 5.0, z
    scaled = (0.95 * ref[0], 0.95**2 * ref[1])
    assert np.abs(ours[0].mean((0, 1)) / scaled[0].mean((0, 1)) - 1).max() > 0.03
    assert block_z(ours, scaled) > 5.0
    other = mean_and_variance(mitsuba_images(SEED_SPP, not normals, 2))
    assert block_z(ours, (other[0], ref[1])) > 5.0


def test_bad_buffers_name_the_mesh():
    p, f, n, t, c, w = grid()
    mesh = wt.Mesh("grid", len(p), len(f))
    with pytest.raises(wt.MeshError, match=r"mesh 'grid': vertex_positions has shape \(24, 3\); 25 vertices need \(25, 3\)"):
        mesh["vertex_positions"] = p[:24]
    bad = p.copy()
    bad[7, 1] = np.nan
    with pytest.raises(wt.MeshError, match=r"mesh 'grid': vertex_positions: vertex 7 is not finite"):
        mesh["vertex_positions"] = bad
    bad = f.copy()
    bad[3, 2] = 25
    with pytest.raises(wt.MeshError, match=r"mesh 'grid': face 3 \[.*25\] names a vertex outside 0..24"):
        wt.traverse(mesh)["faces"] = bad
    with pytest.raises(wt.MeshError, match=r"mesh 'grid': attribute name 'color' must start with 'vertex_' or 'face_'"):
        mesh.add_attribute("color", 3, c)
    with pytest.raises(wt.MeshError, match=r"mesh 'grid': face_weight has shape \(25,\); 32 faces need \(32, 1\)"):
        mesh.add_attribute("face_weight", 1, c[:, 0])
    assert "face_weight" not in mesh
    with pytest.raises(KeyError, match="construct it with has_vertex_normals=True"):
        mesh["vertex_normals"] = n
    mesh["vertex_positions"] = p
    mesh["faces"] = f
    mesh.add_attribute("vertex_color", 3, c)
    with pytest.raises(wt.MeshError, match="attribute 'vertex_color' already exists"):
        mesh.add_attribute("vertex_color", 3, c)
    # A texture reading an attribute the mesh lacks: the loader's error names the mesh.
    mesh.props["bsdf"] = {"type": "diffuse",
                          "reflectance": {"type": "mesh_attribute", "name": "vertex_missing"}}
    with pytest.raises(ValueError, match=r"grid: mesh has no attribute 'vertex_missing' .*it has vertex_color"):
        wt.load_dict(scene_dict(mesh))
    # Read by a blendbsdf's weight: checked as well.
    mesh.props["bsdf"] = BSDF
    with pytest.raises(ValueError, match=r"grid: mesh has no attribute 'face_weight' .*it has vertex_color"):
        wt.load_dict(scene_dict(mesh))
    mesh.props["bsdf"] = {"type": "diffuse",
                          "reflectance": {"type": "mesh_attribute", "name": "color"}}
    with pytest.raises(ValueError, match=r"scene\['grid'\]\['bsdf'\]\['reflectance'\].*must start with 'vertex_' or 'face_'"):
        wt.load_dict(scene_dict(mesh))


def test_mesh_from_arrays_is_flat_without_normals():
    p, f, n, t, c, w = grid()
    mesh = wt.Mesh("flat", vertex_positions=p, faces=f,
                   props={"bsdf": {"type": "diffuse"}, "to_world": np.diag([1.0, 1.0, 1.0, 1.0])})
    assert (mesh.vertex_count, mesh.face_count) == (25, 32)
    assert mesh.keys() == ["vertex_positions", "faces"]
    np.testing.assert_array_equal(wt.traverse(mesh)["faces"], f.ravel())
    scene = wt.load_dict(scene_dict(mesh))
    assert scene.info()["triangles"] == 32


def test_mesh_props_errors_name_the_key():
    mesh = python_mesh(colour=[1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"load_dict: scene\['grid'\]\['colour'\].*colour"):
        wt.load_dict(scene_dict(mesh))
    with pytest.raises(wt.MeshError, match="props is a dict"):
        wt.Mesh("grid", 3, 1, props=[("bsdf", BSDF)])
    with pytest.raises(wt.MeshError, match="vertex_count must be a non-negative integer"):
        wt.Mesh("grid", -1, 1)
