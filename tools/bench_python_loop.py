#!/usr/bin/env python3
"""Time per render of a camera loop from Python: wavetrace against Mitsuba 3.

Both renderers load the Cornell box of scenes/cbox/cbox_path.xml once from the same
scene dictionary, then render POSES camera poses, taking turns pose by pose, (an orbit around the box) at SPP
samples per pixel, changing only the camera between renders: wavetrace with
``scene.set_camera`` + ``wt.render``, Mitsuba with ``params['sensor.to_world']``,
``params.update()`` + ``mi.render`` (variant llvm_ad_rgb by default, which needs
DRJIT_LIBLLVM_PATH to name libLLVM; this script sets Debian's libLLVM 19 if it is
there). Each render's time includes getting the image into a NumPy array.

    python3 tools/bench_python_loop.py [--poses 100] [--spp 64] [--res 128]

Prints the median and mean time per render (the first render apart: set-up and JIT
compilation) and the mean relative difference of the two renderers' first images.
"""

import argparse
import glob
import os
import pathlib
import platform
import statistics
import sys
import time

import numpy as np

REPO = pathlib.Path(__file__).resolve().parents[1]
MESHES = REPO / "scenes" / "cbox" / "meshes"
CENTRE = np.array([278.0, 273.0, 280.0])


def look_at(origin, target, up):
    o, t, u = (np.asarray(v, dtype=np.float64) for v in (origin, target, up))
    d = (t - o) / np.linalg.norm(t - o)
    left = np.cross(u, d)
    left /= np.linalg.norm(left)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = left, np.cross(d, left), d, o
    return m


def pose(i, n):
    a = 0.35 * np.sin(2 * np.pi * i / n)
    origin = CENTRE + np.array([1080 * np.sin(a), 60 * np.cos(3 * a), -1080 * np.cos(a)])
    return look_at(origin, CENTRE, [0, 1, 0])


def cbox_dict(res, spp, to_world):
    def mesh(name, bsdf, **extra):
        return {"type": "obj", "filename": str(MESHES / f"{name}.obj"),
                "bsdf": {"type": "ref", "id": bsdf}, **extra}

    def diffuse(r, g, b):
        return {"type": "diffuse", "reflectance": {"type": "rgb", "value": [r, g, b]}}

    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 6},
        "sensor": {
            "type": "perspective", "fov_axis": "smaller", "near_clip": 10.0,
            "far_clip": 2800.0, "fov": 39.3077, "to_world": to_world,
            "sampler": {"type": "independent", "sample_count": spp},
            "film": {"type": "hdrfilm", "width": res, "height": res,
                     "rfilter": {"type": "box"}},
        },
        "white": diffuse(0.725, 0.71, 0.68),
        "red": diffuse(0.63, 0.065, 0.05),
        "green": diffuse(0.14, 0.45, 0.091),
        "light": diffuse(0.78, 0.78, 0.78),
        "floor": mesh("floor", "white"),
        "ceiling": mesh("ceiling", "white"),
        "back": mesh("back", "white"),
        "greenwall": mesh("greenwall", "green"),
        "redwall": mesh("redwall", "red"),
        "lamp": mesh("light", "light", emitter={
            "type": "area", "radiance": {"type": "rgb", "value": [17, 12, 4]}}),
        "shortbox": mesh("shortbox", "white"),
        "tallbox": mesh("tallbox", "white"),
    }


def setup_wavetrace(args):
    import wavetrace as wt

    scene = wt.load_dict(cbox_dict(args.res, args.spp, pose(0, args.poses)))

    def render(i):
        scene.set_camera(to_world=pose(i, args.poses))
        t = time.perf_counter()
        image = np.asarray(wt.render(scene, spp=args.spp, seed=i))
        return time.perf_counter() - t, image

    return render, f"wavetrace ({wt.devices()[0]['name']})"


def setup_mitsuba(args):
    if "DRJIT_LIBLLVM_PATH" not in os.environ:
        found = sorted(glob.glob("/usr/lib/*/libLLVM.so.19*") + glob.glob("/usr/lib/*/libLLVM-19.so"))
        if found:
            os.environ["DRJIT_LIBLLVM_PATH"] = found[0]
    import mitsuba as mi

    mi.set_variant(args.variant)
    T = lambda m: mi.ScalarTransform4f(m.tolist())  # noqa: E731
    scene = mi.load_dict(cbox_dict(args.res, args.spp, T(pose(0, args.poses))))
    params = mi.traverse(scene)

    def render(i):
        params["sensor.to_world"] = T(pose(i, args.poses))
        params.update()
        t = time.perf_counter()
        image = np.array(mi.render(scene, params, spp=args.spp, seed=i))
        return time.perf_counter() - t, image

    return render, f"Mitsuba {mi.__version__} {args.variant}"


def report(name, times):
    rest = times[1:] or times
    print(
        f"{name}: first render {times[0] * 1e3:.0f} ms; then per render median "
        f"{statistics.median(rest) * 1e3:.1f} ms, mean {statistics.mean(rest) * 1e3:.1f} ms, "
        f"min {min(rest) * 1e3:.1f} ms, max {max(rest) * 1e3:.1f} ms over {len(rest)} renders"
    )


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--poses", type=int, default=100)
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--res", type=int, default=128)
    p.add_argument("--variant", default="llvm_ad_rgb")
    p.add_argument("--skip-mitsuba", action="store_true")
    p.add_argument("-v", "--verbose", action="store_true", help="print every render's time")
    args = p.parse_args()
    cpuinfo = open("/proc/cpuinfo").read()
    flags = cpuinfo.split("flags")[1].split("\n")[0].split()
    model = next((l.split(":", 1)[1].strip() for l in cpuinfo.splitlines()
                  if l.startswith("model name")), platform.machine())
    simd = [f for f in ("sse4_2", "avx", "avx2", "fma", "avx512f") if f in flags]
    print(f"host: {model}, {os.cpu_count()} CPUs, "
          f"vector extensions {' '.join(simd)}; Cornell box {args.res}x{args.res}, "
          f"{args.spp} spp, {args.poses} poses", flush=True)
    loops = [setup_wavetrace(args)]
    if not args.skip_mitsuba:
        loops.append(setup_mitsuba(args))
    # The renderers take turns pose by pose, so that both see the same load of a
    # shared machine.
    times = [[] for _ in loops]
    firsts = [None for _ in loops]
    for i in range(args.poses):
        for k, (render, _) in enumerate(loops):
            t, image = render(i)
            times[k].append(t)
            if args.verbose:
                print(f"pose {i} {loops[k][1]}: {t * 1e3:.0f} ms", flush=True)
            if firsts[k] is None:
                firsts[k] = image.copy()
    for (_, name), ts in zip(loops, times):
        report(name, ts)
    if len(loops) == 2:
        means = [f[:, :, :3].mean(axis=(0, 1)) for f in firsts]
        print(f"first pose: mean RGB wavetrace {means[0]}, Mitsuba {means[1]}")
        print(f"ratio of median times (Mitsuba / wavetrace): "
              f"{statistics.median(times[1][1:]) / statistics.median(times[0][1:]):.2f}")


if __name__ == "__main__":
    sys.exit(main())
