#!/usr/bin/env python3
"""The value of an irradiancemeter scene's 1 x 1 film under Mitsuba 3 and its noise:
N renders of S samples each (seeds 0 .. N-1), printed as JSON with the mean and the
standard error of the mean per channel (the spread of the N renders over sqrt N).

    python3 tools/mitsuba_irradiancemeter.py SCENE.xml [-D NAME=VALUE] [--renders N]
        [--spp S] [--variant scalar_rgb]
"""
import argparse
import json

import mitsuba as mi
import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene")
    ap.add_argument("-D", action="append", default=[], metavar="NAME=VALUE",
                    help="a scene parameter ($NAME)")
    ap.add_argument("--renders", type=int, default=16)
    ap.add_argument("--spp", type=int, default=65536)
    ap.add_argument("--variant", default="scalar_rgb")
    args = ap.parse_args()
    mi.set_variant(args.variant)
    params = dict(d.split("=", 1) for d in args.D)
    scene = mi.load_file(args.scene, **params)
    values = []
    for seed in range(args.renders):
        img = np.array(mi.render(scene, seed=seed, spp=args.spp), dtype=np.float64)
        assert img.shape[:2] == (1, 1), "a 1 x 1 film"
        values.append(img.reshape(-1)[:3])
    values = np.array(values)
    mean = values.mean(axis=0)
    stderr = values.std(axis=0, ddof=1) / np.sqrt(len(values))
    print(json.dumps({
        "scene": args.scene, "defines": params, "mitsuba": mi.__version__,
        "variant": args.variant, "renders": args.renders, "spp": args.spp,
        "mean": mean.tolist(), "stderr": stderr.tolist(),
    }, indent=1))


if __name__ == "__main__":
    main()
