#!/usr/bin/env python3
"""The speed comparison of the surface and media issues, in one command.

    python3 tools/bench_suite.py [--scenes cbox,veach,...]
        [--variants scalar_rgb,llvm_ad_rgb,llvm_ad_rgb@avx2]
        [--seeds 11,12,13,14] [--spp 16,64] [--samplers independent,multijitter,...]
        [--refs DIR] [--wavetrace BIN] [--json OUT]

For every scene of the suite (256 x 256, the resolution the issues measure at), every
Mitsuba variant and every seed, runs tools/bench_compare.py (wavetrace and Mitsuba on
the same scene file, the same sample counts and the same reference) and prints the
efficiency ratio (t x relMSE) wavetrace / (t x relMSE) Mitsuba at each sample count:
per seed, and their geometric mean. Below 1, wavetrace reaches a given error sooner.
Then the MSE of both at equal spp (mean over seeds) with the ratios of their MSEs and
relMSEs, each with its standard error over the seeds.

The host: the first line names its CPU and vector extensions (tools/llvm_target.py), and
the JSON keeps them (`host`). A variant written `llvm_ad_rgb@avx2` is Mitsuba's LLVM
variant compiled for an AVX2 host's 8 lanes instead of this host's full width
(bench_compare.py --llvm-target): `--variants llvm_ad_rgb,llvm_ad_rgb@avx2` measures an
AVX-512 host natively and as an AVX2 host in one run.

References are Mitsuba renders, made once and kept in --refs (default
target/bench-refs/, outside version control: about 0.8 MB each): with the LLVM variant
when Debian's libLLVM-19 is installed (see tools/README.md), else scalar_rgb. A
reference's own noise adds to both renderers' relMSE alike and pulls the ratios
towards 1; the suite's sample counts (4096, 1024 for the slow Cornell-box smoke) keep
that under 2 % at 64 spp.

Timings on a shared 2-core machine swing by 10-20 % from run to run and the relMSE of
one seed by as much again: read the geometric means over several seeds, and run
nothing else meanwhile.

Samplers: `--samplers` runs every scene once per sampler, both renderers with that
sampler (tools/bench_compare.py --sampler; Mitsuba has no zsobol and runs
`independent` there), and prints the MSE of each at each sample count next to
Mitsuba's, and the efficiency ratio. `--scenes samplers` is the sampler issue's three
scenes at the resolutions of their shipped references (scenes/refs/, Mitsuba 4096 spp):
the Cornell box (`path`, 128 x 128), Veach's plates (`direct`, 128 x 128) and the
environment map (`path`, 64 x 64).
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

TOOLS = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, TOOLS)
import llvm_target  # noqa: E402  (same folder)
ROOT = os.path.normpath(os.path.join(TOOLS, ".."))
LIBLLVM = "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"

# name -> (scene, defines for both renderers, wavetrace integrator or None for the
# scene's own, reference spp)
SUITE = {
    "cbox": ("scenes/cbox/cbox_path.xml", ["res=256"], None, 4096),
    "veach": ("scenes/veach/veach.xml", ["res=256", "integrator=path", "max_depth=4"], None, 4096),
    "glass": ("scenes/glass/glass.xml", ["res=256"], None, 4096),
    "cube": ("scenes/media/cube.xml", ["res=256"], None, 4096),
    "two_media": ("scenes/media/two_media.xml", ["res=256"], None, 4096),
    "smoke": ("scenes/media/smoke.xml", ["res=256"], None, 4096),
    "cbox_smoke": ("scenes/media/cbox_smoke.xml", ["res=256"], None, 1024),
    "cube_g07": ("scenes/media/cube.xml", ["res=256", "g=0.7"], None, 1024),
    "cube_gm07": ("scenes/media/cube.xml", ["res=256", "g=-0.7"], None, 1024),
    "cube_absorber": ("scenes/media/cube.xml", ["res=256", "albedo=0"], None, 1024),
    "thin_textured": ("scenes/media/thin_textured.xml", ["res=256"], None, 1024),
    "smoke_rotated": ("scenes/media/smoke_rotated.xml", ["res=256"], None, 1024),
    # The sampler issue's scenes, against their shipped references.
    "cbox_path": ("scenes/cbox/cbox_path.xml", [], None, "scenes/refs/cbox_path.exr"),
    "veach_direct": ("scenes/veach/veach.xml", ["integrator=direct"], None,
                     "scenes/refs/veach_direct.exr"),
    "envmap": ("scenes/envmap/envmap.xml", [], None, "scenes/refs/envmap.exr"),
    # The speed issue's shading-heavy scenes: a lat-long EXR lighting a rough conductor
    # and a rough plastic (unbounded paths), and bitmap textures on geometry (diffuse
    # reflectance, a rough conductor's roughness) and on an area emitter's radiance.
    "envmap_glossy": ("scenes/envmap/envmap_glossy.xml", ["res=256"], None, 4096),
    "textures": ("scenes/textures/textures.xml", ["res=256"], None, 4096),
    # A normal-mapped brick wall and sphere under a grazing area light.
    "normalmap": ("scenes/textures/normalmap.xml", ["res=256"], None, 4096),
    # Mitsuba's principled and principledthin under the environment map.
    "principled": ("scenes/principled/principled.xml", ["res=256"], None, 1024),
}
SURFACES = ["cbox", "veach", "glass"]
MEDIA = ["cube", "two_media", "smoke", "cbox_smoke"]
# The other shipped media scenes with a Mitsuba twin (fog_point's single_scatter has
# none): phase functions, an absorber, a textured thin dielectric, a rotated spiky grid.
MEDIA_MORE = ["cube_g07", "cube_gm07", "cube_absorber", "thin_textured", "smoke_rotated"]
SAMPLER_SCENES = ["cbox_path", "veach_direct", "envmap"]
SHADING = ["envmap_glossy", "textures", "normalmap"]
# One scene of each kind the speed issue's table measures against llvm_ad_rgb.
SPEED = ["cbox", "veach_direct", "glass", "cube", "cube_g07", "smoke", "envmap_glossy",
         "textures", "normalmap"]


def die(msg):
    sys.exit("bench_suite.py: " + msg)


def ints(text, what):
    try:
        values = [int(t) for t in text.split(",")]
    except ValueError:
        values = []
    if not values:
        die("%s expects integers separated by commas, got %r" % (what, text))
    return values


def reference(name, refs, seed_base=1000):
    """The scene's reference EXR: shipped, or rendered by Mitsuba if missing."""
    scene, defines, _, spp = SUITE[name]
    if isinstance(spp, str):
        return os.path.join(ROOT, spp)
    out = os.path.join(refs, name + ".exr")
    if os.path.isfile(out):
        return out
    os.makedirs(refs, exist_ok=True)
    variant = "llvm_ad_rgb" if os.path.isfile(LIBLLVM) else "scalar_rgb"
    env = dict(os.environ)
    if variant.startswith("llvm"):
        env.setdefault("DRJIT_LIBLLVM_PATH", LIBLLVM)
    cmd = [sys.executable, os.path.join(TOOLS, "mitsuba_ref.py"), os.path.join(ROOT, scene),
           "-o", out, "--spp", str(spp), "--variant", variant, "--pass-spp", "256",
           "--seed", str(seed_base), "--keep-filter"]
    for d in defines:
        cmd += ["-D", d]
    print("$ " + " ".join(cmd), file=sys.stderr)
    if subprocess.run(cmd, env=env).returncode != 0:
        die("reference for %s failed" % name)
    return out


def compare(name, ref, variant, seed, spp, wavetrace, sampler, repeat):
    scene, defines, integrator, _ = SUITE[name]
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "cmp.json")
        cmd = [sys.executable, os.path.join(TOOLS, "bench_compare.py"), os.path.join(ROOT, scene),
               "--ref", ref, "--spp", ",".join(map(str, spp)), "--variant", variant,
               "--seed", str(seed), "--repeat", str(repeat), "--json", out]
        for d in defines:
            cmd += ["-D", d]
        if integrator:
            cmd += ["--integrator", integrator]
        if wavetrace:
            cmd += ["--wavetrace", wavetrace]
        if sampler:
            cmd += ["--sampler", sampler]
        print("$ " + " ".join(cmd), file=sys.stderr)
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if proc.returncode != 0:
            die("bench_compare failed for %s:\n%s" % (name, proc.stderr))
        with open(out) as f:
            return json.load(f)


def ratio_of_means(num, den):
    """mean(num) / mean(den) over seeds and its standard error (first-order: the
    relative standard errors of the two means added in quadrature; nan below 2 seeds).
    The seeds of one renderer are independent renders, the two renderers too."""
    n = len(num)
    if n == 0 or len(den) != n:
        return float("nan"), float("nan")
    a, b = sum(num) / n, sum(den) / n
    if a <= 0 or b <= 0:
        return float("nan"), float("nan")
    if n < 2:
        return a / b, float("nan")
    rel2 = sum(((x - a) / a) ** 2 for x in num) / (n - 1) / n + sum(((x - b) / b) ** 2 for x in den) / (n - 1) / n
    return a / b, a / b * math.sqrt(rel2)


def geomean(xs):
    xs = [x for x in xs if x > 0 and math.isfinite(x)]
    return math.exp(sum(map(math.log, xs)) / len(xs)) if xs else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", default="surfaces,shading,media",
                    help="comma-separated subset of: %s (or 'surfaces', 'shading', 'media', 'speed', "
                    "'media_more', 'samplers')"
                    % ", ".join(SUITE))
    ap.add_argument("--variants", default="scalar_rgb", help="Mitsuba variants (default scalar_rgb)")
    ap.add_argument("--seeds", default="11,12,13,14", help="seeds (default 11,12,13,14)")
    ap.add_argument("--spp", default="16,64", help="sample counts (default 16,64)")
    ap.add_argument("--refs", default=os.path.join(ROOT, "target", "bench-refs"),
                    help="folder of the references (default target/bench-refs)")
    ap.add_argument("--samplers", default="",
                    help="samplers to run each scene with (default: the scene's own)")
    ap.add_argument("--wavetrace", help="wavetrace binary (default: bench_compare.py's)")
    ap.add_argument("--repeat", type=int, default=1,
                    help="bench_compare.py --repeat: time each render this many times, alternating the "
                    "renderers, and take the median (default 1)")
    ap.add_argument("--json", help="write every run and the summary here")
    args = ap.parse_args()

    names = []
    for n in args.scenes.split(","):
        groups = {"surfaces": SURFACES, "shading": SHADING, "media": MEDIA,
                  "media_more": MEDIA_MORE, "samplers": SAMPLER_SCENES, "speed": SPEED}
        names += groups.get(n, [n])
    for n in names:
        if n not in SUITE:
            die("no scene %r in the suite (%s)" % (n, ", ".join(SUITE)))
    variants = [v for v in args.variants.split(",") if v]
    seeds = ints(args.seeds, "--seeds")
    spp = ints(args.spp, "--spp")
    samplers = [s for s in args.samplers.split(",") if s] or [None]

    host = llvm_target.vector_extensions()
    print("host: %s" % llvm_target.describe_host(), flush=True)
    runs = []
    summary = []
    for name in names:
        ref = reference(name, args.refs)
        for variant in variants:
            for sampler in samplers:
                per_seed = []
                for seed in seeds:
                    result = compare(name, ref, variant, seed, spp, args.wavetrace, sampler, args.repeat)
                    runs.append({"scene": name, "variant": variant, "sampler": sampler,
                                 "seed": seed, "result": result})
                    per_seed.append(result["comparison"])
                for i, n in enumerate(spp):
                    rows = [c[i] for c in per_seed if i < len(c)]
                    ratios = [r["efficiency_ratio"] for r in rows]
                    # MSE: the mean over seeds (as the table), not the geometric mean.
                    mean = lambda k: sum(r[k] for r in rows) / len(rows)  # noqa: E731
                    mse_ratio, mse_ratio_se = ratio_of_means([r["wavetrace_mse"] for r in rows],
                                                             [r["mitsuba_mse"] for r in rows])
                    rel_ratio, rel_ratio_se = ratio_of_means([r["wavetrace_rel_mse"] for r in rows],
                                                             [r["mitsuba_rel_mse"] for r in rows])
                    summary.append({
                        "scene": name, "variant": variant, "sampler": sampler or "scene's",
                        "spp": n, "rendered_spp": rows[0]["spp"] if rows else n,
                        "efficiency_ratio": geomean(ratios), "per_seed": ratios,
                        "wavetrace_seconds": mean("wavetrace_seconds"),
                        "mitsuba_seconds": mean("mitsuba_seconds"),
                        "wavetrace_rel_mse": geomean([r["wavetrace_rel_mse"] for r in rows]),
                        "mitsuba_rel_mse": geomean([r["mitsuba_rel_mse"] for r in rows]),
                        "wavetrace_mse": mean("wavetrace_mse"),
                        "mitsuba_mse": mean("mitsuba_mse"),
                        "mse_ratio": mse_ratio, "mse_ratio_se": mse_ratio_se,
                        "rel_mse_ratio": rel_ratio, "rel_mse_ratio_se": rel_ratio_se,
                        "mitsuba_sampler": runs[-1]["result"]["mitsuba"]["sampler"],
                    })
                    s = summary[-1]
                    print("%-12s %-17s %-12s %4d spp: ratio %.3f  (seeds %s)  wt %.2f s MSE %.3e  "
                          "mi %.2f s MSE %.3e (%s)" % (
                              name, variant, s["sampler"], s["rendered_spp"], s["efficiency_ratio"],
                              " ".join("%.2f" % r for r in ratios), s["wavetrace_seconds"],
                              s["wavetrace_mse"], s["mitsuba_seconds"], s["mitsuba_mse"],
                              s["mitsuba_sampler"]), flush=True)

    print("\nefficiency ratio (t x relMSE) wavetrace / Mitsuba, geometric mean over seeds %s;"
          " below 1: wavetrace ahead; host %s" % (",".join(map(str, seeds)), llvm_target.describe_host()))
    print("%-12s %-17s %-12s " % ("scene", "variant", "sampler")
          + " ".join("%8s" % ("%d spp" % n) for n in spp))
    for name in names:
        for variant in variants:
            for sampler in samplers:
                cells = [s for s in summary if s["scene"] == name and s["variant"] == variant
                         and s["sampler"] == (sampler or "scene's")]
                print("%-12s %-17s %-12s " % (name, variant, sampler or "scene's")
                      + " ".join("%8.3f" % c["efficiency_ratio"] for c in cells))
    print("\nMSE at equal spp, mean over seeds: wavetrace / Mitsuba (same sampler; Mitsuba "
          "runs independent for zsobol); in brackets the ratio of MSEs and of relMSEs, "
          "each +- its standard error over the seeds")
    for name in names:
        for variant in variants:
            for sampler in samplers:
                cells = [s for s in summary if s["scene"] == name and s["variant"] == variant
                         and s["sampler"] == (sampler or "scene's")]
                print("%-12s %-17s %-12s " % (name, variant, sampler or "scene's") + "  ".join(
                    "%d spp %.2e / %.2e (MSE %.2f+-%.2f, relMSE %.2f+-%.2f)" % (
                        c["rendered_spp"], c["wavetrace_mse"], c["mitsuba_mse"], c["mse_ratio"],
                        c["mse_ratio_se"], c["rel_mse_ratio"], c["rel_mse_ratio_se"])
                    for c in cells))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"host": host, "summary": summary, "runs": runs}, f, indent=2)
            f.write("\n")
        print("wrote %s" % args.json, file=sys.stderr)


if __name__ == "__main__":
    main()
