"""wavetrace from Python: load a scene, render it into a NumPy array, move its camera.

    import wavetrace as wt
    scene = wt.load_file("scenes/cbox/cbox_path.xml", spp=16)
    image = wt.render(scene, spp=64, seed=0)      # float32, (height, width, channels)
    image.channels                                  # ['R', 'G', 'B']
    wt.write("cbox.exr", image)

The API follows Mitsuba 3's (``load_file``, ``load_dict``, ``render``); the manual is
docs/python.md. The rendering runs in wavetrace's GLSL kernels on a Vulkan device
(``devices()``), with the GIL released; Ctrl-C raises ``KeyboardInterrupt`` within a
batch and the scene renders again afterwards.
"""

import os
import re
import sys
import tempfile
import time
import zlib
import struct

import numpy as np

from . import _wavetrace
from . import _dict
from ._mesh import Mesh, MeshError, traverse

__all__ = [
    "Image",
    "Mesh",
    "MeshError",
    "Scene",
    "traverse",
    "devices",
    "set_device",
    "load_file",
    "load_dict",
    "render",
    "write",
    "read",
    "look_at",
    "plugins",
]

_device = None


def devices():
    """The Vulkan devices wavetrace can render on: a list of dicts with ``index``,
    ``name`` and ``kind``."""
    return [
        {"index": i, "name": n, "kind": k} for i, n, k in _wavetrace.devices()
    ]


def set_device(selector=None):
    """Renders scenes loaded from now on on the device `selector` names (its index in
    ``devices()`` or part of its name); ``None``: the best one (as the CLI's
    ``--device``)."""
    global _device
    _device = None if selector is None else str(selector)


def plugins():
    """The Mitsuba plugin types wavetrace knows: ``{type: (xml tag, supported)}``."""
    return {name: (tag, ok) for name, tag, ok in _wavetrace.plugins()}


class Image(np.ndarray):
    """A rendered image: a float32 NumPy array of shape (height, width, channels)
    whose ``channels`` are the channels' names (``['R', 'G', 'B']``, AOVs after).
    In Jupyter it shows itself (``_repr_png_``: sRGB, clipped)."""

    def __new__(cls, array, channels=None):
        obj = np.asarray(array, dtype=np.float32)
        if obj.ndim == 2:
            obj = obj[:, :, None]
        obj = obj.view(cls)
        if channels is None:
            channels = _default_channels(obj.shape[2])
        obj.channels = list(channels)
        return obj

    def __array_finalize__(self, obj):
        self.channels = getattr(obj, "channels", None)

    def __reduce__(self):
        # Pickles as a plain array with its channel names.
        return (Image, (np.asarray(self), self.channels))

    def to_srgb8(self):
        """The image as 8-bit sRGB (height, width, 3): RGB channels (or the first
        one as grey), sRGB's transfer curve, clipped to [0, 1]."""
        a = np.asarray(self, dtype=np.float32)
        names = self.channels or []
        if all(c in names for c in "RGB"):
            rgb = np.stack([a[:, :, names.index(c)] for c in "RGB"], axis=-1)
        elif a.shape[2] >= 3:
            rgb = a[:, :, :3]
        else:
            rgb = np.repeat(a[:, :, :1], 3, axis=2)
        rgb = np.nan_to_num(np.clip(rgb, 0.0, 1.0))
        srgb = np.where(rgb <= 0.0031308, 12.92 * rgb, 1.055 * np.power(rgb, 1 / 2.4) - 0.055)
        return (np.clip(srgb, 0, 1) * 255 + 0.5).astype(np.uint8)

    def _repr_png_(self):
        if self.ndim != 3:
            return None
        return _png_bytes(self.to_srgb8())


def _default_channels(n):
    return {1: ["Y"], 2: ["Y", "A"], 3: ["R", "G", "B"], 4: ["R", "G", "B", "A"]}.get(
        n, [f"C{i}" for i in range(n)]
    )


def _png_bytes(rgb8):
    """A PNG file of an (h, w, 3) uint8 array."""
    h, w, _ = rgb8.shape
    raw = b"".join(b"\x00" + rgb8[y].tobytes() for y in range(h))

    def chunk(kind, data):
        c = struct.pack(">I", len(data)) + kind + data
        return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    return (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
        + chunk(b"IDAT", zlib.compress(raw, 6))
        + chunk(b"IEND", b"")
    )


class Scene:
    """A loaded scene. Kept on the device between renders: a new seed, sample count or
    camera (``set_camera``) costs nothing; another integrator, ``set_emitter_radiance``
    or ``set_bsdf_color`` sets the scene up again at the next render."""

    def __init__(self, native):
        self._native = native

    def info(self):
        """Shapes, triangles, emitters, BSDFs, film size, channels, spp, integrator."""
        return self._native.info()

    @property
    def camera_to_world(self):
        """The camera-to-world matrix (4x4 NumPy array)."""
        return np.array(self._native.camera_to_world(), dtype=np.float64)

    @camera_to_world.setter
    def camera_to_world(self, m):
        self.set_camera(to_world=m)

    @property
    def fov(self):
        """The horizontal field of view, degrees."""
        return float(self._native.info()["fov"])

    @fov.setter
    def fov(self, degrees):
        self.set_camera(fov=degrees)

    def set_camera(self, to_world=None, fov=None):
        """Moves the camera: `to_world` a 4x4 matrix (nested lists, a NumPy array or a
        ``mi.ScalarTransform4f``; see ``look_at``), `fov` the horizontal field of view
        in degrees."""
        rows = None
        if to_world is not None:
            m = _dict._matrix(to_world)
            if m is None:
                raise ValueError("to_world must be a 4x4 matrix")
            rows = m.astype(np.float32).tolist()
        self._native.set_camera(rows, None if fov is None else float(fov))

    def set_emitter_radiance(self, index, rgb):
        """Sets emitter `index`'s radiance (area, constant) or intensity (point, spot)
        to `rgb` (3 numbers, or one)."""
        self._native.set_emitter_radiance(int(index), _rgb(rgb))

    def set_bsdf_color(self, index, rgb):
        """Sets BSDF `index`'s reflectance (``diffuse``, also inside ``twosided``)."""
        self._native.set_bsdf_color(int(index), _rgb(rgb))

    def __repr__(self):
        i = self.info()
        w, h = i["film_size"]
        return (
            f"<wavetrace.Scene {os.path.basename(i['path'])}: {i['shapes']} shapes, "
            f"{i['triangles']} triangles, {i['emitters']} emitters, {w}x{h}>"
        )


def _rgb(v):
    a = np.asarray(v, dtype=np.float64).reshape(-1)
    if a.size == 1:
        a = np.repeat(a, 3)
    if a.size != 3:
        raise ValueError(f"expected 3 numbers (or one), got {v!r}")
    return [float(x) for x in a]


def _define_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (list, tuple, np.ndarray)):
        return ", ".join(str(x) for x in np.asarray(v).reshape(-1))
    return str(v)


def load_file(path, **defines):
    """Loads a Mitsuba 3 or Nori scene file; keyword arguments override its
    ``<default>`` values as the CLI's ``-D name=value`` does."""
    d = [(k, _define_value(v)) for k, v in defines.items()]
    return Scene(_wavetrace.load_file(os.fspath(path), d, _device))


def load_dict(scene):
    """Loads a scene from Mitsuba 3's dictionary format (see docs/python.md): nested
    plugin dicts with a ``type``, transforms as 4x4 matrices (lists, NumPy arrays,
    ``mi.ScalarTransform4f``), ``{'type': 'ref', 'id': ...}`` references, ``Mesh``
    objects built in Python (handed to the loader in memory). A dict
    wavetrace cannot read raises ``ValueError`` naming the key."""
    tags = {name: tag for name, tag, _ in _wavetrace.plugins()}
    xml, keys, meshes = _dict.to_xml(scene, tags)
    fd, tmp = tempfile.mkstemp(prefix="wavetrace_dict_", suffix=".xml")
    try:
        with os.fdopen(fd, "w") as f:
            f.write(xml)
        try:
            native = _wavetrace.load_file(tmp, [], _device, [m._parts() for m in meshes])
        except ValueError as e:
            raise _dict.DictError(_name_keys(str(e), tmp, keys)) from None
    finally:
        os.unlink(tmp)
    return Scene(native)


def _name_keys(message, tmp, keys):
    """`message` with the generated file's `path:line` replaced by the key path."""

    def at(m):
        return f"load_dict: {_dict.key_of_line(keys, int(m.group(1)))}"

    out = re.sub(re.escape(tmp) + r":(\d+)(?::\d+)?", at, message)
    return out.replace(tmp, "load_dict")


class _Bar:
    """A progress bar on stderr (tqdm's if it is installed)."""

    def __init__(self):
        try:
            from tqdm.auto import tqdm

            self.tqdm = tqdm(total=100, unit="%", leave=False)
        except ImportError:
            self.tqdm = None
        self.shown = -1
        self.t0 = time.perf_counter()

    def __call__(self, done, total):
        pct = int(100 * done / max(total, 1))
        if pct == self.shown:
            return
        if self.tqdm is not None:
            self.tqdm.update(pct - max(self.shown, 0))
        else:
            bar = "#" * (pct // 4)
            sys.stderr.write(f"\r[{bar:<25}] {pct:3d}% {time.perf_counter() - self.t0:6.1f} s")
            sys.stderr.flush()
        self.shown = pct

    def close(self):
        if self.tqdm is not None:
            self.tqdm.close()
        elif self.shown >= 0:
            sys.stderr.write("\n")


def render(scene, spp=None, seed=0, sensor=0, integrator=None, progress=None):
    """Renders `scene` and returns an ``Image`` (float32 NumPy array, (height, width,
    channels), names in ``image.channels``).

    spp: samples per pixel (default: the scene's); seed: added to the sampler's seed,
    as the CLI's ``--seed``; sensor: the scene's sensor (wavetrace scenes have one:
    0); integrator: an integrator name overriding the scene's, as ``--integrator``;
    progress: ``True`` for a progress bar, or a callable ``f(done, total)`` called after
    every batch (paths done, paths in all).
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"render() takes a wavetrace.Scene, got {type(scene).__name__}")
    if sensor not in (0, None):
        raise ValueError(f"sensor {sensor!r}: the scene has one sensor (0)")
    if spp is not None and (int(spp) != spp or spp < 1):
        raise ValueError(f"spp must be a positive integer, got {spp!r}")
    if int(seed) != seed or not 0 <= seed < 2**32:
        raise ValueError(f"seed must be an integer in [0, 2^32), got {seed!r}")
    bar = _Bar() if progress is True else None
    callback = bar if bar is not None else progress
    if callback is not None and not callable(callback):
        raise TypeError("progress must be True or a callable f(done, total)")
    try:
        h, w, names, data = scene._native.render(
            None if spp is None else int(spp), int(seed), integrator, callback
        )
    finally:
        if bar is not None:
            bar.close()
    a = np.frombuffer(data, dtype=np.float32).reshape(h, w, len(names))
    return Image(a, names)


def write(path, image, channels=None, half=False):
    """Writes an image (an ``Image`` or an (h, w[, c]) array) to `path`: OpenEXR
    (float32, or half floats with ``half=True``) or PFM, linear; or an sRGB PNG, by the
    extension."""
    path = os.fspath(path)
    a = np.asarray(image, dtype=np.float32)
    if a.ndim == 2:
        a = a[:, :, None]
    if a.ndim != 3:
        raise ValueError(f"an image is (height, width[, channels]), got shape {a.shape}")
    names = channels or getattr(image, "channels", None) or _default_channels(a.shape[2])
    if len(names) != a.shape[2]:
        raise ValueError(f"{len(names)} channel names for {a.shape[2]} channels")
    if path.lower().endswith(".png"):
        with open(path, "wb") as f:
            f.write(_png_bytes(Image(a, names).to_srgb8()))
        return
    h, w, _ = a.shape
    _wavetrace.write(path, w, h, list(names), np.ascontiguousarray(a).tobytes(), half)


def read(path):
    """Reads an OpenEXR file into an ``Image`` (its channels as the file stores them,
    sorted by name)."""
    h, w, names, data = _wavetrace.read_exr(os.fspath(path))
    a = np.frombuffer(data, dtype=np.float32).reshape(h, w, len(names))
    return Image(a, names)


def look_at(origin, target, up):
    """The camera-to-world matrix of a camera at `origin` looking at `target` (4x4
    NumPy array; Mitsuba's ``ScalarTransform4f.look_at``)."""
    o, t, u = (np.asarray(v, dtype=np.float64).reshape(3) for v in (origin, target, up))
    d = t - o
    d /= np.linalg.norm(d)
    left = np.cross(u, d)
    left /= np.linalg.norm(left)
    new_up = np.cross(d, left)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = left, new_up, d, o
    return m
