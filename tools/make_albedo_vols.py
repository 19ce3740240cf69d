#!/usr/bin/env python3
"""Write the albedo grids of scenes/media/albedo_*.xml (Mitsuba .vol, version 3,
float32, bounding box the unit cube), deterministic:

* albedo_rgb.vol: 7 x 5 x 3 voxels, 3 channels: red rises along x, green alternates
  between voxels along y, blue falls along z, each in [0.15, 0.95].
* albedo_gray.vol: 9 x 4 x 6 voxels, 1 channel: a diagonal ramp with a checker.

    python3 tools/make_albedo_vols.py [DIR]   (default scenes/media)
"""

import os
import struct
import sys


def write(path, res, channels, value):
    xr, yr, zr = res
    with open(path, "wb") as f:
        f.write(b"VOL\x03")
        f.write(struct.pack("<5i", 1, xr, yr, zr, channels))
        f.write(struct.pack("<6f", 0, 0, 0, 1, 1, 1))
        for z in range(zr):
            for y in range(yr):
                for x in range(xr):
                    f.write(struct.pack(f"<{channels}f", *value(x, y, z)))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "scenes/media"
    write(os.path.join(out, "albedo_rgb.vol"), (7, 5, 3), 3,
          lambda x, y, z: (0.15 + 0.8 * x / 6, 0.95 if y % 2 else 0.3, 0.95 - 0.8 * z / 2))
    write(os.path.join(out, "albedo_gray.vol"), (9, 4, 6), 1,
          lambda x, y, z: (min(0.95, 0.2 + 0.5 * (x + y + z) / 16 + (0.25 if (x + z) % 2 else 0.0)),))


if __name__ == "__main__":
    main()
