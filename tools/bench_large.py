#!/usr/bin/env python3
"""Large-scene benchmark: loading, BVH build and rendering of height fields of 1, 8
and 30 M triangles, next to Mitsuba 3 loading the same files (docs/performance.md, "Large scenes").

    python3 tools/bench_large.py [--sizes 1M,8M,30M] [--dir target/large] [--runs 2]
                                 [--wavetrace target/release/wavetrace] [--variant scalar_rgb]
                                 [--res 256] [--spp 16] [--no-render] [--no-obj] [--json OUT.json]

For each size: makes the mesh with tools/make_heightfield.py if missing (binary PLY,
and the same mesh as a text OBJ unless --no-obj), then
- `wavetrace info`: load time, BVH build time, SAH cost and the build's peak memory
  above the loaded scene (wavetrace measures it from /proc/self), and the process's
  peak resident memory and CPU time (user + system);
- the load time of the OBJ, and the speed of reading each file from the page cache
  (the file read once before, then timed: the disk's best case);
- Mitsuba 3 `load_file` of the same scene (it reads the PLY and builds its own
  acceleration structure), wall time and peak memory;
- `wavetrace render` at --res x --res and --spp samples: rays/s and peak memory.
Each timing is the fastest of --runs runs (the machine may be shared; runs wait on
/work/coord/bench.lock when it exists, so concurrent benchmarks do not overlap).
A 30 M-triangle render needs about 7 GB of memory.
"""

import argparse
import json
import os
import re
import subprocess
import sys
import time

TOOLS = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(TOOLS)
LOCK = "/work/coord/bench.lock"
LIBLLVM = "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"

MITSUBA_LOAD = """
import sys, time
import mitsuba as mi
mi.set_variant(sys.argv[2])
t = time.time()
mi.load_file(sys.argv[1])
print("seconds %.4f" % (time.time() - t))
"""


def die(msg):
    sys.exit("bench_large.py: " + msg)


def run(cmd, env=None):
    """Runs cmd under /usr/bin/time (and the bench lock): (stdout+stderr, peak KiB)."""
    wrapped = ["/usr/bin/time", "-f", "PEAK_KIB %M CPU_S %U %S"] + cmd
    if os.path.exists(os.path.dirname(LOCK)):
        wrapped = ["flock", LOCK] + wrapped
    p = subprocess.run(wrapped, capture_output=True, text=True, env=env)
    out = p.stdout + p.stderr
    if p.returncode != 0:
        die("%s failed:\n%s" % (" ".join(cmd), out[-3000:]))
    m = re.search(r"PEAK_KIB (\d+) CPU_S ([\d.]+) ([\d.]+)", out)
    return out, int(m.group(1)), float(m.group(2)) + float(m.group(3))


def cached_read_speed(path):
    """Bytes per second reading `path` from the page cache (one read to fill it)."""
    best = None
    for _ in range(3):
        t = time.time()
        with open(path, "rb", buffering=0) as f:
            while f.read(1 << 24):
                pass
        dt = time.time() - t
        best = dt if best is None else min(best, dt)
    return os.path.getsize(path) / best


def number(pattern, text, what):
    m = re.search(pattern, text)
    if not m:
        die("no %s in:\n%s" % (what, text[-3000:]))
    return float(m.group(1))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", default="1M,8M,30M")
    ap.add_argument("--dir", default=os.path.join(ROOT, "target", "large"))
    ap.add_argument("--runs", type=int, default=2)
    ap.add_argument("--wavetrace", default=os.path.join(ROOT, "target", "release", "wavetrace"))
    ap.add_argument("--variant", default="scalar_rgb")
    ap.add_argument("--res", type=int, default=256)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--no-render", action="store_true")
    ap.add_argument("--no-obj", action="store_true", help="skip the OBJ load")
    ap.add_argument("--json")
    args = ap.parse_args()
    if not os.path.isfile(args.wavetrace):
        die("%s not found (cargo build --release)" % args.wavetrace)
    env = dict(os.environ)
    if args.variant.startswith("llvm") and os.path.isfile(LIBLLVM):
        env.setdefault("DRJIT_LIBLLVM_PATH", LIBLLVM)
    rows = []
    for size in args.sizes.split(","):
        base = os.path.join(args.dir, "hf" + size.lower())
        if not os.path.isfile(base + ".ply"):
            subprocess.run([sys.executable, os.path.join(TOOLS, "make_heightfield.py"),
                            "--triangles", size, "-o", base], check=True)
        if not args.no_obj and not os.path.isfile(base + ".obj"):
            subprocess.run([sys.executable, os.path.join(TOOLS, "make_heightfield.py"),
                            "--triangles", size, "-o", base, "--obj"], check=True)
        scene = base + ".xml"
        row = {"size": size, "ply_bytes": os.path.getsize(base + ".ply"),
               "ply_cached_read_bps": cached_read_speed(base + ".ply")}
        best = None
        for _ in range(args.runs):
            out, peak, cpu = run([args.wavetrace, "info", scene])
            r = {
                "triangles": int(number(r"triangles:\s+(\d+)", out, "triangle count")),
                "load_s": number(r"loaded in ([\d.]+) ms", out, "load time") / 1e3,
                "bvh_s": number(r"built in ([\d.]+) ms", out, "BVH time") / 1e3,
                "sah_cost": number(r"SAH cost ([\d.]+)", out, "SAH cost"),
                "bvh_peak_bytes": number(r"build peak ([\d.]+) MiB", out, "BVH peak") * 2**20,
                "info_peak_bytes": peak * 1024,
                "info_cpu_s": cpu,
            }
            if best is None or r["load_s"] + r["bvh_s"] < best["load_s"] + best["bvh_s"]:
                best = r
        row.update(best)
        if not args.no_obj:
            row["obj_bytes"] = os.path.getsize(base + ".obj")
            row["obj_cached_read_bps"] = cached_read_speed(base + ".obj")
            obj_load = None
            for _ in range(args.runs):
                out, _, _ = run([args.wavetrace, "info", base + "_obj.xml"])
                t = number(r"loaded in ([\d.]+) ms", out, "load time") / 1e3
                obj_load = t if obj_load is None else min(obj_load, t)
            row["obj_load_s"] = obj_load
        mi = None
        for _ in range(args.runs):
            out, peak, cpu = run([sys.executable, "-c", MITSUBA_LOAD, scene, args.variant],
                                 env=env)
            r = {"mitsuba_load_s": number(r"seconds ([\d.]+)", out, "Mitsuba time"),
                 "mitsuba_peak_bytes": peak * 1024, "mitsuba_cpu_s": cpu}
            if mi is None or r["mitsuba_load_s"] < mi["mitsuba_load_s"]:
                mi = r
        row.update(mi)
        if not args.no_render:
            rend = None
            for _ in range(args.runs):
                out, peak, _ = run([args.wavetrace, "render", scene, "-D", "res=%d" % args.res,
                                 "--spp", str(args.spp), "-q", "-o",
                                 os.path.join(args.dir, "out_%s.exr" % size.lower())])
                r = {"render_s": number(r"rendered in ([\d.]+) s", out, "render time"),
                     "mrays_per_s": number(r"([\d.]+) M rays/s", out, "rays/s"),
                     "render_peak_bytes": peak * 1024}
                if rend is None or r["render_s"] < rend["render_s"]:
                    rend = r
            row.update(rend)
        rows.append(row)
        n = row["triangles"]
        mb = lambda b, s: b / s / 1e6
        loads = "PLY %.2f s (%.0f MB/s; cached read %.0f MB/s)" % (
            row["load_s"], mb(row["ply_bytes"], row["load_s"]), row["ply_cached_read_bps"] / 1e6)
        if not args.no_obj:
            loads += ", OBJ %.2f s (%.0f MB/s; cached read %.0f MB/s)" % (
                row["obj_load_s"], mb(row["obj_bytes"], row["obj_load_s"]),
                row["obj_cached_read_bps"] / 1e6)
        print("%s: %d triangles; wavetrace load %s; BVH %.2f s (SAH %.2f, build peak %.0f "
              "bytes/triangle), info peak %.2f GB, CPU %.1f s; Mitsuba %s load %.2f s, peak "
              "%.2f GB, CPU %.1f s%s"
              % (size, n, loads, row["bvh_s"], row["sah_cost"],
                 row["bvh_peak_bytes"] / n, row["info_peak_bytes"] / 1e9, row["info_cpu_s"],
                 args.variant, row["mitsuba_load_s"], row["mitsuba_peak_bytes"] / 1e9,
                 row["mitsuba_cpu_s"],
                 "" if args.no_render else "; render %d^2 x %d spp %.2f s, %.2f M rays/s, "
                 "peak %.2f GB" % (args.res, args.spp, row["render_s"], row["mrays_per_s"],
                                   row["render_peak_bytes"] / 1e9)),
              flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"date": time.strftime("%Y-%m-%d"), "variant": args.variant,
                       "rows": rows}, f, indent=2)


if __name__ == "__main__":
    main()
