#!/usr/bin/env python3
"""Write the texture and environment-map scenes: scenes/textures/ and scenes/envmap/.

    python3 tools/make_texture_scenes.py

Needs numpy, Pillow and Mitsuba 3 (for EXR I/O), and the CC0 assets in
../shared/assets/ (relative to the repository root):

* scenes/textures/tex/bricks_{color.jpg,normal.png,roughness.jpg}: ambientCG
  Bricks102 (CC0), box-downscaled from 1024² to 128² (colour and roughness averaged as
  stored, the normal map averaged and renormalized); bricks_color.png is the colour
  JPEG as libjpeg decodes it.
* scenes/textures/tex/light.exr: an 8 x 4 emission pattern (made here).
* scenes/envmap/venice_sunset_256.exr: Poly Haven "Venice Sunset" (CC0), box-averaged
  from 1024 x 512 to 256 x 128 (energy kept: the sun is one bright texel), half floats.
"""

import os
import sys

import numpy as np
from PIL import Image

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ASSETS = os.path.join(ROOT, "..", "shared", "assets")


def box_down(a, f):
    h, w = a.shape[0] // f, a.shape[1] // f
    return a[: h * f, : w * f].reshape(h, f, w, f, -1).mean(axis=(1, 3))


def write_exr(path, rgb, half=False):
    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    data = rgb.astype(np.float16 if half else np.float32)
    mi.Bitmap(data, pixel_format=mi.Bitmap.PixelFormat.RGB).write(path)


def textures():
    tex = os.path.join(ROOT, "scenes", "textures", "tex")
    os.makedirs(tex, exist_ok=True)
    src = os.path.join(ASSETS, "textures", "bricks102", "Bricks102_1K-JPG_")
    color = np.asarray(Image.open(src + "Color.jpg").convert("RGB"), dtype=np.float64)
    Image.fromarray(np.round(box_down(color, 8)).astype(np.uint8)).save(
        os.path.join(tex, "bricks_color.jpg"), quality=92)
    # The same JPEG as libjpeg decodes it (Pillow and Mitsuba agree to the bit), for
    # normalmap.xml: the image crate's decoder upsamples the 4:2:0 chroma and rounds
    # its IDCT differently (21% of values off by 1 to 3 levels, linear mean +0.23%),
    # a legitimate JPEG difference that the normal-map test must not measure.
    decoded = Image.open(os.path.join(tex, "bricks_color.jpg")).convert("RGB")
    decoded.save(os.path.join(tex, "bricks_color.png"))
    normal = np.asarray(Image.open(src + "NormalGL.jpg").convert("RGB"), dtype=np.float64) / 255.0
    n = box_down(normal * 2.0 - 1.0, 8)
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    Image.fromarray(np.round((n * 0.5 + 0.5) * 255.0).astype(np.uint8)).save(
        os.path.join(tex, "bricks_normal.png"))
    rough = np.asarray(Image.open(src + "Roughness.jpg").convert("L"), dtype=np.float64)
    Image.fromarray(np.round(box_down(rough[..., None], 8)[..., 0]).astype(np.uint8)).save(
        os.path.join(tex, "bricks_roughness.jpg"), quality=92)
    # Emission pattern: warm and cool stripes with one bright cell, not symmetric, so
    # a flipped or mirrored lookup shows.
    light = np.zeros((4, 8, 3))
    for y in range(4):
        for x in range(8):
            light[y, x] = [6.0 + 2 * x, 5.0 + y, 3.0] if (x + y) % 2 == 0 else [2.0, 4.0, 9.0 - x]
    light[0, 6] = [40.0, 36.0, 30.0]
    write_exr(os.path.join(tex, "light.exr"), light)


def envmap():
    out = os.path.join(ROOT, "scenes", "envmap")
    os.makedirs(out, exist_ok=True)
    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    src = np.array(mi.Bitmap(os.path.join(ASSETS, "envmaps", "venice_sunset_1k.exr")))[..., :3]
    write_exr(os.path.join(out, "venice_sunset_256.exr"), box_down(src.astype(np.float64), 4), half=True)


def main():
    if not os.path.isdir(ASSETS):
        sys.exit("make_texture_scenes.py: %s not found" % ASSETS)
    textures()
    envmap()


if __name__ == "__main__":
    main()
