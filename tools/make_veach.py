#!/usr/bin/env python3
"""Write scenes/veach/veach.xml: a scene in the spirit of Veach's multiple importance
sampling test (Veach 1997, PhD thesis, fig. 9.2), built from scratch.

    python3 tools/make_veach.py        # writes scenes/veach/veach.xml

Four metal plates, from smooth (top, farthest) to rough (bottom, nearest), reflect
four spherical lights of increasing radius and equal power. Each plate is tilted so
that the mirror direction of a camera ray through its centre points at the middle of
the row of lights: the lights' reflections then lie across every plate, and each
plate shows four highlights whose size depends on both the light's radius and the
plate's roughness. Sampling the lights wins on rough plates and large lights,
sampling the BSDF on smooth plates and small lights; MIS must do well everywhere.

Numbers (world units, y up):
- camera at (0, 2.5, 11) looking at (0, 2.3, 0), 45 degree horizontal field of view;
- plates 8 x 1 (half-extents 4 x 0.5), centres (0, 1.35 - 0.6 i, -1.2 + 1.2 i) for
  i = 0..3, `roughconductor` (GGX) with aluminium's RGB eta/k and alpha
  0.005, 0.02, 0.05, 0.1 (i = 0 smoothest);
- lights: `sphere` shapes at x = -3.6, -1.2, 1.2, 3.6, y = 6, z = -2.5, radius
  0.05, 0.15, 0.4, 0.9 (left to right), radiance scale 1 / r^2 times a tint whose
  channels average 1, so every light emits the same power: a sphere of radius r and
  radiance L emits pi L 4 pi r^2 = 4 pi^2 (L r^2);
  the spheres' own BSDF is black so they only emit;
- a dark diffuse backdrop (reflectance 0.1): a floor at y = -1.2 and a wall at z = -6.

Scene parameters (Mitsuba's `<default>`, `-D name=value` in wavetrace and in
tools/mitsuba_ref.py): `integrator` (default `direct`, Mitsuba's MIS direct lighting;
`path` for path tracing), `max_depth` (default 4, used by `path`), `res` (128) and
`spp` (64). One file serves both integrators through
`<include filename="integrator_$integrator.xml"/>`: Mitsuba's `direct` refuses a
`max_depth` it does not read, so each integrator's element lives in its own small
file (integrator_direct.xml, integrator_path.xml) and the parameter picks the file.
"""

import math
import os

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
OUT = os.path.join(ROOT, "scenes", "veach")

CAMERA = (0.0, 2.5, 11.0)
TARGET = (0.0, 2.3, 0.0)
FOV = 45.0

PLATE_HALF = (4.0, 0.5)
ALPHAS = (0.005, 0.02, 0.05, 0.1)
AL_ETA = "1.65746, 0.880369, 0.521229"
AL_K = "9.22387, 6.26952, 4.837"

LIGHT_Y, LIGHT_Z = 6.0, -2.5
LIGHT_X = (-3.6, -1.2, 1.2, 3.6)
RADII = (0.05, 0.15, 0.4, 0.9)
TINTS = ((1.3, 0.9, 0.8), (0.8, 1.3, 0.9), (0.8, 0.9, 1.3), (1.1, 1.1, 0.8))
POWER = 1.0  # L r^2


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def add(a, b):
    return tuple(x + y for x, y in zip(a, b))


def scale(a, s):
    return tuple(x * s for x in a)


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normalize(v):
    return scale(v, 1.0 / math.sqrt(dot(v, v)))


def plate_center(i):
    return (0.0, 1.35 - 0.6 * i, -1.2 + 1.2 * i)


def plate_matrix(i):
    """to_world of Mitsuba's `rectangle` ([-1,1]^2 at z = 0, normal +z) for plate i:
    x stays x (the plate's long side), z becomes the half vector between the
    directions to the camera and to the middle of the lights, y completes the frame."""
    c = plate_center(i)
    light = (0.0, LIGHT_Y, LIGHT_Z)
    n = normalize(add(normalize(sub(CAMERA, c)), normalize(sub(light, c))))
    x = (1.0, 0.0, 0.0)
    y = normalize(cross(n, x))
    cols = (scale(x, PLATE_HALF[0]), scale(y, PLATE_HALF[1]), n)
    rows = [[cols[0][r], cols[1][r], cols[2][r], c[r]] for r in range(3)] + [[0, 0, 0, 1]]
    return ", ".join("%.6g" % v for row in rows for v in row)


def fmt(v):
    return ", ".join("%.6g" % x for x in v)


INTEGRATORS = {
    "direct": '<integrator type="direct"/>',
    "path": """<integrator type="path">
        <integer name="max_depth" value="$max_depth"/>
    </integrator>""",
}


def integrator_xml(name):
    return """<!-- The integrator of veach.xml when integrator=%s; written by tools/make_veach.py. -->
<scene version="3.0.0">
    %s
</scene>
""" % (name, INTEGRATORS[name])


def scene_xml():
    plates = []
    for i, alpha in enumerate(ALPHAS):
        plates.append(
            """    <shape type="rectangle">
        <!-- plate %d: alpha %g -->
        <transform name="to_world">
            <matrix value="%s"/>
        </transform>
        <bsdf type="roughconductor">
            <string name="distribution" value="ggx"/>
            <float name="alpha" value="%g"/>
            <rgb name="eta" value="%s"/>
            <rgb name="k" value="%s"/>
        </bsdf>
    </shape>"""
            % (i, alpha, plate_matrix(i), alpha, AL_ETA, AL_K)
        )
    lights = []
    for x, r, tint in zip(LIGHT_X, RADII, TINTS):
        radiance = scale(tint, POWER / (r * r))
        lights.append(
            """    <shape type="sphere">
        <point name="center" value="%s"/>
        <float name="radius" value="%g"/>
        <ref id="black"/>
        <emitter type="area">
            <rgb name="radiance" value="%s"/>
        </emitter>
    </shape>"""
            % (fmt((x, LIGHT_Y, LIGHT_Z)), r, fmt(radiance))
        )
    return """<!-- Veach's MIS scene rebuilt (Mitsuba 3 dialect, RGB); written by tools/make_veach.py. -->
<scene version="3.0.0">
    <default name="integrator" value="direct"/>
    <default name="max_depth" value="4"/>
    <default name="res" value="128"/>
    <default name="spp" value="64"/>

    <include filename="integrator_$integrator.xml"/>

    <sensor type="perspective">
        <float name="fov" value="%g"/>
        <transform name="to_world">
            <lookat origin="%s" target="%s" up="0, 1, 0"/>
        </transform>
        <sampler type="independent">
            <integer name="sample_count" value="$spp"/>
        </sampler>
        <film type="hdrfilm">
            <integer name="width" value="$res"/>
            <integer name="height" value="$res"/>
            <rfilter type="box"/>
        </film>
    </sensor>

    <bsdf type="diffuse" id="backdrop">
        <rgb name="reflectance" value="0.1"/>
    </bsdf>
    <bsdf type="diffuse" id="black">
        <rgb name="reflectance" value="0"/>
    </bsdf>

    <!-- backdrop: floor (y = -1.2) and back wall (z = -6) -->
    <shape type="rectangle">
        <transform name="to_world">
            <scale value="20"/>
            <rotate x="1" angle="-90"/>
            <translate value="0, -1.2, 0"/>
        </transform>
        <ref id="backdrop"/>
    </shape>
    <shape type="rectangle">
        <transform name="to_world">
            <scale value="20"/>
            <translate value="0, 0, -6"/>
        </transform>
        <ref id="backdrop"/>
    </shape>

%s

%s
</scene>
""" % (FOV, fmt(CAMERA), fmt(TARGET), "\n".join(plates), "\n".join(lights))


def main():
    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, "veach.xml"), "w") as f:
        f.write(scene_xml())
    for name in INTEGRATORS:
        with open(os.path.join(OUT, "integrator_%s.xml" % name), "w") as f:
            f.write(integrator_xml(name))
    print("wrote %s" % os.path.relpath(OUT, ROOT))


if __name__ == "__main__":
    main()
