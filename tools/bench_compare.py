#!/usr/bin/env python3
"""Time against error, wavetrace against Mitsuba 3, on the same scene file.

    python3 tools/bench_compare.py SCENE.xml --ref REF.exr [--spp 1,4,16,64,256]
        [--variant scalar_rgb|llvm_ad_rgb[@avx2]] [--llvm-target native|avx2]
        [--integrator NAME] [--max-depth N]
        [-D name=value] [--seed S] [--sampler NAME [--mitsuba-sampler NAME]]
        [--wavetrace BIN] [--device SEL] [--repeat K] [--json OUT.json]

Both renderers render samples 0..N for every N of --spp and are compared with the
same reference by the same metrics as `wavetrace bench` (RMSE; relMSE, the mean over
pixels and channels of (a - b)^2 / (b^2 + 0.01)).

wavetrace: runs `wavetrace bench SCENE --ref REF --spp ... --json` and reads its JSON
(times exclude scene loading, BVH, pipelines and kernel compilation: a 1-spp warm-up
render precedes the measurements).

Mitsuba: the scene is prepared as tools/mitsuba_ref.py --keep-filter prepares
references (the scene's own reconstruction filter, crop window and sample_border, as
wavetrace renders them; RGB float32 film; `ao` scenes rewritten to Mitsuba's `direct`
under a constant environment), loaded once, and rendered once at 1 spp untimed (for the LLVM
variants this also JIT-compiles the kernels; Dr.Jit caches them). The wall time of each
`mi.render` call is then measured, including the conversion of the result to a NumPy
array (which forces evaluation of the lazy LLVM variants). With `--variant
llvm_ad_rgb`, each sample count is rendered twice and the second (warm) run is timed,
since Dr.Jit may compile a kernel per wavefront size; scene loading and the warm-up
times are reported apart.

The host: every speed figure names it. The header prints the host's CPU and vector
extensions (AVX-512: 16 float32 lanes, AVX2: 8) and the target Mitsuba's LLVM backend
compiles for, which is the host's full width unless `--llvm-target avx2` (or a variant
written `llvm_ad_rgb@avx2`) restricts it to an AVX2 host's 8 lanes (Haswell), so one
AVX-512 machine measures both kinds of host (tools/llvm_target.py). The JSON has both
under `mitsuba.host` and `mitsuba.llvm_target`.

--repeat K times each renderer K times, alternating (wavetrace at every sample count,
then Mitsuba at every sample count, K times over; Mitsuba's scene loaded and warmed up
once), and takes the median time of each sample count; the fastest is kept too (JSON
`seconds_min`, `seconds_runs`). Errors are those of the first run (the same seed renders
the same image). On a shared machine whose timings swing 20-40 % from run to run, this
is what tells a 5 % step.

The sampler: the scene's own, unless --sampler names one: wavetrace gets `--sampler NAME`
and Mitsuba the same type in the scene's <sampler> (--mitsuba-sampler for another; the
default for pbrt-v4's zsobol, which Mitsuba lacks, is `independent`). Both round the
sample count as Mitsuba does (e.g. orthogonal 64 -> 121); rows are matched by the
count asked for, and both MSEs are printed: the MSE ratio at equal spp is what a
sampler changes.

The integrator: the scene's own, unless --integrator names a wavetrace integrator,
which is mapped to the Mitsuba integrator computing the same estimator where one
exists: direct_mis -> direct, direct_ems -> direct (emitter_samples 1,
bsdf_samples 0), direct_mats -> direct (emitter_samples 0, bsdf_samples 1),
path_mis -> path, ao -> the ao rewrite. path_mats has no Mitsuba twin (Mitsuba's
path always samples emitters); it is compared with path, which converges to the same
image by a different estimator. --max-depth sets Mitsuba's path max_depth (default:
the scene's).

Printed, per sample count: both times and relMSEs, and
- the efficiency ratio at equal spp, (t_w * relMSE_w) / (t_m * relMSE_m): below 1,
  wavetrace reaches a given error sooner (for unbiased renderers t * relMSE is about
  constant in spp, so this is the ratio of times to equal error);
- the time ratio at equal relMSE: wavetrace's time for its relMSE over the time
  Mitsuba needs for that same relMSE, read off Mitsuba's curve by linear
  interpolation in log(time)-log(relMSE); outside Mitsuba's measured range the end
  segment's slope is extended (marked `*`).
"""

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import llvm_target  # noqa: E402  (same folder)
import mitsuba_ref  # noqa: E402  (same folder)

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
REL_MSE_EPSILON = 1e-2  # as wavetrace::image::metrics::REL_MSE_EPSILON

# wavetrace integrator -> (Mitsuba integrator, its parameters)
# Sampler types Mitsuba 3 has.
MITSUBA_SAMPLERS = ("independent", "stratified", "multijitter", "orthogonal", "ldsampler")
MITSUBA_TWIN = {
    "direct_mis": ("direct", {}),
    "direct_ems": ("direct", {"emitter_samples": 1, "bsdf_samples": 0}),
    "direct_mats": ("direct", {"emitter_samples": 0, "bsdf_samples": 1}),
    "path_mis": ("path", {}),
    "path_mats": ("path", {}),
    "ao": ("ao", {}),
}


def die(msg):
    sys.exit("bench_compare.py: " + msg)


def parse_spp(text):
    try:
        counts = [int(t) for t in text.split(",")]
    except ValueError:
        counts = []
    if not counts or any(n < 1 for n in counts):
        die("--spp expects positive integers separated by commas, got %r" % text)
    return counts


def find_wavetrace(explicit):
    if explicit:
        return explicit
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    for profile in ("release", "debug"):
        path = os.path.join(target, profile, "wavetrace")
        if os.path.isfile(path):
            return path
    die("no wavetrace binary in %s/{release,debug}: run `cargo build --release` or pass --wavetrace" % target)


def run_wavetrace(args, spp):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "bench.json")
        cmd = [find_wavetrace(args.wavetrace), "bench", args.scene, "--ref", args.ref,
               "--spp", ",".join(map(str, spp)), "--json", out, "--seed", str(args.seed), "-q"]
        for d in args.defines:
            cmd += ["-D", d]
        if args.integrator:
            cmd += ["--integrator", args.integrator]
        if args.sampler:
            cmd += ["--sampler", args.sampler]
        if args.device:
            cmd += ["--device", args.device]
        print("$ " + " ".join(cmd), file=sys.stderr)
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if proc.returncode != 0:
            die("wavetrace bench failed:\n" + proc.stderr)
        sys.stderr.write(proc.stdout)
        with open(out) as f:
            return json.load(f)


def scene_integrator(root, scene_path, defines):
    """The scene's integrator element (following includes), or None."""
    resolve = mitsuba_ref.resolver_of(root, defines)
    el = root.find("integrator")
    for path in mitsuba_ref.included(root, scene_path, resolve):
        if el is None and os.path.isfile(path):
            el = ET.parse(path).getroot().find("integrator")
    return el, resolve


def prepare_mitsuba_xml(args, defines):
    """The scene as Mitsuba should render it, and a description of its integrator."""
    try:
        root = ET.parse(args.scene).getroot()
    except (OSError, ET.ParseError) as e:
        die("%s: %s" % (args.scene, e))
    if root.tag != "scene" or "version" not in root.attrib:
        die("%s: not a Mitsuba 3 scene" % args.scene)
    el, resolve = scene_integrator(root, args.scene, defines)
    own = resolve(el.get("type", "")) if el is not None else ""
    kind, params = (own, {}) if not args.integrator else MITSUBA_TWIN.get(args.integrator, (None, None))
    if kind is None:
        die("no Mitsuba integrator for wavetrace's %r" % args.integrator)
    if kind in ("ao", "direct_mis", "direct_ems", "direct_mats", "path_mis", "path_mats"):
        kind, params = MITSUBA_TWIN[kind]
    if kind == "ao":
        mitsuba_ref.rewrite_for_ao(root)
        described = "direct (the ao rewrite of tools/mitsuba_ref.py)"
    elif kind != own or args.max_depth is not None or params:
        depth = args.max_depth
        if depth is None and el is not None:
            for c in el:
                if c.get("name") == "max_depth":
                    depth = int(resolve(c.get("value")))
        # Drop the scene's integrator, its includes of integrator files included.
        for inc in [i for i in root.findall("include") if "integrator" in i.get("filename", "")]:
            root.remove(inc)
        mitsuba_ref.set_integrator(root, kind, depth if depth is not None else 6)
        new = root.find("integrator")
        for k, v in params.items():
            ET.SubElement(new, "integer", name=k, value=str(v))
        described = " ".join([kind] + ["%s=%s" % (c.get("name"), c.get("value")) for c in new])
    else:
        described = " ".join([own] + ["%s=%s" % (c.get("name"), resolve(c.get("value", ""))) for c in el])
    mitsuba_ref.prepare(root, None, keep_filter=True)
    if args.mitsuba_sampler:
        sampler = next(root.iter("sensor")).find("sampler")
        sampler.set("type", args.mitsuba_sampler)
    return ET.tostring(root, encoding="unicode"), described


def metrics(image, reference):
    import numpy as np

    d = image.astype(np.float64) - reference
    mse = float(np.mean(d * d))
    rel = float(np.mean(d * d / (reference * reference + REL_MSE_EPSILON)))
    return math.sqrt(mse), mse, rel


class MitsubaRun:
    """Mitsuba with the scene loaded and warmed up once; `rows(spp)` times one render
    of each sample count."""

    def __init__(self, args, defines):
        import numpy as np

        if args.variant.startswith("llvm") and "DRJIT_LIBLLVM_PATH" not in os.environ:
            for cand in ("/usr/lib/x86_64-linux-gnu/libLLVM-19.so", "/usr/lib/llvm-19/lib/libLLVM-19.so"):
                if os.path.isfile(cand):
                    os.environ["DRJIT_LIBLLVM_PATH"] = cand
                    break
        llvm = args.variant.startswith("llvm")
        if llvm:
            llvm_target.restrict_llvm(args.llvm_target)
        import mitsuba as mi

        self.np, self.mi, self.args = np, mi, args
        mi.set_variant(args.variant)
        xml, described = prepare_mitsuba_xml(args, defines)
        mi.file_resolver().prepend(os.path.dirname(os.path.abspath(args.scene)))
        self.reference = np.array(mi.Bitmap(args.ref).convert(mi.Bitmap.PixelFormat.RGB,
                                                              mi.Struct.Type.Float32, False),
                                  dtype=np.float64)

        t = time.perf_counter()
        try:
            self.scene = mi.load_string(xml, **defines)
        except Exception as e:
            die("%s: %s" % (args.scene, e))
        load_seconds = time.perf_counter() - t
        size = tuple(self.scene.sensors()[0].film().size())
        if (size[1], size[0]) != self.reference.shape[:2]:
            die("reference %s is %dx%d but Mitsuba renders %s at %dx%d"
                % (args.ref, self.reference.shape[1], self.reference.shape[0], args.scene, size[0],
                   size[1]))

        t = time.perf_counter()
        np.array(mi.render(self.scene, spp=1, seed=args.seed + 1_000_000))
        warmup_seconds = time.perf_counter() - t

        self.warm_each = llvm
        self.info = {
            "version": mi.__version__,
            "variant": args.variant,
            "integrator": described,
            "sampler": next(iter(ET.fromstring(xml).iter("sensor"))).find("sampler").get("type"),
            "libllvm": os.environ.get("DRJIT_LIBLLVM_PATH") if llvm else None,
            "host": llvm_target.vector_extensions(),
            "llvm_target": llvm_target.llvm_info() if llvm else None,
            "load_seconds": load_seconds,
            "warmup_seconds": warmup_seconds,
            "warm_run_per_spp": self.warm_each,
        }

    def rows(self, spp):
        np, mi, args, scene = self.np, self.mi, self.args, self.scene
        rows = []
        for n in spp:
            if self.warm_each:
                np.array(mi.render(scene, spp=n, seed=args.seed + 2_000_000))
            t = time.perf_counter()
            image = np.array(mi.render(scene, spp=n, seed=args.seed))
            seconds = time.perf_counter() - t
            rmse, mse, rel = metrics(image[..., :3], self.reference[..., :3])
            rendered = scene.sensors()[0].sampler().sample_count()
            rows.append({"spp": rendered, "requested_spp": n, "seconds": seconds, "rmse": rmse,
                         "mse": mse, "rel_mse": rel})
            print("mitsuba %5d spp: %.3f s, relMSE %.4e" % (n, seconds, rel), file=sys.stderr)
        return rows


def run_mitsuba(args, spp, defines):
    """Mitsuba's curve: the scene loaded and warmed up, each sample count timed once."""
    m = MitsubaRun(args, defines)
    return dict(m.info, rows=m.rows(spp))


def merge_runs(runs):
    """The rows of the first of several runs of one renderer, each row's `seconds` the
    median over the runs (`seconds_runs` all of them, `seconds_min` the fastest)."""
    rows = []
    for i, row in enumerate(runs[0]):
        times = [run[i]["seconds"] for run in runs]
        rows.append(dict(row, seconds=statistics.median(times), seconds_min=min(times),
                         seconds_runs=times))
    return rows


def time_for_error(rows, target):
    """Time at which a renderer reaches relMSE `target`, by linear interpolation of
    log(relMSE) against log(time) along its measured rows (sorted by time); beyond
    the ends the end segment's slope is extended. Returns (time, extrapolated)."""
    pts = sorted((r["seconds"], r["rel_mse"]) for r in rows if r["seconds"] > 0 and r["rel_mse"] > 0)
    if not pts:
        return float("nan"), True
    if len(pts) == 1:
        # One point: assume relMSE ~ 1/time, the unbiased Monte Carlo rate.
        t, e = pts[0]
        return t * e / target, True
    lt = [math.log(t) for t, _ in pts]
    le = [math.log(e) for _, e in pts]
    y = math.log(target)
    for i in range(len(pts) - 1):
        lo, hi = sorted((le[i], le[i + 1]))
        if lo <= y <= hi and le[i] != le[i + 1]:
            f = (y - le[i]) / (le[i + 1] - le[i])
            return math.exp(lt[i] + f * (lt[i + 1] - lt[i])), False
    # Extrapolate from the nearer end.
    i = 0 if y > le[0] else len(pts) - 2
    if le[i + 1] == le[i]:
        return float("nan"), True
    slope = (lt[i + 1] - lt[i]) / (le[i + 1] - le[i])
    j = i if y > le[0] else i + 1
    return math.exp(lt[j] + slope * (y - le[j])), True


def compare(ours, theirs):
    by_spp = {r.get("requested_spp", r["spp"]): r for r in theirs["rows"]}
    out = []
    for w in ours["rows"]:
        m = by_spp.get(w.get("requested_spp", w["spp"]))
        if m is None:
            continue
        w_mse = w["rmse"] ** 2
        eff_rel = (w["seconds"] * w["rel_mse"]) / (m["seconds"] * m["rel_mse"])
        eff_mse = (w["seconds"] * w_mse) / (m["seconds"] * m["mse"]) if m["mse"] > 0 else float("nan")
        t_m, extrapolated = time_for_error(theirs["rows"], w["rel_mse"])
        out.append({
            "spp": w["spp"],
            "requested_spp": w.get("requested_spp", w["spp"]),
            "mitsuba_spp": m["spp"],
            "wavetrace_seconds": w["seconds"],
            "wavetrace_seconds_min": w.get("seconds_min", w["seconds"]),
            "wavetrace_rel_mse": w["rel_mse"],
            "wavetrace_mse": w_mse,
            "mitsuba_seconds": m["seconds"],
            "mitsuba_seconds_min": m.get("seconds_min", m["seconds"]),
            "mitsuba_rel_mse": m["rel_mse"],
            "mitsuba_mse": m["mse"],
            "mse_ratio": w_mse / m["mse"] if m["mse"] > 0 else float("nan"),
            "efficiency_ratio": eff_rel,
            "efficiency_ratio_mse": eff_mse,
            "mitsuba_seconds_to_equal_rel_mse": t_m,
            "time_ratio_at_equal_rel_mse": w["seconds"] / t_m if t_m > 0 else float("nan"),
            "extrapolated": extrapolated,
        })
    return out


def print_table(ours, theirs, rows):
    print("scene %s, reference %s" % (ours["scene"], ours["reference"]))
    print("wavetrace: %s, sampler %s, on %s; Mitsuba %s %s: %s, sampler %s" % (
        ours["integrator"], ours.get("sampler", "independent"), ours["device"], theirs["version"],
        theirs["variant"], theirs["integrator"], theirs["sampler"]))
    host = theirs["host"]
    target = theirs.get("llvm_target")
    print("host: %s, %s (%d float32 lanes)%s" % (
        host["cpu"], host["name"], host["lanes"],
        "; Mitsuba's LLVM compiles for %s, %d lanes" % (target["cpu"], target["lanes"]) if target else ""))
    print("Mitsuba scene load %.2f s, warm-up %.2f s%s" % (
        theirs["load_seconds"], theirs["warmup_seconds"],
        " (each spp rendered twice, the warm run timed)" if theirs["warm_run_per_spp"] else ""))
    repeat = len(ours["rows"][0].get("seconds_runs", [0])) if ours["rows"] else 1
    if repeat > 1:
        print("times: the median of %d runs of each renderer, alternated; fastest: %s" % (
            repeat, ", ".join("%d spp wt %.4f s mi %.4f s" % (r["spp"], r["wavetrace_seconds_min"],
                                                            r["mitsuba_seconds_min"]) for r in rows)))
    print("%6s %10s %11s %11s %10s %11s %11s %9s %10s %10s" % (
        "spp", "wt s", "wt MSE", "wt relMSE", "mi s", "mi MSE", "mi relMSE", "MSE ratio",
        "eff ratio", "t ratio"))
    for r in rows:
        print("%6d %10.4f %11.4e %11.4e %10.4f %11.4e %11.4e %9.3f %10.3f %9.3f%s" % (
            r["spp"], r["wavetrace_seconds"], r["wavetrace_mse"], r["wavetrace_rel_mse"],
            r["mitsuba_seconds"], r["mitsuba_mse"], r["mitsuba_rel_mse"], r["mse_ratio"],
            r["efficiency_ratio"], r["time_ratio_at_equal_rel_mse"],
            "*" if r["extrapolated"] else " "))
    print("MSE ratio = wavetrace MSE / Mitsuba MSE at equal spp; "
          "eff ratio = (t x relMSE) wavetrace / (t x relMSE) Mitsuba at equal spp; "
          "t ratio = wavetrace time / Mitsuba time to the same relMSE (* extrapolated). "
          "Below 1: wavetrace is ahead.")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene", help="scene file in Mitsuba 3's XML dialect")
    ap.add_argument("--ref", required=True, help="reference EXR (e.g. scenes/refs/*.exr)")
    ap.add_argument("--spp", default="1,4,16,64,256", help="sample counts (default 1,4,16,64,256)")
    ap.add_argument("--variant", default="scalar_rgb",
                    help="Mitsuba variant (default scalar_rgb); VARIANT@TARGET sets --llvm-target too")
    ap.add_argument("--llvm-target", default="native", choices=sorted(llvm_target.TARGETS),
                    help="what Mitsuba's LLVM backend compiles for: the host (native, default) "
                         "or an AVX2 host's 8 lanes (avx2)")
    ap.add_argument("--integrator", help="wavetrace integrator (Mitsuba gets its twin; see above)")
    ap.add_argument("--max-depth", type=int, help="Mitsuba path max_depth (default: the scene's)")
    ap.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE",
                    help="scene parameter, passed to both renderers")
    ap.add_argument("--seed", type=int, default=0, help="seed of both renderers (default 0)")
    ap.add_argument("--wavetrace", help="wavetrace binary (default: $CARGO_TARGET_DIR or target/, release first)")
    ap.add_argument("--sampler", help="sampler of both renderers (default: the scene's)")
    ap.add_argument("--mitsuba-sampler",
                    help="Mitsuba's sampler, when not --sampler's (default for zsobol: independent)")
    ap.add_argument("--device", help="wavetrace --device")
    ap.add_argument("--repeat", type=int, default=1,
                    help="time each renderer this many times, alternated, and take the median (default 1)")
    ap.add_argument("--json", help="write both curves and the ratios here")
    args = ap.parse_args()
    if args.repeat < 1:
        die("--repeat must be at least 1, not %d" % args.repeat)
    if "@" in args.variant:
        args.variant, args.llvm_target = args.variant.split("@", 1)
        if args.llvm_target not in llvm_target.TARGETS:
            die("unknown LLVM target '%s' (known: %s)" % (args.llvm_target, ", ".join(llvm_target.TARGETS)))
    if args.llvm_target != "native" and not args.variant.startswith("llvm"):
        die("--llvm-target %s needs an llvm variant, not %s" % (args.llvm_target, args.variant))

    spp = parse_spp(args.spp)
    if args.sampler and not args.mitsuba_sampler:
        args.mitsuba_sampler = args.sampler if args.sampler in MITSUBA_SAMPLERS else "independent"
    if args.mitsuba_sampler and args.mitsuba_sampler not in MITSUBA_SAMPLERS:
        die("Mitsuba has no sampler %r (it has %s)" % (args.mitsuba_sampler, ", ".join(MITSUBA_SAMPLERS)))
    try:
        defines = mitsuba_ref.parse_defines(args.defines)
    except ValueError as e:
        die(str(e))
    for path in (args.scene, args.ref):
        if not os.path.isfile(path):
            die("%s: no such file" % path)

    mitsuba = MitsubaRun(args, defines)
    ours_runs, theirs_runs = [], []
    for _ in range(args.repeat):
        ours_runs.append(run_wavetrace(args, spp))
        theirs_runs.append(mitsuba.rows(spp))
    ours = dict(ours_runs[0], rows=merge_runs([o["rows"] for o in ours_runs]))
    theirs = dict(mitsuba.info, rows=merge_runs(theirs_runs))
    rows = compare(ours, theirs)
    print_table(ours, theirs, rows)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"wavetrace": ours, "mitsuba": theirs, "comparison": rows}, f, indent=2)
            f.write("\n")
        print("wrote %s" % args.json, file=sys.stderr)


if __name__ == "__main__":
    main()
