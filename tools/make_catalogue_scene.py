#!/usr/bin/env python3
"""Writes tests/data/catalogue/: one Mitsuba 3 scene that uses every material plugin of
the material-catalogue issue at once, with the files it reads, for
tests/catalogue_vs_mitsuba.rs.

    python3 tools/make_catalogue_scene.py            # the scene and its files
    python3 tools/mitsuba_ref.py tests/data/catalogue/catalogue.xml \\
        -o tests/data/catalogue/catalogue_ref.exr --spp 4096 --variant scalar_rgb

The scene: a floor of `principled` with a BMP texture on its base colour (a bitmap
format wavetrace could not read before), lit by a rectangular area light and a
constant sky, holding a row of spheres and a PLY mesh:
  - `mask` (opacity 0.6 from a float) over a diffuse,
  - `blendbsdf` (weight from a checkerboard) of a diffuse and a rough conductor of
    Mitsuba's named material `a-C`,
  - `twosided` with two different BSDFs, as an open disk seen from both sides,
  - `bumpmap` (a height field from a raw BMP bitmap, `scale`) over a rough plastic,
  - `principledthin` (diff_trans, spec_trans),
  - `pplastic`,
  - a PLY mesh with per-vertex colours, its diffuse reflectance a `mesh_attribute`
    (`vertex_color`), beside a `rawconstant` diffuse,
  - `hair` (Chiang et al. 2016, melanin concentrations) on a sphere,
  - `measured` (the RGL file tests/data/measured_iso.bsdf, one folder up),
and, floating behind the row,
  - a rough conductor whose `eta` is a raw BMP texture and whose `k` a spectrum file
    (`k.spd`),
  - a diffuse whose reflectance is a spectrum file (`paint.spd`: wavelength-value
    lines with comments, Mitsuba's `.spd`).
Every file is written by this script (no third-party data); the BMP by hand (24-bit,
bottom-up rows, as the format is).
"""

import math
import os
import struct

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "tests", "data", "catalogue")


def write_bmp(path, w, h, pixel):
    """A 24-bit BMP of w x h pixels, pixel(x, y) -> (r, g, b) bytes, y = 0 at the top."""
    row = (3 * w + 3) & ~3
    data = bytearray()
    for y in range(h - 1, -1, -1):  # bottom-up
        line = bytearray()
        for x in range(w):
            r, g, b = pixel(x, y)
            line += bytes((b, g, r))
        line += b"\0" * (row - 3 * w)
        data += line
    header = struct.pack("<2sIHHI", b"BM", 54 + len(data), 0, 0, 54)
    info = struct.pack("<IiiHHIIiiII", 40, w, h, 1, 24, 0, len(data), 2835, 2835, 0, 0)
    with open(path, "wb") as f:
        f.write(header + info + data)


def write_ply(path):
    """A low-poly sphere of radius 1 with a colour per vertex (red to blue by height,
    green by angle), ASCII PLY with red/green/blue float properties in [0, 1] (Mitsuba's
    `vertex_color`)."""
    rings, segs = 8, 12
    verts, faces = [], []
    for i in range(rings + 1):
        th = math.pi * i / rings
        for j in range(segs):
            ph = 2 * math.pi * j / segs
            p = (math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph))
            c = (1 - i / rings, 0.5 + 0.5 * math.cos(ph), i / rings)
            verts.append((p, c))
    for i in range(rings):
        for j in range(segs):
            a = i * segs + j
            b = i * segs + (j + 1) % segs
            c2 = (i + 1) * segs + j
            d = (i + 1) * segs + (j + 1) % segs
            if i > 0:
                faces.append((a, b, d))
            if i < rings - 1:
                faces.append((a, d, c2))
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\n")
        f.write(f"element vertex {len(verts)}\n")
        f.write("property float x\nproperty float y\nproperty float z\n")
        f.write("property float red\nproperty float green\nproperty float blue\n")
        f.write(f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
        for p, c in verts:
            f.write(" ".join(f"{v:.6f}" for v in p + c) + "\n")
        for t in faces:
            f.write(f"3 {t[0]} {t[1]} {t[2]}\n")


SCENE = """<scene version="3.0.0">
    <!-- Written by tools/make_catalogue_scene.py: every material plugin of the
         material-catalogue issue at once, against a Mitsuba 3.9.1 reference. -->
    <default name="spp" value="64"/>
    <integrator type="path"><integer name="max_depth" value="5"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0, 2.2, 9" target="0, 0.6, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
        <film type="hdrfilm"><integer name="width" value="96"/><integer name="height" value="48"/>
            <rfilter type="box"/></film>
    </sensor>

    <emitter type="constant"><rgb name="radiance" value="0.3, 0.35, 0.4"/></emitter>
    <shape type="rectangle">
        <transform name="to_world"><scale value="2"/><rotate x="1" angle="90"/><translate x="-1" y="5" z="3"/></transform>
        <emitter type="area"><rgb name="radiance" value="6, 5.5, 5"/></emitter>
    </shape>

    <!-- floor: principled, BMP base colour -->
    <shape type="rectangle">
        <transform name="to_world"><scale x="8" y="4" z="1"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="principled">
            <texture type="bitmap" name="base_color"><string name="filename" value="floor.bmp"/></texture>
            <float name="roughness" value="0.45"/>
            <float name="metallic" value="0.1"/>
            <float name="specular" value="0.5"/>
            <float name="clearcoat" value="0.3"/>
            <float name="sheen" value="0.2"/>
        </bsdf>
    </shape>

    <shape type="sphere">
        <point name="center" x="-3.3" y="0.6" z="0"/><float name="radius" value="0.6"/>
        <bsdf type="mask">
            <float name="opacity" value="0.6"/>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.3, 0.2"/></bsdf>
        </bsdf>
    </shape>

    <shape type="sphere">
        <point name="center" x="-2.0" y="0.6" z="0"/><float name="radius" value="0.6"/>
        <bsdf type="blendbsdf">
            <texture type="checkerboard" name="weight">
                <transform name="to_uv"><scale x="6" y="6"/></transform>
            </texture>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.2, 0.6, 0.3"/></bsdf>
            <bsdf type="roughconductor"><string name="material" value="a-C"/><float name="alpha" value="0.2"/></bsdf>
        </bsdf>
    </shape>

    <shape type="disk">
        <transform name="to_world"><scale value="0.6"/><rotate y="1" angle="70"/><translate x="-0.7" y="0.7" z="0"/></transform>
        <bsdf type="twosided">
            <bsdf type="diffuse"><rgb name="reflectance" value="0.9, 0.8, 0.2"/></bsdf>
            <bsdf type="roughconductor"><string name="material" value="Cu"/><float name="alpha" value="0.15"/></bsdf>
        </bsdf>
    </shape>

    <shape type="sphere">
        <point name="center" x="0.6" y="0.6" z="0"/><float name="radius" value="0.6"/>
        <bsdf type="bumpmap">
            <texture type="bitmap" name="arbitrary">
                <string name="filename" value="bumps.bmp"/>
                <boolean name="raw" value="true"/>
            </texture>
            <float name="scale" value="0.5"/>
            <bsdf type="roughplastic">
                <rgb name="diffuse_reflectance" value="0.3, 0.3, 0.7"/>
                <float name="alpha" value="0.1"/>
            </bsdf>
        </bsdf>
    </shape>

    <shape type="sphere">
        <point name="center" x="1.9" y="0.6" z="0"/><float name="radius" value="0.6"/>
        <bsdf type="principledthin">
            <rgb name="base_color" value="0.7, 0.5, 0.9"/>
            <float name="roughness" value="0.3"/>
            <float name="diff_trans" value="0.4"/>
            <float name="spec_trans" value="0.3"/>
            <float name="eta" value="1.4"/>
        </bsdf>
    </shape>

    <shape type="sphere">
        <point name="center" x="3.2" y="0.6" z="0"/><float name="radius" value="0.6"/>
        <bsdf type="pplastic">
            <rgb name="diffuse_reflectance" value="0.6, 0.2, 0.5"/>
            <float name="alpha" value="0.2"/>
        </bsdf>
    </shape>

    <shape type="ply">
        <string name="filename" value="vcolor.ply"/>
        <transform name="to_world"><scale value="0.5"/><translate x="-1.2" y="0.5" z="1.6"/></transform>
        <bsdf type="diffuse">
            <texture type="mesh_attribute" name="reflectance"><string name="name" value="vertex_color"/></texture>
        </bsdf>
    </shape>

    <shape type="sphere">
        <point name="center" x="1.2" y="0.4" z="1.7"/><float name="radius" value="0.4"/>
        <bsdf type="diffuse">
            <texture type="rawconstant" name="reflectance"><vector name="value" x="0.4" y="0.7" z="0.6"/></texture>
        </bsdf>
    </shape>

    <shape type="sphere">
        <point name="center" x="-2.3" y="0.4" z="1.7"/><float name="radius" value="0.4"/>
        <bsdf type="hair">
            <float name="eumelanin" value="0.3"/>
            <float name="pheomelanin" value="0.6"/>
        </bsdf>
    </shape>

    <shape type="sphere">
        <point name="center" x="0.0" y="0.4" z="1.8"/><float name="radius" value="0.4"/>
        <bsdf type="measured"><string name="filename" value="../measured_iso.bsdf"/></bsdf>
    </shape>

    <shape type="sphere">
        <point name="center" x="-1.4" y="1.5" z="-2.2"/><float name="radius" value="0.5"/>
        <bsdf type="roughconductor">
            <float name="alpha" value="0.15"/>
            <texture type="bitmap" name="eta">
                <string name="filename" value="eta.bmp"/>
                <boolean name="raw" value="true"/>
            </texture>
            <spectrum name="k" filename="k.spd"/>
        </bsdf>
    </shape>

    <shape type="sphere">
        <point name="center" x="1.4" y="1.5" z="-2.2"/><float name="radius" value="0.5"/>
        <bsdf type="diffuse"><spectrum name="reflectance" filename="paint.spd"/></bsdf>
    </shape>
</scene>
"""


def main():
    os.makedirs(OUT, exist_ok=True)

    def floor(x, y):
        c = ((x // 4) + (y // 4)) % 2
        return (200, 180, 150) if c else (60, 90, 140)

    write_bmp(os.path.join(OUT, "floor.bmp"), 32, 16, floor)
    def bumps(x, y):
        v = int(127.5 + 127.5 * math.sin(2 * math.pi * x / 8) * math.sin(2 * math.pi * y / 8))
        return (v, v, v)

    write_bmp(os.path.join(OUT, "bumps.bmp"), 32, 32, bumps)
    write_ply(os.path.join(OUT, "vcolor.ply"))

    def eta(x, y):  # raw: eta = byte / 255, 0.2 .. 1.6 over u, stripes over v
        t = x / 15
        return tuple(int(255 * min(1.0, 0.15 + 0.85 * t * f + 0.1 * (y // 4 % 2)))
                     for f in (0.3, 0.6, 1.0))

    write_bmp(os.path.join(OUT, "eta.bmp"), 16, 16, eta)
    with open(os.path.join(OUT, "k.spd"), "w") as f:
        f.write("# k of a gold-like conductor, nm and value\n400 1.9\n500 1.8\n"
                "600 2.9\n700 3.9\n")
    with open(os.path.join(OUT, "paint.spd"), "w") as f:
        f.write("# a teal paint: wavelength (nm) reflectance\n380 0.05\n450 0.35\n"
                "500 0.6 # peak\n550 0.45\n\n600 0.1\n700 0.08\n780 0.1\n")
    with open(os.path.join(OUT, "catalogue.xml"), "w") as f:
        f.write(SCENE)
    print(f"wrote {OUT}/catalogue.xml, floor.bmp, bumps.bmp, vcolor.ply, eta.bmp, k.spd, "
          "paint.spd")


if __name__ == "__main__":
    main()
