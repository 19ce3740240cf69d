#!/usr/bin/env python3
"""Write scenes/media/smoke.vol: a 32^3 single-channel density grid of a rising,
curling smoke plume for the shipped heterogeneous-medium scene (scenes/media/smoke.xml).

The plume is a chain of Gaussian puffs along a curve, broken up by value noise and cut
to exactly 0 below a threshold, so the grid has empty regions (majorant cells of 0,
skipped by delta tracking) next to dense ones. `--spikes N` adds N single-voxel
spikes of density 40 (the stress test's grid; the shipped one has none, since a
single global majorant of 40 makes Mitsuba's reference 40 times slower). Format: Mitsuba's .vol version 3 (b"VOL",
3, int32 encoding 1 = float32, int32 xres, yres, zres, channels, 6 float32 bounding
box, float32 data with x fastest), bounding box the unit cube. Deterministic (seeded).
`--zero-border` sets the outermost layer of voxels to 0 (smoke_border.vol, the grid of
smoke_rotated.xml: a
rotated grid whose border is empty is the same medium in wavetrace, which confines it to
the rotated box, and in Mitsuba 3.9, which fills the box's world-space bounding box
with the border values clamped outwards).

    python3 tools/make_smoke.py [-o scenes/media/smoke.vol] [--res 32] [--spikes 0] [--zero-border]
"""

import argparse
import struct

import numpy as np


def value_noise(res, cells, rng):
    """Trilinear interpolation of random values on a (cells+1)^3 lattice."""
    lattice = rng.random((cells + 1,) * 3)
    x = np.linspace(0, cells, res, endpoint=False) + 0.5 * cells / res
    i = np.minimum(x.astype(int), cells - 1)
    f = x - i
    out = np.zeros((res, res, res))
    for dz in (0, 1):
        for dy in (0, 1):
            for dx in (0, 1):
                w = (
                    (f if dz else 1 - f)[:, None, None]
                    * (f if dy else 1 - f)[None, :, None]
                    * (f if dx else 1 - f)[None, None, :]
                )
                out += w * lattice[np.ix_(i + dz, i + dy, i + dx)]
    return out


def plume(res, spikes=0, seed=7):
    rng = np.random.default_rng(seed)
    c = (np.arange(res) + 0.5) / res
    z, y, x = np.meshgrid(c, c, c, indexing="ij")  # array index [z, y, x]
    density = np.zeros((res, res, res))
    for k in range(14):
        s = k / 13.0
        # The puffs rise along y, drifting and curling in x and z, and widen.
        cx = 0.5 + 0.18 * np.sin(3.0 * s)
        cz = 0.5 + 0.12 * np.cos(4.0 * s)
        cy = 0.12 + 0.75 * s
        r = 0.07 + 0.1 * s
        d2 = (x - cx) ** 2 + (y - cy) ** 2 + (z - cz) ** 2
        density += (1.0 - 0.4 * s) * np.exp(-d2 / (2 * r * r))
    noise = 0.5 * value_noise(res, 4, rng) + 0.5 * value_noise(res, 9, rng)
    density *= 0.4 + 1.2 * noise
    density = np.where(density > 0.15, density - 0.15, 0.0)
    density /= density.max()
    for _ in range(spikes):
        i = rng.integers(res // 4, 3 * res // 4, size=3)
        density[i[0], i[1], i[2]] = 40.0
    return density.astype(np.float32)


def write_vol(path, grid):
    zr, yr, xr = grid.shape
    with open(path, "wb") as f:
        f.write(b"VOL" + bytes([3]))
        f.write(struct.pack("<iiiii", 1, xr, yr, zr, 1))
        f.write(struct.pack("<6f", 0, 0, 0, 1, 1, 1))
        f.write(grid.astype("<f4").tobytes())


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", default="scenes/media/smoke.vol")
    ap.add_argument("--res", type=int, default=32)
    ap.add_argument("--spikes", type=int, default=0)
    ap.add_argument("--zero-border", action="store_true")
    args = ap.parse_args()
    grid = plume(args.res, args.spikes)
    if args.zero_border:
        grid[[0, -1], :, :] = 0
        grid[:, [0, -1], :] = 0
        grid[:, :, [0, -1]] = 0
    write_vol(args.o, grid)
    empty = (grid == 0).mean()
    print(f"{args.o}: {args.res}^3, max {grid.max():.1f}, {100 * empty:.0f}% empty voxels")


if __name__ == "__main__":
    main()
