#!/usr/bin/python3
"""Write the OpenVDB test grids of scenes/media/ from the smoke grid, with Debian's
OpenVDB Python bindings (`apt-get install python3-openvdb`; Debian's build uses
blosc, so values are written blosc/LZ4-compressed with mask compression, as
OpenVDB writes by default). Run with the system Python, which has the bindings:

    /usr/bin/python3 tools/make_vdb.py

- smoke.vdb: one float grid `density`, the values of smoke_border.vol (32^3, zero
  border), placed by the grid's own transform exactly where the .vol's unit cube is:
  voxel (i, j, k) centred at ((i, j, k) + 0.5) / 32, the .vol's voxel centres. So
  `-D vol=smoke.vdb` and `-D vol=smoke_border.vol` in smoke.xml are the same medium
  (tests/media_grids.rs renders both). Voxels of value 0 are inactive.
- smoke_grids.vdb: several grids in one file, for choosing one by name:
  `temperature` (float, first in the file: 2 - density where the smoke is, else 0,
  under an affine transform that turns the grid 90 degrees about z: a matrix with
  rotation, scale and translation), `density` (the smoke again, saved as half
  floats), `velocity` (a vec3s grid: not scalar), `tiles` (constant tiles at the
  leaf level and one leaf), `huge` (one active root tile of 4096^3 voxels: too
  large).

The .vdb files are committed, so tests do not need OpenVDB installed.
"""

import os
import struct

import numpy as np
import pyopenvdb as vdb

HERE = os.path.dirname(os.path.abspath(__file__))
MEDIA = os.path.join(HERE, "..", "scenes", "media")


def read_vol(path):
    """A Mitsuba .vol (version 3, float32, one channel) as an array [x, y, z]."""
    with open(path, "rb") as f:
        b = f.read()
    assert b[:4] == b"VOL\x03"
    enc, xr, yr, zr, ch = struct.unpack("<5i", b[4:24])
    assert enc == 1 and ch == 1
    data = np.frombuffer(b, dtype="<f4", offset=48).reshape(zr, yr, xr)
    return np.ascontiguousarray(data.transpose(2, 1, 0)).astype(np.float32)


def unit_cube_transform(res):
    """Index (i, j, k) -> world ((i, j, k) + 0.5) / res, as OpenVDB's row-vector matrix."""
    s = 1.0 / res
    return vdb.createLinearTransform(
        [[s, 0, 0, 0], [0, s, 0, 0], [0, 0, s, 0], [0.5 * s, 0.5 * s, 0.5 * s, 1]]
    )


def density_grid(values, half=False):
    g = vdb.FloatGrid(0.0)
    g.copyFromArray(values, ijk=(0, 0, 0), tolerance=0)
    g.name = "density"
    g.gridClass = vdb.GridClass.FOG_VOLUME
    g.transform = unit_cube_transform(values.shape[0])
    g.saveFloatAsHalf = half
    return g


def main():
    smoke = read_vol(os.path.join(MEDIA, "smoke_border.vol"))
    res = smoke.shape[0]
    vdb.write(os.path.join(MEDIA, "smoke.vdb"), grids=[density_grid(smoke)])

    temperature = vdb.FloatGrid(0.0)
    temperature.copyFromArray(np.where(smoke > 0, 2.0 - smoke, 0.0).astype(np.float32))
    temperature.name = "temperature"
    # Row-vector matrix: index (i, j, k) -> world (-j, i, k) / 16 + (1, 2, 3).
    temperature.transform = vdb.createLinearTransform(
        [[0, 1.0 / 16, 0, 0], [-1.0 / 16, 0, 0, 0], [0, 0, 1.0 / 16, 0], [1, 2, 3, 1]]
    )

    velocity = vdb.Vec3SGrid()
    velocity.fill((0, 0, 0), (3, 3, 3), (1.0, 0.0, 0.0))
    velocity.name = "velocity"

    tiles = vdb.FloatGrid(0.0)
    tiles.fill((0, 0, 0), (15, 15, 15), 0.5)  # 8 tiles of 8^3 in a level-1 node
    tiles.fill((16, 0, 0), (23, 7, 7), 2.0)  # one more
    tiles.getAccessor().setValueOn((30, 3, 3), 1.0)  # a leaf with one active voxel
    tiles.name = "tiles"

    huge = vdb.FloatGrid(0.0)
    huge.fill((0, 0, 0), (4095, 4095, 4095), 1.0)  # one root tile
    huge.name = "huge"

    vdb.write(
        os.path.join(MEDIA, "smoke_grids.vdb"),
        grids=[temperature, density_grid(smoke, half=True), velocity, tiles, huge],
    )
    for name in ("smoke.vdb", "smoke_grids.vdb"):
        path = os.path.join(MEDIA, name)
        print(path, os.path.getsize(path), "bytes")
        for g in vdb.readAllGridMetadata(path):
            print("  ", g.name, g.valueTypeName, g.metadata.get("file_bbox_min"),
                  g.metadata.get("file_bbox_max"))


if __name__ == "__main__":
    main()
