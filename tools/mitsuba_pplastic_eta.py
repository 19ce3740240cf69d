#!/usr/bin/env python3
"""Mitsuba 3's eval and pdf of `pplastic` BSDFs whose `eta` is a texture (or an RGB
value), the reference of tests/pplastic_vs_mitsuba.rs's textured-eta test.

    python3 tools/mitsuba_pplastic_eta.py   # writes tests/data/pplastic_eta/

Writes tests/data/pplastic_eta/eta.exr (8 x 8 linear RGB, a ramp plus a hash, channels
apart so that luminance, mean and any one channel differ; eta from about 0.6 to 2.2,
below and above 1), then evaluates each case of CASES, an XML `<bsdf>` that the test
loads with wavetrace's loader as it is, at random uv and (wo, wi) pairs in Mitsuba
3.9.1 `scalar_rgb` (single precision). Directions as tools/mitsuba_pairs.py says (`wo`
towards the viewer, `wi` towards the light, local frame, f32). Beside each value:
the eta Mitsuba's pplastic reads there, `eval_1` of its eta texture (Mitsuba's
pplastic.cpp calls m_eta->eval_1(si) in eval; pdf and the lobe weights do not read
eta), and the texture's RGB there, so a failing test says whether the lookup or the
model differs.

What Mitsuba 3.9.1 does with a textured eta (src/bsdfs/pplastic.cpp,
get_unbounded_texture("eta")): a bitmap's eval_1 is the luminance of its RGB
(0.212671, 0.715160, 0.072169); a checkerboard's is its colors' eval_1 with the squares
of eval swapped; an `rgb` value's is the mean of its channels. eta is used as it is
(no check): 1 turns the Fresnel terms off, below 1 reflects totally beyond the
critical angle.
"""
import json
import os
import random

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")

from mitsuba_pairs import textured_query  # noqa: E402

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data",
                    "pplastic_eta")

# name, the <bsdf> as wavetrace and Mitsuba both read it (eta.exr next to the scene).
CASES = [
    ("bitmap eta, ggx α 0.3", """<bsdf type="pplastic">
    <string name="distribution" value="ggx"/><float name="alpha" value="0.3"/>
    <rgb name="diffuse_reflectance" value="0.3, 0.1, 0.5"/>
    <texture type="bitmap" name="eta"><string name="filename" value="eta.exr"/></texture>
</bsdf>"""),
    ("bitmap eta, beckmann 0.08 / 0.3, specular 0.8", """<bsdf type="pplastic">
    <float name="alpha_u" value="0.08"/><float name="alpha_v" value="0.3"/>
    <boolean name="sample_visible" value="false"/>
    <rgb name="specular_reflectance" value="0.8, 0.7, 0.9"/>
    <texture type="bitmap" name="eta"><string name="filename" value="eta.exr"/>
        <transform name="to_uv"><scale x="2" y="3"/></transform></texture>
</bsdf>"""),
    ("checkerboard eta 0.75 / 1.6, ggx α 0.2", """<bsdf type="pplastic">
    <string name="distribution" value="ggx"/><float name="alpha" value="0.2"/>
    <rgb name="diffuse_reflectance" value="0.1, 0.4, 0.2"/>
    <texture type="checkerboard" name="eta"><float name="color0" value="0.75"/>
        <float name="color1" value="1.6"/>
        <transform name="to_uv"><scale value="3"/></transform></texture>
</bsdf>"""),
    ("rgb eta 1.2, 1.5, 1.9, ggx α 0.15", """<bsdf type="pplastic">
    <string name="distribution" value="ggx"/><float name="alpha" value="0.15"/>
    <rgb name="eta" value="1.2, 1.5, 1.9"/>
</bsdf>"""),
]


def write_texture():
    n = 8
    eta = np.zeros((n, n, 3), dtype=np.float32)
    for y in range(n):
        for x in range(n):
            h = ((x * 73856093) ^ (y * 19349663)) % 1000 / 1000.0
            for c in range(3):
                t = (x / (n - 1)) * (0.5 + 0.3 * c) + (y / (n - 1)) * (0.6 - 0.25 * c)
                eta[y, x, c] = 0.6 + 1.6 * (t + 0.3 * h) / 1.7
    mi.Bitmap(eta).write(os.path.join(HERE, "eta.exr"))


def load(xml):
    return mi.load_string(xml.replace('<bsdf type="pplastic">',
                                      '<bsdf version="3.0.0" type="pplastic">', 1))


def main():
    os.makedirs(HERE, exist_ok=True)
    write_texture()
    mi.file_resolver().prepend(HERE)
    rng = random.Random(3939)
    ctx = mi.BSDFContext()
    cases = []
    for name, xml in CASES:
        bsdf = load(xml)
        values = []
        for _ in range(48):
            uv, wo, wi, si, e, p = textured_query(rng, bsdf, ctx)
            values.append({"uv": uv, "wo": wo, "wi": wi, "eval": e, "pdf": p,
                           "eta": eta_at(xml, si), "eta_rgb": eta_rgb_at(xml, si)})
        cases.append({"name": name, "xml": xml, "values": values})
    with open(os.path.join(HERE, "values.json"), "w") as f:
        json.dump({"mitsuba": mi.__version__, "variant": mi.variant(), "cases": cases}, f,
                  indent=1)


_eta_textures = {}


def eta_at(xml, si):
    """eval_1 of the case's eta (a texture, or the rgb value's srgb texture) at si."""
    if xml not in _eta_textures:
        start = xml.find('<texture type=')
        if start >= 0:
            body = xml[start:xml.find('</texture>', start) + len('</texture>')]
            body = body.replace(' name="eta"', '', 1).replace('<texture ', '<texture version="3.0.0" ', 1)
        else:
            start = xml.find('<rgb name="eta"')
            value = xml[start:].split('value="')[1].split('"')[0]
            body = f'<spectrum version="3.0.0" type="srgb"><rgb name="color" value="{value}"/><boolean name="unbounded" value="true"/></spectrum>'
        _eta_textures[xml] = mi.load_string(body)
    return float(_eta_textures[xml].eval_1(si))


def eta_rgb_at(xml, si):
    """The RGB of the case's eta texture at si (its eval), or the rgb value."""
    eta_at(xml, si)
    c = _eta_textures[xml].eval(si)
    return [float(c[i]) for i in range(3)]


if __name__ == "__main__":
    main()
