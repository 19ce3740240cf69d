#!/usr/bin/env python3
"""Writes RGL `.bsdf` tensor files (Dupuy and Jakob 2018, "An Adaptive
Parameterization for Efficient Material Acquisition and Rendering"; the format Mitsuba
3's `measured` BSDF reads) tabulated from an analytic model: a GGX conductor with a
Schlick Fresnel term, in the paper's parameterization. No RGL measurement ships with
wavetrace; these stand in for one in the tests (tests/measured_vs_mitsuba.rs).

    python3 tools/make_measured_bsdf.py tests/data/measured_iso.bsdf --alpha 0.3
    python3 tools/make_measured_bsdf.py tests/data/measured_aniso.bsdf \\
        --alpha-u 0.15 --alpha-v 0.4

The fields (Mitsuba 3's src/bsdfs/measured.cpp reads them; shapes row-major, the last
index contiguous):

- `description` (uint8 text), `jacobian` (one uint8: 1),
- `theta_i` [Nθ], `phi_i` [Nφ] (radians): the incident directions tabulated; one
  `phi_i` for an isotropic material; an anisotropic one spans 2π / reduction (here
  [-π, -π/2], reduction 4: the GGX lobe is symmetric in x and y),
- `ndf` [H, W]: D(m) over u = (sqrt(2 θm / π), (φm + π) / 2π) (x = θ, y = φ),
- `sigma` [H, W]: the projected area σ(wi) = cos θi / G1(wi) over the same u,
- `vndf` [Nφ, Nθ, H, W]: the visible normals' density in u (D_wi(m) dω/du), relative
  φm = φm - φi for an isotropic material,
- `luminance` [Nφ, Nθ, N, N] and `rgb` [Nφ, Nθ, 3, N, N]: over the square the VNDF
  warp maps to u (its inverse), the luminance of `rgb` (sampled first) and `rgb` =
  f cos θo / (D / (4 σ)) = F(wi·m) G2 / G1(wi).

The tabulation uses Mitsuba 3's own `MarginalContinuous2D2` for the VNDF warp, so the
tables are consistent with the reader as Mitsuba builds it.
"""
import argparse
import math

import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")

F0 = np.array([0.95, 0.64, 0.54])  # gold-like


def g1(w, au, av):
    if w[2] <= 0:
        return 0.0
    t2 = (au * au * w[0] * w[0] + av * av * w[1] * w[1]) / (w[2] * w[2])
    return 2.0 / (1.0 + math.sqrt(1.0 + t2))


def ndf(m, au, av):
    if m[2] <= 0:
        return 0.0
    x, y, z = m[0] / au, m[1] / av, m[2]
    d = x * x + y * y + z * z
    return 1.0 / (math.pi * au * av * d * d)


def direction(theta, phi):
    return np.array([math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)])


def u2theta(u):
    return u * u * math.pi / 2


def u2phi(u):
    return (2 * u - 1) * math.pi


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out")
    ap.add_argument("--alpha", type=float)
    ap.add_argument("--alpha-u", type=float)
    ap.add_argument("--alpha-v", type=float)
    ap.add_argument("--vndf-res", type=int, default=24, help="W = H of ndf, sigma, vndf")
    ap.add_argument("--res", type=int, default=16, help="N of luminance and rgb")
    ap.add_argument("--theta-i", type=int, default=6)
    ap.add_argument("--phi-i", type=int, default=3, help="anisotropic only")
    a = ap.parse_args()
    iso = a.alpha is not None
    au, av = (a.alpha, a.alpha) if iso else (a.alpha_u, a.alpha_v)
    theta_i = np.radians(np.linspace(0, 75, a.theta_i)).astype(np.float32)
    if iso:
        phi_i = np.array([0.0], np.float32)
    else:
        phi_i = np.linspace(-math.pi, -math.pi / 2, a.phi_i).astype(np.float32)
    R, N = a.vndf_res, a.res
    us = np.linspace(0, 1, R)

    ndf_t = np.zeros((R, R), np.float32)
    sigma_t = np.zeros((R, R), np.float32)
    for y in range(R):
        for x in range(R):
            w = direction(u2theta(us[x]), u2phi(us[y]))
            ndf_t[y, x] = ndf(w, au, av)
            sigma_t[y, x] = w[2] / g1(w, au, av) if w[2] > 1e-7 else 0.0

    vndf = np.zeros((len(phi_i), len(theta_i), R, R), np.float32)
    for p, pi_ in enumerate(phi_i):
        for t, ti in enumerate(theta_i):
            wi = direction(float(ti), float(pi_))
            for y in range(R):
                for x in range(R):
                    th, ph = u2theta(us[x]), u2phi(us[y])
                    m = direction(th, ph + (float(pi_) if iso else 0.0))
                    dwi = g1(wi, au, av) * max(0.0, float(wi @ m)) * ndf(m, au, av) / wi[2]
                    # dω = 2 π² u sin θm du (the paper's Jacobian of u -> m)
                    vndf[p, t, y, x] = dwi * 2 * math.pi ** 2 * us[x] * math.sin(th)

    warp = mi.MarginalContinuous2D2(vndf, [phi_i.tolist(), theta_i.tolist()], normalize=True)
    rgb = np.zeros((len(phi_i), len(theta_i), 3, N, N), np.float32)
    ss = np.linspace(0, 1, N)
    for p, pi_ in enumerate(phi_i):
        for t, ti in enumerate(theta_i):
            wi = direction(float(ti), float(pi_))
            for y in range(N):
                for x in range(N):
                    u, _ = warp.sample(mi.Point2f(ss[x], ss[y]), [float(pi_), float(ti)])
                    th, ph = u2theta(u[0]), u2phi(u[1])
                    m = direction(th, ph + (float(pi_) if iso else 0.0))
                    c = float(wi @ m)
                    wo = 2 * c * m - wi
                    if c <= 0 or wo[2] <= 0:
                        continue
                    g2 = 1.0 / (1.0 / max(g1(wi, au, av), 1e-7) + 1.0 / g1(wo, au, av) - 1.0)
                    f = F0 + (1 - F0) * (1 - c) ** 5
                    rgb[p, t, :, y, x] = f * g2 / g1(wi, au, av)
    lum = (0.2126 * rgb[:, :, 0] + 0.7152 * rgb[:, :, 1] + 0.0722 * rgb[:, :, 2]).astype(np.float32)
    lum = np.maximum(lum, 1e-3).astype(np.float32)

    what = f"GGX conductor alpha=({au}, {av}), Schlick F0={F0.tolist()} (tools/make_measured_bsdf.py)"
    mi.tensor_io.write(
        a.out,
        description=what,
        jacobian=np.array([1], np.uint8),
        theta_i=theta_i,
        phi_i=phi_i,
        ndf=ndf_t,
        sigma=sigma_t,
        vndf=vndf,
        luminance=lum,
        rgb=rgb,
    )


if __name__ == "__main__":
    main()
