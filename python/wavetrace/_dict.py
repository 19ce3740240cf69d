"""Mitsuba 3's scene dictionaries as the Mitsuba XML wavetrace's loader reads.

``load_dict`` writes the dictionary out as a scene file, one element per line, and
loads that: the same loader, the same checks and the same image as the file. Every
line remembers the dictionary key it came from, so an error the loader reports at
a line is reported at the key (``scene['light']['emitter']['radiance']``).

What a value becomes (Mitsuba's ``load_dict`` conventions):

- ``{'type': 'scene', ...}``: the root; each other key is an object, its key its ``id``;
- ``{'type': T, ...}``: a nested object of the family that registers ``T``
  (``bsdf``, ``shape``, ``emitter``, ``texture``, ...);
- ``{'type': 'rgb', 'value': [r, g, b] or v}``, ``{'type': 'spectrum', 'value': v or
  [(wavelength, value), ...]}`` or ``{'type': 'spectrum', 'filename': ...}``: colours;
- ``{'type': 'ref', 'id': name}``: a reference to an object of the root;
- a ``wavetrace.Mesh`` at the root: a shape whose buffers the loader gets in memory
  (``<shape type="mesh">`` naming it by index), its ``props`` the shape's parameters;
- ``bool``, ``int``, ``float``, ``str``: ``boolean``, ``integer``, ``float``, ``string``;
- a 4x4 matrix (nested lists, a NumPy array, or anything with a ``matrix``
  attribute such as ``mi.ScalarTransform4f``): a ``transform``;
- three numbers: a ``point`` (a ``vector`` for ``direction``, ``up`` and ``axis``).
"""

import os
from xml.sax.saxutils import quoteattr

import numpy as np

from ._mesh import Mesh

# Families not in the plugin catalogue (wavetrace reads them inside their parents).
_EXTRA_TAGS = {
    "box": "rfilter",
    "tent": "rfilter",
    "gaussian": "rfilter",
    "mitchell": "rfilter",
    "catmullrom": "rfilter",
    "lanczos": "rfilter",
    "isotropic": "phase",
    "hg": "phase",
    "rayleigh": "phase",
    "sggx": "phase",
    "gridvolume": "volume",
    "constvolume": "volume",
}

# Families whose nested objects are named by their key (the parameter they fill).
_NAMED = {"texture", "medium", "volume"}
# Families whose objects at the root may carry an id.
_ROOT_IDS = {"bsdf", "texture", "medium", "shape", "emitter", "sensor", "integrator"}
_VECTORS = {"direction", "up", "axis"}


class DictError(ValueError):
    """A scene dictionary wavetrace cannot read; the message names the key."""


def _path(keys):
    return "scene" + "".join(f"[{k!r}]" for k in keys)


def _matrix(value):
    """The 4x4 matrix `value` holds, or None."""
    m = getattr(value, "matrix", value)
    if isinstance(value, (str, bytes, dict)):
        return None
    try:
        a = np.asarray(m, dtype=np.float64)
    except (TypeError, ValueError):
        return None
    if a.shape == (4, 4):
        return a
    return None


def _numbers(value, n):
    """`value` as n floats (a sequence or array of n numbers), or None."""
    if isinstance(value, (str, bytes, dict, bool)):
        return None
    try:
        a = np.asarray(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        return None
    return a if a.size == n else None


def _fmt(x):
    return repr(float(x))


class _Writer:
    def __init__(self, tags):
        self.tags = tags
        self.lines = []
        self.keys = []  # per line: the key path it came from
        self.meshes = []  # the Mesh objects, in the order of their "provided" index

    def mesh(self, depth, key, mesh, keys):
        """A ``Mesh`` built in Python: a ``mesh`` shape naming it by its index among
        the meshes handed to the loader, with the shape parameters of its props."""
        self.line(depth, f"<shape type=\"mesh\" id={quoteattr(key)}>", keys)
        self.line(depth + 1, f"<integer name=\"provided\" value=\"{len(self.meshes)}\"/>", keys)
        self.meshes.append(mesh)
        for k, v in mesh.props.items():
            if not isinstance(k, str) or k in ("type", "id", "provided"):
                raise DictError(
                    f"load_dict: {_path(keys)}: mesh '{mesh.name}': props key {k!r} is not "
                    "a shape parameter"
                )
            self.value(depth + 1, k, v, keys + [k])
        self.line(depth, "</shape>", keys)

    def line(self, depth, text, keys):
        self.lines.append("    " * depth + text)
        self.keys.append(keys)

    def tag_of(self, type_name, keys):
        tag = self.tags.get(type_name) or _EXTRA_TAGS.get(type_name)
        if tag is None:
            raise DictError(
                f"load_dict: {_path(keys)}: unknown plugin type {type_name!r} "
                "(wavetrace.plugins() lists the known ones)"
            )
        return tag

    def obj(self, depth, key, d, keys, root_level):
        t = d.get("type")
        if not isinstance(t, str):
            raise DictError(f"load_dict: {_path(keys)}: an object needs a 'type' string")
        if t == "ref":
            rid = d.get("id")
            if not isinstance(rid, str):
                raise DictError(f"load_dict: {_path(keys)}: a ref needs an 'id' string")
            extra = set(d) - {"type", "id"}
            if extra:
                raise DictError(
                    f"load_dict: {_path(keys + [sorted(extra)[0]])}: a ref takes only 'id'"
                )
            name = "" if root_level else f" name={quoteattr(key)}"
            self.line(depth, f"<ref id={quoteattr(rid)}{name}/>", keys)
            return
        if t in ("rgb", "spectrum"):
            self.colour(depth, key, d, keys)
            return
        tag = self.tag_of(t, keys)
        attrs = f" type={quoteattr(t)}"
        oid = d.get("id")
        if oid is not None:
            if not isinstance(oid, str):
                raise DictError(f"load_dict: {_path(keys + ['id'])}: an id is a string")
            attrs += f" id={quoteattr(oid)}"
        elif root_level and tag in _ROOT_IDS:
            attrs += f" id={quoteattr(key)}"
        if not root_level and tag in _NAMED:
            attrs += f" name={quoteattr(key)}"
        self.line(depth, f"<{tag}{attrs}>", keys)
        for k, v in d.items():
            if k in ("type", "id"):
                continue
            self.value(depth + 1, k, v, keys + [k])
        self.line(depth, f"</{tag}>", keys)

    def colour(self, depth, key, d, keys):
        t = d["type"]
        extra = set(d) - {"type", "value", "filename"}
        if extra:
            raise DictError(
                f"load_dict: {_path(keys + [sorted(extra)[0]])}: {t!r} takes 'value'"
                + (" or 'filename'" if t == "spectrum" else "")
            )
        name = quoteattr(key)
        if t == "spectrum" and "filename" in d:
            f = d["filename"]
            if not isinstance(f, str):
                raise DictError(f"load_dict: {_path(keys + ['filename'])}: a file name string")
            self.line(depth, f"<spectrum name={name} filename={quoteattr(_abs(f))}/>", keys)
            return
        if "value" not in d:
            raise DictError(f"load_dict: {_path(keys)}: {t!r} needs a 'value'")
        v = d["value"]
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            text = _fmt(v)
        elif t == "rgb" and _numbers(v, 3) is not None:
            text = ", ".join(_fmt(x) for x in _numbers(v, 3))
        elif t == "spectrum" and _pairs(v) is not None:
            text = ", ".join(f"{_fmt(w)}:{_fmt(x)}" for w, x in _pairs(v))
        else:
            want = "a number or 3 numbers" if t == "rgb" else "a number or (wavelength, value) pairs"
            raise DictError(f"load_dict: {_path(keys + ['value'])}: {t!r} value must be {want}, got {v!r}")
        self.line(depth, f"<{t} name={name} value={quoteattr(text)}/>", keys)

    def value(self, depth, key, v, keys):
        name = quoteattr(key)
        if isinstance(v, dict):
            self.obj(depth, key, v, keys, root_level=False)
        elif isinstance(v, bool):
            self.line(depth, f"<boolean name={name} value=\"{'true' if v else 'false'}\"/>", keys)
        elif isinstance(v, (int, np.integer)):
            self.line(depth, f"<integer name={name} value=\"{int(v)}\"/>", keys)
        elif isinstance(v, (float, np.floating)):
            self.line(depth, f"<float name={name} value={quoteattr(_fmt(v))}/>", keys)
        elif isinstance(v, str):
            s = _abs(v) if key == "filename" else v
            self.line(depth, f"<string name={name} value={quoteattr(s)}/>", keys)
        elif _matrix(v) is not None:
            m = _matrix(v)
            text = " ".join(_fmt(x) for x in m.reshape(-1))
            self.line(depth, f"<transform name={name}>", keys)
            self.line(depth + 1, f"<matrix value={quoteattr(text)}/>", keys)
            self.line(depth, "</transform>", keys)
        elif _numbers(v, 3) is not None:
            tag = "vector" if key in _VECTORS else "point"
            text = ", ".join(_fmt(x) for x in _numbers(v, 3))
            self.line(depth, f"<{tag} name={name} value={quoteattr(text)}/>", keys)
        else:
            raise DictError(
                f"load_dict: {_path(keys)}: cannot use a value of type {type(v).__name__} "
                f"({v!r:.60}): give a number, string, bool, plugin dict, 3 numbers or a 4x4 matrix"
            )


def _pairs(v):
    try:
        a = np.asarray(v, dtype=np.float64)
    except (TypeError, ValueError):
        return None
    if a.ndim == 2 and a.shape[1] == 2 and a.shape[0] >= 1:
        return [tuple(p) for p in a]
    return None


def _abs(filename):
    """A file name as Mitsuba resolves it from a dictionary: relative to the working
    folder."""
    return filename if os.path.isabs(filename) else os.path.abspath(filename)


def to_xml(scene, tags):
    """The Mitsuba XML text of the scene dictionary `scene` and, per line, the key path
    it came from. `tags`: plugin type name -> XML tag."""
    if not isinstance(scene, dict):
        raise DictError(f"load_dict: expects a dict, got {type(scene).__name__}")
    if scene.get("type") != "scene":
        raise DictError("load_dict: scene['type']: the root dictionary needs 'type': 'scene'")
    w = _Writer(tags)
    w.line(0, '<scene version="3.0.0">', [])
    for key, v in scene.items():
        if key == "type":
            continue
        if not isinstance(key, str):
            raise DictError(f"load_dict: key {key!r} of the scene is not a string")
        if isinstance(v, Mesh):
            w.mesh(1, key, v, [key])
            continue
        if not isinstance(v, dict):
            raise DictError(
                f"load_dict: {_path([key])}: the scene holds objects (dicts with a 'type' "
                f"or wavetrace.Mesh), got {type(v).__name__}"
            )
        w.obj(1, key, v, [key], root_level=True)
    w.line(0, "</scene>", [])
    return "\n".join(w.lines) + "\n", w.keys, w.meshes


def key_of_line(keys, line):
    """The key path of 1-based `line`, as `scene['a']['b']`."""
    if 1 <= line <= len(keys) and keys[line - 1]:
        return _path(keys[line - 1])
    return "scene"
