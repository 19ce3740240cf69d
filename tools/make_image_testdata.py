#!/usr/bin/env python3
"""Write the EXR fixture that src/image/exr.rs's tests read, with Mitsuba 3's Bitmap.

    python3 tools/make_image_testdata.py     # writes src/image/testdata/mitsuba_rgba_f16.exr

An 8x4 RGBA float16 image, pixel (x, y) = (x/8, y/4, 0.25, 0.5): values exact in half
precision, written by the OpenEXR library inside Mitsuba as `hdrfilm` would write an
RGBA half render. It checks that wavetrace reads other renderers' EXRs (alpha
channel, half samples) and not only its own.
"""

import os

import mitsuba as mi

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def main():
    mi.set_variant("scalar_rgb")
    width, height = 8, 4
    values = []
    for y in range(height):
        for x in range(width):
            values += [x / 8, y / 4, 0.25, 0.5]
    tensor = mi.TensorXf(values, shape=(height, width, 4))
    bitmap = mi.Bitmap(tensor, pixel_format=mi.Bitmap.PixelFormat.RGBA)
    bitmap = bitmap.convert(mi.Bitmap.PixelFormat.RGBA, mi.Struct.Type.Float16, False)
    path = os.path.join(ROOT, "src", "image", "testdata", "mitsuba_rgba_f16.exr")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    bitmap.write(path)
    print("wrote %s (Mitsuba %s)" % (os.path.relpath(path, ROOT), mi.__version__))


if __name__ == "__main__":
    main()
