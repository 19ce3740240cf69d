#!/usr/bin/env python3
"""Error against time of wavetrace's `sppm`, wavetrace's `path_mis` and Mitsuba 3's
`path` on one scene, in one run (issue 13, item 4).

    python3 tools/photon_curves.py SCENE.xml --ref REF.exr
        [--sppm 16,32,64,128,256] [--path 64,256,1024,4096] [--mitsuba 64,256,1024,4096]
        [--variant llvm_ad_rgb] [--max-depth -1] [-D name=value] [--seed S]
        [--wavetrace BIN] [--json OUT.json]

Each curve is a list of (seconds, MSE, relMSE) points against the same reference:
`sppm` at the given iteration counts and `path_mis` at the given sample counts through
`wavetrace bench` (times exclude scene loading and kernel compilation; each count is a
render from scratch), Mitsuba's `path` (`max_depth` from --max-depth, default -1) at
the given sample counts as tools/bench_compare.py times it (scene loaded and warmed up
first; the LLVM variants render each count twice and time the second run). The scene
file's own integrator must be `sppm`.

Printed: the three curves, and for every `sppm` point the time `path_mis` and Mitsuba
need to reach its MSE and its relMSE (log-log interpolation along their curves, `*`
where it had to extend an end segment). Ratios above 1: sppm reaches that error
sooner. Timings on a shared machine vary by 10-20%: compare runs made back to back.
"""

import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_compare  # noqa: E402  (same folder)
import mitsuba_ref  # noqa: E402


def time_to_reach(rows, key, target):
    """Time at which a curve reaches `key` (mse or rel_mse) = target, by log-log
    interpolation (bench_compare.time_for_error on another metric)."""
    renamed = [{"seconds": r["seconds"], "rel_mse": r[key]} for r in rows]
    return bench_compare.time_for_error(renamed, target)


def wavetrace_curve(args, integrator, counts):
    ns = argparse.Namespace(
        wavetrace=args.wavetrace, scene=args.scene, ref=args.ref, seed=args.seed,
        defines=args.defines, integrator=integrator, sampler=None, device=args.device)
    report = bench_compare.run_wavetrace(ns, counts)
    rows = [{"spp": r["spp"], "seconds": r["seconds"], "mse": r["rmse"] ** 2,
             "rel_mse": r["rel_mse"], "photons": r.get("photons")} for r in report["rows"]]
    return report, rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene", help="scene file (Mitsuba 3 dialect) whose integrator is sppm")
    ap.add_argument("--ref", required=True, help="reference EXR")
    ap.add_argument("--sppm", default="16,32,64,128,256", help="sppm iteration counts")
    ap.add_argument("--path", default="64,256,1024,4096", help="path_mis sample counts")
    ap.add_argument("--mitsuba", default="64,256,1024,4096", help="Mitsuba path sample counts")
    ap.add_argument("--variant", default="llvm_ad_rgb", help="Mitsuba variant (default llvm_ad_rgb)")
    ap.add_argument("--max-depth", type=int, default=-1, help="Mitsuba path max_depth (default -1)")
    ap.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE",
                    help="scene parameter, passed to both renderers")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--wavetrace", help="wavetrace binary (default: target/, release first)")
    ap.add_argument("--device", help="wavetrace --device")
    ap.add_argument("--json", help="write the curves here")
    args = ap.parse_args()
    try:
        defines = mitsuba_ref.parse_defines(args.defines)
    except ValueError as e:
        bench_compare.die(str(e))
    for path in (args.scene, args.ref):
        if not os.path.isfile(path):
            bench_compare.die("%s: no such file" % path)

    sppm_report, sppm = wavetrace_curve(args, None, bench_compare.parse_spp(args.sppm))
    if sppm_report["integrator"] != "sppm":
        bench_compare.die("%s renders with %s, not sppm" % (args.scene, sppm_report["integrator"]))
    path_report, path = wavetrace_curve(args, "path_mis", bench_compare.parse_spp(args.path))
    mi_args = argparse.Namespace(
        scene=args.scene, ref=args.ref, seed=args.seed, variant=args.variant,
        integrator="path_mis", max_depth=args.max_depth, mitsuba_sampler=None)
    theirs = bench_compare.run_mitsuba(mi_args, bench_compare.parse_spp(args.mitsuba), defines)
    mitsuba = [{"spp": r["spp"], "seconds": r["seconds"], "mse": r["mse"], "rel_mse": r["rel_mse"]}
               for r in theirs["rows"]]

    print("scene %s (%dx%d), reference %s; wavetrace on %s; Mitsuba %s %s: %s" % (
        args.scene, sppm_report["width"], sppm_report["height"], args.ref, sppm_report["device"],
        theirs["version"], theirs["variant"], theirs["integrator"]))
    for name, rows, unit in (("wavetrace sppm", sppm, "iterations"),
                             ("wavetrace path_mis", path, "spp"),
                             ("Mitsuba path", mitsuba, "spp")):
        print("%s:" % name)
        print("  %10s %10s %12s %12s" % (unit, "seconds", "MSE", "relMSE"))
        for r in rows:
            print("  %10d %10.3f %12.4e %12.4e" % (r["spp"], r["seconds"], r["mse"], r["rel_mse"]))
    print("time to reach sppm's error (ratio = their time / sppm's; above 1: sppm is sooner):")
    print("  %10s %9s | %22s %22s | %22s %22s" % (
        "iterations", "sppm s", "path_mis s (MSE)", "Mitsuba s (MSE)",
        "path_mis s (relMSE)", "Mitsuba s (relMSE)"))
    summary = []
    for r in sppm:
        entry = {"iterations": r["spp"], "sppm_seconds": r["seconds"]}
        cells = []
        for key in ("mse", "rel_mse"):
            for label, rows in (("path_mis", path), ("mitsuba", mitsuba)):
                t, ext = time_to_reach(rows, key, r[key])
                entry["%s_seconds_to_%s" % (label, key)] = t
                entry["%s_extrapolated_%s" % (label, key)] = ext
                ratio = t / r["seconds"] if r["seconds"] > 0 else float("nan")
                cells.append("%9.3f (x%6.2f)%s" % (t, ratio, "*" if ext else " "))
        summary.append(entry)
        print("  %10d %9.3f | %s %s | %s %s" % (r["spp"], r["seconds"], *cells))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"sppm": sppm_report, "path_mis": path_report, "mitsuba": theirs,
                       "time_to_sppm_error": summary}, f, indent=2)
            f.write("\n")
        print("wrote %s" % args.json, file=sys.stderr)


if __name__ == "__main__":
    main()
