"""Triangle meshes built in Python, as Mitsuba 3's ``mi.Mesh`` (docs/python.md).

    mesh = wt.Mesh("grid", vertex_count=4, face_count=2, has_vertex_normals=True,
                   props={"bsdf": {"type": "diffuse", "reflectance":
                       {"type": "mesh_attribute", "name": "vertex_color"}}})
    params = wt.traverse(mesh)
    params["vertex_positions"] = positions      # (4, 3) or flat, float
    params["faces"] = faces                     # (2, 3) or flat, integers
    params.update()
    mesh.add_attribute("vertex_color", 3, colors)
    scene = wt.load_dict({"type": "scene", "grid": mesh, ...})

``load_dict`` hands the buffers to the Rust loader in memory (no file is written);
there the mesh is a shape as a PLY file's would be (``to_world``, ``face_normals``,
``flip_normals``, its BSDF and area emitter from ``props``), except that a mesh
without vertex normals is flat-shaded, as Mitsuba's ``mi.Mesh`` is.
"""

import numpy as np

# Per buffer: (values per vertex or face, dtype, "vertex" or "face").
_BUFFERS = {
    "vertex_positions": (3, np.float32, "vertex"),
    "vertex_normals": (3, np.float32, "vertex"),
    "vertex_texcoords": (2, np.float32, "vertex"),
    "faces": (3, np.uint32, "face"),
}


class MeshError(ValueError):
    """A buffer or attribute a mesh cannot take; the message names the mesh."""


class Mesh:
    """A triangle mesh with `vertex_count` vertices and `face_count` triangles, its
    buffers zero until set (Mitsuba 3's ``mi.Mesh(name, vertex_count, face_count,
    props, has_vertex_normals, has_vertex_texcoords)``).

    props: the shape's parameters as in a scene dictionary: ``bsdf``, ``emitter``,
    ``to_world``, ``face_normals``, ``flip_normals``, ``interior``, ``exterior``.
    The buffers may also be given as arrays (``vertex_positions``, ``faces``,
    ``vertex_normals``, ``vertex_texcoords``); the counts are then taken from them.
    """

    def __init__(
        self,
        name,
        vertex_count=None,
        face_count=None,
        props=None,
        has_vertex_normals=False,
        has_vertex_texcoords=False,
        *,
        vertex_positions=None,
        faces=None,
        vertex_normals=None,
        vertex_texcoords=None,
    ):
        if not isinstance(name, str) or not name:
            raise MeshError(f"Mesh: a mesh's name is a non-empty string, got {name!r}")
        self.name = name
        if vertex_count is None and vertex_positions is not None:
            vertex_count = np.asarray(vertex_positions).size // 3
        if face_count is None and faces is not None:
            face_count = np.asarray(faces).size // 3
        self.vertex_count = self._count(vertex_count, "vertex_count")
        self.face_count = self._count(face_count, "face_count")
        if props is not None and not isinstance(props, dict):
            raise MeshError(f"mesh '{name}': props is a dict of shape parameters, got {type(props).__name__}")
        self.props = dict(props or {})
        has_vertex_normals = has_vertex_normals or vertex_normals is not None
        has_vertex_texcoords = has_vertex_texcoords or vertex_texcoords is not None
        self._buffers = {
            "vertex_positions": np.zeros((self.vertex_count, 3), np.float32),
            "faces": np.zeros((self.face_count, 3), np.uint32),
        }
        if has_vertex_normals:
            self._buffers["vertex_normals"] = np.zeros((self.vertex_count, 3), np.float32)
        if has_vertex_texcoords:
            self._buffers["vertex_texcoords"] = np.zeros((self.vertex_count, 2), np.float32)
        self._attributes = {}  # name -> (vertex_count or face_count, size) array
        for key, value in (
            ("vertex_positions", vertex_positions),
            ("faces", faces),
            ("vertex_normals", vertex_normals),
            ("vertex_texcoords", vertex_texcoords),
        ):
            if value is not None:
                self[key] = value

    def _count(self, n, what):
        if n is None or isinstance(n, bool) or int(n) != n or n < 0:
            raise MeshError(f"mesh '{self.name}': {what} must be a non-negative integer, got {n!r}")
        return int(n)

    def _error(self, message):
        return MeshError(f"mesh '{self.name}': {message}")

    # The buffers, as named by Mitsuba's mi.traverse(mesh).

    def keys(self):
        """The buffers' names: ``vertex_positions``, ``faces``, ``vertex_normals`` and
        ``vertex_texcoords`` where the mesh has them, then the attributes'."""
        return list(self._buffers) + list(self._attributes)

    def __contains__(self, key):
        return key in self._buffers or key in self._attributes

    def __getitem__(self, key):
        """A buffer as a read-only array of shape (count, values per element)."""
        if key in self._buffers:
            a = self._buffers[key]
        elif key in self._attributes:
            a = self._attributes[key]
        else:
            raise KeyError(self._unknown(key))
        v = a.view()
        v.flags.writeable = False
        return v

    def __setitem__(self, key, value):
        """Sets a buffer (``vertex_positions``, ``faces``, ...) or an attribute's values
        from an array of shape (count, values per element) or a flat one."""
        if key in self._buffers:
            width, dtype, element = _BUFFERS[key]
        elif key in self._attributes:
            width, dtype, element = self._attributes[key].shape[1], np.float32, key.split("_")[0]
        else:
            raise KeyError(self._unknown(key))
        self._set(key, value, width, dtype, element)

    def _unknown(self, key):
        if key in _BUFFERS:
            flag = "has_vertex_normals" if key == "vertex_normals" else "has_vertex_texcoords"
            return f"mesh '{self.name}' has no {key} (construct it with {flag}=True)"
        return f"mesh '{self.name}' has no buffer {key!r} (it has {', '.join(self.keys())})"

    def _set(self, key, value, width, dtype, element):
        count = self.vertex_count if element == "vertex" else self.face_count
        what = "vertices" if element == "vertex" else "faces"
        try:
            a = np.asarray(value)
        except (TypeError, ValueError) as e:
            raise self._error(f"{key}: not an array of numbers ({e})") from None
        if a.dtype == object or not (np.issubdtype(a.dtype, np.number) or a.dtype == bool):
            raise self._error(f"{key}: not an array of numbers (dtype {a.dtype})")
        if not (a.shape == (count, width) or a.shape == (count * width,) or (width == 1 and a.shape == (count,))):
            raise self._error(
                f"{key} has shape {a.shape}; {count} {what} need ({count}, {width}) "
                f"or ({count * width},)"
            )
        if dtype == np.uint32:
            if not np.issubdtype(a.dtype, np.integer):
                if not np.all(np.isfinite(a)) or np.any(a != np.round(a)):
                    raise self._error(f"{key}: vertex indices must be integers")
            a = a.reshape(count, width)
            if a.size and (a.min() < 0 or a.max() >= self.vertex_count):
                bad = np.argwhere((a < 0) | (a >= self.vertex_count))[0][0]
                raise self._error(
                    f"face {bad} {a[bad].astype(np.int64).tolist()} names a vertex outside "
                    f"0..{self.vertex_count - 1}"
                )
            self._store(key, a.astype(np.uint32))
            return
        a = a.astype(np.float64).reshape(count, width)
        bad = ~np.isfinite(a)
        if bad.any():
            i = np.argwhere(bad)[0][0]
            raise self._error(f"{key}: {'vertex' if element == 'vertex' else 'face'} {i} is not finite ({a[i].tolist()})")
        self._store(key, a.astype(np.float32))

    def _store(self, key, a):
        if key in self._buffers:
            self._buffers[key] = np.ascontiguousarray(a)
        else:
            self._attributes[key] = np.ascontiguousarray(a)

    def add_attribute(self, name, size, values):
        """Adds the attribute `name` (``vertex_...``: `size` values per vertex,
        interpolated; ``face_...``: per face) with `values` (Mitsuba's
        ``Mesh.add_attribute``). A ``mesh_attribute`` texture reads attributes of 1
        or 3 values."""
        if not isinstance(name, str) or not (name.startswith("vertex_") or name.startswith("face_")):
            raise self._error(
                f"attribute name {name!r} must start with 'vertex_' or 'face_'"
            )
        if name in self:
            raise self._error(f"attribute {name!r} already exists")
        if isinstance(size, bool) or int(size) != size or size < 1:
            raise self._error(f"attribute {name!r}: size must be a positive integer, got {size!r}")
        element = "vertex" if name.startswith("vertex_") else "face"
        count = self.vertex_count if element == "vertex" else self.face_count
        self._attributes[name] = np.zeros((count, int(size)), np.float32)
        try:
            self._set(name, values, int(size), np.float32, element)
        except MeshError:
            del self._attributes[name]
            raise

    def has_vertex_normals(self):
        return "vertex_normals" in self._buffers

    def has_vertex_texcoords(self):
        return "vertex_texcoords" in self._buffers

    def _parts(self):
        """The mesh as the native loader takes it (name, buffers as bytes, attributes)."""
        empty = b""
        return (
            self.name,
            self._buffers["vertex_positions"].tobytes(),
            self._buffers["faces"].tobytes(),
            self._buffers["vertex_normals"].tobytes() if "vertex_normals" in self._buffers else empty,
            self._buffers["vertex_texcoords"].tobytes() if "vertex_texcoords" in self._buffers else empty,
            [(n, a.shape[1], a.tobytes()) for n, a in self._attributes.items()],
        )

    def __repr__(self):
        extra = "".join(f", {k}" for k in self.keys()[2:])
        return f"<wavetrace.Mesh {self.name!r}: {self.vertex_count} vertices, {self.face_count} faces{extra}>"


class MeshParameters:
    """``traverse(mesh)``: the mesh's buffers by Mitsuba's names, flat as Mitsuba's
    ``mi.traverse`` gives them; setting one takes a flat or (count, n) array.
    ``update()`` is there for Mitsuba's code (buffers are checked when set)."""

    def __init__(self, mesh):
        self._mesh = mesh

    def keys(self):
        return self._mesh.keys()

    def __iter__(self):
        return iter(self.keys())

    def __len__(self):
        return len(self.keys())

    def __contains__(self, key):
        return key in self._mesh

    def __getitem__(self, key):
        return self._mesh[key].reshape(-1)

    def __setitem__(self, key, value):
        self._mesh[key] = value

    def items(self):
        return [(k, self[k]) for k in self.keys()]

    def update(self):
        return []

    def __repr__(self):
        rows = "".join(f"\n  {k}: {self[k].size} values" for k in self.keys())
        return f"MeshParameters of {self._mesh.name!r}[{rows}\n]"


def traverse(obj):
    """The settable buffers of a ``Mesh`` (Mitsuba's ``mi.traverse(mesh)``)."""
    if not isinstance(obj, Mesh):
        raise TypeError(f"traverse() takes a wavetrace.Mesh, got {type(obj).__name__}")
    return MeshParameters(obj)
