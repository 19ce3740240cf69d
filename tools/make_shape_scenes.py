#!/usr/bin/env python3
"""Write the shape image-test scenes of scenes/shapes/ and their textures.

    python3 tools/make_shape_scenes.py

* tex/uv_debug.png      64 x 64: red = u, green = v, an 8 x 8 grid of dark lines, a
                        blue square in the texel corner (u, v) < (1/8, 1/8) and a
                        white one at u > 7/8, v < 1/8, so any shift, turn or mirror of
                        a shape's uvs shows
* tex/normal_debug.png  32 x 32 tangent-space normals tilted along the tangent in
                        bands across u and along the bitangent in bands across v
                        (read raw)
* tex/checker.png       4 x 4 black and white checker with one red and one blue cell
* tex/floor.png, tex/light.png  a grid for the floor, a gradient for the light
* {cube,rectangle,disk,sphere,cylinder,obj,ply,serialized}.xml  each shape twice:
  left a diffuse with uv_debug.png; right, mirrored by to_world, a twosided normal map
  (normal_debug.png) over an anisotropic rough conductor, whose highlight follows the
  tangent frame; a rectangle light and a dim constant environment, path tracing with
  max_depth 3
* checker_cube.xml       the issue's scene: a cube with a checkerboard bitmap, a
                         bitmap-textured floor and a bitmap-textured area light

The meshes are tools/make_shape_meshes.py's. References: scenes/refs/README.md.
Every scene names a box reconstruction filter.
"""

import math
import os
import struct
import zlib

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), ".."))
OUT = os.path.join(ROOT, "scenes", "shapes")


def write_png(path, width, height, pixel):
    """An 8-bit RGB PNG; pixel(x, y) -> (r, g, b) in 0..255, row 0 at the top."""
    rows = b"".join(
        b"\0" + bytes(c for x in range(width) for c in pixel(x, y)) for y in range(height))

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def textures():
    tex = os.path.join(OUT, "tex")
    os.makedirs(tex, exist_ok=True)

    def uv_debug(x, y):
        if x < 8 and y < 8:
            return (30, 60, 255)
        if x >= 56 and y < 8:
            return (255, 255, 255)
        r, g = 40 + 3 * x, 40 + 3 * y
        if x % 8 == 0 or y % 8 == 0:
            r, g = r // 3, g // 3
        return (r, g, 60)
    write_png(os.path.join(tex, "uv_debug.png"), 64, 64, uv_debug)

    def normal_debug(x, y):
        u, v = (x + 0.5) / 32, (y + 0.5) / 32
        n = (0.45 * math.sin(2 * math.pi * 3 * u), 0.3 * math.cos(2 * math.pi * 2 * v), 1.0)
        length = math.sqrt(sum(c * c for c in n))
        return tuple(round((c / length * 0.5 + 0.5) * 255) for c in n)
    write_png(os.path.join(tex, "normal_debug.png"), 32, 32, normal_debug)

    def checker(x, y):
        if (x, y) == (0, 0):
            return (220, 30, 30)
        if (x, y) == (3, 1):
            return (30, 30, 220)
        return (230, 230, 230) if (x + y) % 2 == 0 else (25, 25, 25)
    write_png(os.path.join(tex, "checker.png"), 4, 4, checker)

    def floor(x, y):
        line = x % 16 == 0 or y % 16 == 0
        return (60, 60, 70) if line else (170 + x // 2, 160, 130 + y // 2)
    write_png(os.path.join(tex, "floor.png"), 64, 64, floor)

    def light(x, y):
        return (255, 200 + 3 * x, 120 + 15 * y)
    write_png(os.path.join(tex, "light.png"), 16, 8, light)


HEADER = """<scene version="3.0.0">
    <!-- Written by tools/make_shape_scenes.py. {comment} -->
    <path value="."/>
    <default name="spp" value="64"/>
    <default name="width" value="{width}"/>
    <default name="height" value="{height}"/>
    <integrator type="path">
        <integer name="max_depth" value="3"/>
    </integrator>
    <sensor type="perspective">
        <float name="fov" value="{fov}"/>
        <transform name="to_world">
            <lookat origin="{origin}" target="{target}" up="0, 1, 0"/>
        </transform>
        <sampler type="independent">
            <integer name="sample_count" value="$spp"/>
        </sampler>
        <film type="hdrfilm">
            <integer name="width" value="$width"/>
            <integer name="height" value="$height"/>
            <rfilter type="box"/>
        </film>
    </sensor>
"""

LIGHTS = """    <shape type="rectangle">
        <transform name="to_world">
            <scale value="0.8"/>
            <lookat origin="1.2, 2.6, 2.4" target="0, 0, 0" up="0, 1, 0"/>
        </transform>
        <emitter type="area">
            <rgb name="radiance" value="9, 8.5, 8"/>
        </emitter>
    </shape>
    <emitter type="constant">
        <rgb name="radiance" value="0.15"/>
    </emitter>
"""

LEFT = """        <bsdf type="diffuse">
            <texture type="bitmap" name="reflectance">
                <string name="filename" value="tex/uv_debug.png"/>
            </texture>
        </bsdf>"""

RIGHT = """        <bsdf type="twosided">
            <bsdf type="normalmap">
                <texture type="bitmap" name="normalmap">
                    <string name="filename" value="tex/normal_debug.png"/>
                    <boolean name="raw" value="true"/>
                </texture>
                <bsdf type="roughconductor">
                    <string name="material" value="Cu"/>
                    <string name="distribution" value="ggx"/>
                    <float name="alpha_u" value="0.06"/>
                    <float name="alpha_v" value="0.35"/>
                </bsdf>
            </bsdf>
        </bsdf>"""

# Per shape: its own parameters, and the object-space transform that shows it well
# (applied before the placement left or right).
SHAPES = {
    "cube": ("", '<scale value="0.55"/><rotate y="1" angle="35"/><rotate x="1" angle="25"/>'),
    "rectangle": ("", '<scale value="0.7"/><rotate x="1" angle="-50"/><rotate y="1" angle="25"/>'),
    "disk": ("", '<scale value="0.7"/><rotate x="1" angle="-50"/><rotate y="1" angle="25"/>'),
    "sphere": ('<float name="radius" value="0.7"/>',
               '<rotate x="1" angle="-60"/><rotate z="1" angle="30"/>'),
    "cylinder": ('<point name="p0" value="0, 0, -0.8"/><point name="p1" value="0, 0, 0.8"/>'
                 '<float name="radius" value="0.5"/>',
                 '<rotate x="1" angle="-70"/><rotate y="1" angle="30"/>'),
    "obj": ('<string name="filename" value="meshes/uvsphere.obj"/>',
            '<scale value="0.7"/><rotate x="1" angle="-60"/><rotate z="1" angle="30"/>'),
    "ply": ('<string name="filename" value="meshes/wave.ply"/>',
            '<scale value="0.7"/><rotate x="1" angle="-55"/><rotate y="1" angle="20"/>'),
    "serialized": ('<string name="filename" value="meshes/shapes.serialized"/>',
                   '<scale value="0.7"/><rotate x="1" angle="-55"/><rotate y="1" angle="20"/>'),
}


def shape_scene(kind, params, pose):
    xml = HEADER.format(
        comment=("The %s shape twice: left uv_debug.png on a diffuse, right mirrored "
                 "(scale x = -1) with a twosided normal map over an anisotropic rough "
                 "conductor." % kind),
        width=96, height=48, fov=50, origin="0, 0.9, 4.2", target="0, 0, 0")
    xml += LIGHTS
    for side, bsdf, place in (("left", LEFT, '<translate x="-0.95"/>'),
                              ("right", RIGHT, '<scale x="-1"/><translate x="0.95"/>')):
        xml += '    <!-- %s -->\n    <shape type="%s">\n' % (side, kind)
        if params:
            xml += "        %s\n" % params
        xml += '        <transform name="to_world">%s%s</transform>\n' % (pose, place)
        xml += bsdf + "\n    </shape>\n"
    return xml + "</scene>\n"


def checker_cube():
    xml = HEADER.format(
        comment=("The cube of issue 17: a checkerboard bitmap on a Mitsuba cube, a "
                 "bitmap-textured floor and a bitmap-textured area light."),
        width=64, height=64, fov=40, origin="1.7, 1.3, 2.6", target="0, -0.35, 0")
    xml += """    <shape type="cube">
        <transform name="to_world"><scale value="0.6"/><rotate y="1" angle="35"/><translate y="-0.4"/></transform>
        <bsdf type="diffuse">
            <texture type="bitmap" name="reflectance">
                <string name="filename" value="tex/checker.png"/>
                <string name="filter_type" value="nearest"/>
            </texture>
        </bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/><translate y="-1"/></transform>
        <bsdf type="diffuse">
            <texture type="bitmap" name="reflectance">
                <string name="filename" value="tex/floor.png"/>
            </texture>
        </bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="to_world">
            <scale x="1.2" y="0.6"/>
            <lookat origin="-0.6, 1.6, 1.2" target="0, -0.4, 0" up="0, 1, 0"/>
        </transform>
        <emitter type="area">
            <texture type="bitmap" name="radiance">
                <string name="filename" value="tex/light.png"/>
            </texture>
        </emitter>
    </shape>
    <emitter type="constant">
        <rgb name="radiance" value="0.3"/>
    </emitter>
</scene>
"""
    return xml


def main():
    textures()
    for kind, (params, pose) in SHAPES.items():
        with open(os.path.join(OUT, kind + ".xml"), "w") as f:
            f.write(shape_scene(kind, params, pose))
    with open(os.path.join(OUT, "checker_cube.xml"), "w") as f:
        f.write(checker_cube())
    print("wrote", ", ".join(sorted(os.listdir(OUT))), "in", os.path.relpath(OUT, ROOT))


if __name__ == "__main__":
    main()
