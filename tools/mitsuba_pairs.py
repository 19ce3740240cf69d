"""(wo, wi) direction pairs and Mitsuba 3's BSDF eval and pdf at them: what the
tools/mitsuba_*_values.py scripts share (each draws its own pairs with these
helpers and writes the JSON that tests/common/mitsuba_values.rs reads).

Directions follow wavetrace's convention: `wo` towards the viewer (Mitsuba's
`si.wi`), `wi` towards the light (the `wo` argument of Mitsuba's `eval`/`pdf`), both
in the local frame, rounded to f32 before Mitsuba sees them. The scripts set the
variant (`scalar_rgb`) before calling these.
"""
import json
import math
import struct

import mitsuba as mi


def RGB(*v):
    """A Mitsuba RGB dictionary."""
    return {"type": "rgb", "value": list(v)}


def f32(x):
    """`x` rounded to single precision."""
    return struct.unpack("f", struct.pack("f", x))[0]


def unit(v):
    """`v` normalized, each component rounded to f32."""
    n = math.sqrt(sum(c * c for c in v))
    return [f32(c / n) for c in v]


def direction(rng, lower=False, mu_min=0.02, phi_range=(0.0, 2.0 * math.pi)):
    """A direction of the upper (or `lower`) hemisphere: cos θ uniform in
    [mu_min, 1], φ uniform in `phi_range`."""
    mu = rng.uniform(mu_min, 1.0)
    phi = rng.uniform(*phi_range)
    s = math.sqrt(1.0 - mu * mu)
    return unit([s * math.cos(phi), s * math.sin(phi), -mu if lower else mu])


def textured_query(rng, bsdf, ctx, mu_min=0.02):
    """A random uv and (wo, wi) pair for a BSDF with textured parameters (`wi` near
    the mirror direction half the time; directions as `direction` with `mu_min`), the
    surface interaction there and Mitsuba's eval (RGB, cosine-weighted) and pdf of
    `bsdf` at it: (uv, wo, wi, si, eval, pdf)."""
    uv = [f32(rng.uniform(0.0, 1.0)), f32(rng.uniform(0.0, 1.0))]
    wo = direction(rng, mu_min=mu_min)
    if rng.random() < 0.5:  # near the mirror direction
        wi = unit([-wo[0] + rng.gauss(0, 0.3), -wo[1] + rng.gauss(0, 0.3), wo[2]])
    else:
        wi = direction(rng, mu_min=mu_min)
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(wo)
    si.uv = mi.Point2f(uv)
    e = bsdf.eval(ctx, si, mi.Vector3f(wi))
    p = bsdf.pdf(ctx, si, mi.Vector3f(wi))
    return uv, wo, wi, si, [float(e[i]) for i in range(3)], float(p)


def eval_pdf(bsdf, ctx, wo, wi, uv=(0.5, 0.5)):
    """Mitsuba's eval (RGB, cosine-weighted) and pdf (solid angle) of `bsdf` at
    (wo, wi), at the surface coordinates `uv`."""
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(wo)
    si.uv = mi.Point2f(*uv)
    e = bsdf.eval(ctx, si, mi.Vector3f(wi))
    p = bsdf.pdf(ctx, si, mi.Vector3f(wi))
    return [float(e[0]), float(e[1]), float(e[2])], float(p)


def values(bsdf, pairs, uv=(0.5, 0.5)):
    """The `values` of a case: each pair with Mitsuba's eval and pdf there."""
    ctx = mi.BSDFContext()
    out = []
    for wo, wi in pairs:
        e, p = eval_pdf(bsdf, ctx, wo, wi, uv)
        out.append({"wo": wo, "wi": wi, "eval": e, "pdf": p})
    return out


def print_cases(cases, indent=1):
    """Prints the file: Mitsuba's version and variant, and the cases."""
    print(json.dumps({"mitsuba": mi.__version__, "variant": mi.variant(), "cases": cases},
                     indent=indent))
