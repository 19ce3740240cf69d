#!/usr/bin/env python3
"""Render a wavetrace scene (Mitsuba 3 dialect) with Mitsuba 3, as a reference EXR.

    python3 tools/mitsuba_ref.py SCENE.xml -o OUT.exr --spp N [--variant scalar_rgb] [--ao]
                                 [--integrator path|direct|volpath|depth] [--max-depth N]
                                 [-D name=value] [--keep-filter] [--alpha]

What it changes in the scene before Mitsuba sees it (the file itself is not touched):

* Unless `--keep-filter`: the film's reconstruction filter becomes `box` (each sample
  counts once in its own pixel), its pixel format `rgb`, and any crop window or
  `sample_border` goes. With `--keep-filter` the film keeps the scene's filter (none:
  Mitsuba's Gaussian), crop window and `sample_border`, as wavetrace renders them;
  use a JIT variant (`llvm_ad_rgb`) then: Mitsuba's scalar variants look non-box
  filters up in a 31-step table, its JIT variants evaluate them exactly, as wavetrace
  does. Always: component format `float32`, pixel format `rgb`, or `rgba` with
  `--alpha` (the EXR then has an A channel: Mitsuba's alpha). With `--spp` the
  sampler's `sample_count` is replaced.
* With `--integrator path|direct|volpath`: the scene's integrator is replaced by
  Mitsuba's `path` (with `--max-depth`, default 6), `direct` (MIS of one emitter
  sample and one BSDF sample, which is wavetrace's `direct_mis`; it takes no depth)
  or `volpath` (volumetric path tracing, wavetrace's `vol_path_mis`; `--max-depth`). Mitsuba's
  `max_depth` counts path segments from the camera: 1 shows emitters only, 2 is
  direct lighting, 6 is up to five bounces. `--integrator depth`: Mitsuba's `depth`
  (the first hit's distance), wavetrace's `depth`.
* With `-D name=value`: Mitsuba's `$name` parameters (the scene's `<default>`s), as
  `wavetrace -D` does.
* Always: wavetrace-only medium parameters (`majorant_resolution_factor`, which
  Mitsuba 3.9 does not read) are removed.
* With `--ao`: wavetrace's `ao` integrator, ambient occlusion
      AO(x) = (1/pi) * integral over the hemisphere of V(x, w) cos(theta) dw,
  is not a Mitsuba plugin. It equals the direct illumination of a white Lambertian
  surface (f = 1/pi) under a constant environment of radiance 1 with nothing else
  emitting, so the scene is rewritten to exactly that: the integrator becomes
  `direct` with `hide_emitters` (a camera ray that escapes gives 0, as it does for
  wavetrace's and Nori's `ao`, rather than the environment's 1), every BSDF becomes
  `diffuse` with reflectance 1 (ids kept so `<ref>`s still resolve; shapes without
  a BSDF get one, since Mitsuba's default is reflectance 0.5), every emitter and
  medium is removed, and a `constant` emitter of radiance 1 is added.
  Mitsuba's diffuse BSDF is one-sided: a back face renders black. The shipped AO
  scenes show the camera front faces only, so the convention never matters there.

Large sample counts are rendered in passes of at most --pass-spp samples with
different seeds; the film's raw sums (filter-weighted values and weights, Mitsuba's
`bitmap(raw=True)`) of all passes are added and divided once, so the result is the
same estimator as one big pass, whatever the filter (the JIT variants cannot hold a
whole 16k-spp wavefront in memory).
The particle tracer (`ptracer`) splats with weight 0 and each pass is already its own
mean: its passes are averaged, each weighed by its sample count.

Next to OUT.exr it writes OUT.json: the command, spp, passes, seed, variant, Mitsuba version, time
taken, and SHA-256 of the scene file and of every file it names, so a stale reference
can be detected.
"""

import argparse
import hashlib
import json
import os
import shlex
import sys
import time
import xml.etree.ElementTree as ET


def parse_defines(items):
    """`-D NAME=VALUE` arguments as a dict; ValueError names a malformed one."""
    defines = {}
    for d in items:
        name, eq, value = d.partition("=")
        if not name or not eq:
            raise ValueError("-D expects NAME=VALUE, got %r" % d)
        defines[name] = value
    return defines


def die(msg):
    sys.exit("mitsuba_ref.py: " + msg)


def set_param(parent, tag, name, value):
    """Replace (or add) `<tag name=... value=.../>` among parent's direct children."""
    for child in list(parent):
        if child.get("name") == name:
            parent.remove(child)
    ET.SubElement(parent, tag, name=name, value=str(value))


def white_diffuse(bsdf_id=None):
    el = ET.Element("bsdf", type="diffuse")
    if bsdf_id is not None:
        el.set("id", bsdf_id)
    ET.SubElement(el, "rgb", name="reflectance", value="1")
    return el


def parents_of(root):
    return {child: parent for parent in root.iter() for child in parent}


def rewrite_for_ao(root):
    """Rewrite the scene in place so Mitsuba's `direct` integrator computes AO."""
    parent = parents_of(root)

    # Integrator: direct lighting, emitters seen directly hidden.
    for el in [e for e in root.iter("integrator")]:
        parent[el].remove(el)
    integrator = ET.Element("integrator", type="direct")
    ET.SubElement(integrator, "boolean", name="hide_emitters", value="true")
    root.insert(0, integrator)

    # Emitters and media go; AO is geometry only.
    parent = parents_of(root)
    for tag in ("emitter", "medium"):
        for el in [e for e in root.iter(tag)]:
            parent[el].remove(el)
    for el in [e for e in root.iter("ref") if e.get("name") in ("interior", "exterior")]:
        parent[el].remove(el)

    # Every BSDF (the outermost one of a nesting such as twosided) becomes white diffuse.
    parent = parents_of(root)
    bsdf_ids = set()
    outer = [e for e in root.iter("bsdf") if not any(a.tag == "bsdf" for a in ancestors(e, parent))]
    for el in outer:
        p = parent[el]
        index = list(p).index(el)
        p.remove(el)
        p.insert(index, white_diffuse(el.get("id")))
        if el.get("id"):
            bsdf_ids.add(el.get("id"))

    # Shapes with no BSDF at all would get Mitsuba's grey default.
    for shape in root.iter("shape"):
        has = any(c.tag == "bsdf" or (c.tag == "ref" and c.get("id") in bsdf_ids) for c in shape)
        if not has:
            shape.append(white_diffuse())

    emitter = ET.SubElement(root, "emitter", type="constant")
    ET.SubElement(emitter, "rgb", name="radiance", value="1")


def ancestors(el, parent):
    while el in parent:
        el = parent[el]
        yield el


def set_integrator(root, kind, max_depth):
    """Replace the scene's integrator by Mitsuba's `path`, `direct`, `volpath` or `depth`."""
    parent = parents_of(root)
    for el in [e for e in root.iter("integrator")]:
        parent[el].remove(el)
    integrator = ET.Element("integrator", type=kind)
    if kind in ("path", "volpath"):
        ET.SubElement(integrator, "integer", name="max_depth", value=str(max_depth))
    root.insert(0, integrator)


def prepare(root, spp, keep_filter=False, alpha=False):
    """Box filter (unless keep_filter), RGB (or RGBA) float32 film, and the sample
    count."""
    sensors = list(root.iter("sensor"))
    if len(sensors) != 1:
        die("expected exactly one <sensor>, found %d" % len(sensors))
    sensor = sensors[0]
    film = sensor.find("film")
    if film is None:
        die("the <sensor> has no <film>")
    if not keep_filter:
        for rf in film.findall("rfilter"):
            film.remove(rf)
        ET.SubElement(film, "rfilter", type="box")
        for el in [e for e in film if e.get("name") in
                   ("crop_offset_x", "crop_offset_y", "crop_width", "crop_height", "sample_border")]:
            film.remove(el)
    set_param(film, "string", "pixel_format", "rgba" if alpha else "rgb")
    set_param(film, "string", "component_format", "float32")
    set_param(film, "string", "file_format", "openexr")
    sampler = sensor.find("sampler")
    if sampler is None:
        sampler = ET.SubElement(sensor, "sampler", type="independent")
    if spp is not None:
        set_param(sampler, "integer", "sample_count", spp)
    # wavetrace-only medium parameters (Mitsuba 3.9 rejects unknown ones).
    for medium in root.iter("medium"):
        for el in [e for e in medium if e.get("name") == "majorant_resolution_factor"]:
            medium.remove(el)


def render_raw(mi, scene, sensor, spp, seed):
    """One render's raw film: R, G, B, [A,] W per pixel as a flat list."""
    mi.render(scene, spp=spp, seed=seed)
    return list(mi.TensorXf(sensor.film().bitmap(raw=True)).array)


def develop(sums, alpha):
    """The pixels from a film's raw sums (R, G, B, [A,] W per pixel): each value over
    its pixel's weight, as Mitsuba's film develops (a zero weight divides by 1)."""
    channels = 5 if alpha else 4
    out = []
    for p in range(0, len(sums), channels):
        w = sums[p + channels - 1]
        w = 1.0 if w == 0.0 else w
        out.extend(v / w for v in sums[p:p + channels - 1])
    return out


def to_bitmap(values, size, alpha, mi):
    channels = 4 if alpha else 3
    tensor = mi.TensorXf(values, shape=(size[1], size[0], channels))
    fmt = mi.Bitmap.PixelFormat.RGBA if alpha else mi.Bitmap.PixelFormat.RGB
    return mi.Bitmap(tensor, pixel_format=fmt)


def rgb_errors(a, b, alpha):
    """Mean squared error and relative MSE ((a - b)^2 / (b^2 + 1e-2), as wavetrace's
    image::metrics::rel_mse) over the R, G, B values of image a against reference b."""
    channels = 4 if alpha else 3
    pairs = [(x, y) for i, (x, y) in enumerate(zip(a, b)) if i % channels < 3]
    mse = sum((x - y) ** 2 for x, y in pairs) / len(pairs)
    rel = sum((x - y) ** 2 / (y * y + 1e-2) for x, y in pairs) / len(pairs)
    return mse, rel


def scene_files(root, scene_path, defines):
    """The scene file and every file it names (meshes, included files), for the
    sidecar's hashes."""
    resolve = resolver_of(root, defines)
    base = os.path.dirname(os.path.abspath(scene_path))
    files = [os.path.abspath(scene_path)]
    named = [os.path.join(base, resolve(el.get("value")))
             for el in root.iter("string") if el.get("name") == "filename"]
    for path in named + included(root, scene_path, resolve):
        if os.path.isfile(path) and path not in files:
            files.append(path)
    return files


def resolver_of(root, defines):
    """Mitsuba's `$name` substitution with -D values over the scene's <default>s."""
    values = {d.get("name"): d.get("value") for d in root.findall("default")}
    values.update(defines)

    def resolve(text):
        for name in sorted(values, key=len, reverse=True):
            text = text.replace("$" + name, values[name])
        return text

    return resolve


def included(root, scene_path, resolve):
    """Paths of the files that the scene's top-level <include>s name."""
    base = os.path.dirname(os.path.abspath(scene_path))
    return [os.path.join(base, resolve(el.get("filename", ""))) for el in root.findall("include")]


def integrator_description(root, scene_path, defines):
    """The integrator Mitsuba runs as text, e.g. `path max_depth=6`, with `$name`
    parameters resolved from -D and the scene's <default>s; looks into included
    files (veach.xml picks its integrator by including integrator_$integrator.xml)."""
    resolve = resolver_of(root, defines)
    el = root.find("integrator")
    for path in included(root, scene_path, resolve):
        if el is None and os.path.isfile(path):
            el = ET.parse(path).getroot().find("integrator")
    if el is None:
        return "(Mitsuba's default)"
    params = ["%s=%s" % (c.get("name"), resolve(c.get("value", ""))) for c in el]
    return " ".join([resolve(el.get("type", "?"))] + params)


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene", help="scene file in Mitsuba 3's XML dialect")
    ap.add_argument("-o", "--output", required=True, help="EXR to write")
    ap.add_argument("--spp", type=int, help="samples per pixel (default: the scene's)")
    ap.add_argument("--variant", default="scalar_rgb", help="Mitsuba variant (default scalar_rgb)")
    ap.add_argument("--ao", action="store_true", help="render wavetrace's `ao` integrator (see above)")
    ap.add_argument(
        "--integrator",
        choices=("path", "direct", "volpath", "depth"),
        help="replace the scene's integrator by Mitsuba's path, direct (MIS), volpath or depth integrator",
    )
    ap.add_argument(
        "--max-depth", type=int, default=6, help="max_depth of --integrator path or volpath (default 6)"
    )
    ap.add_argument(
        "-D",
        dest="defines",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="set a scene parameter ($NAME, <default name=NAME>)",
    )
    ap.add_argument("--pass-spp", type=int, default=1024, help="most samples per pass (default 1024)")
    ap.add_argument("--seed", type=int, default=0, help="seed of the first pass (default 0)")
    ap.add_argument("--print-xml", action="store_true", help="print the rewritten scene and stop")
    ap.add_argument(
        "--keep-filter",
        action="store_true",
        help="keep the film's reconstruction filter, crop window and sample_border (see above)",
    )
    ap.add_argument("--alpha", action="store_true", help="render RGBA: the EXR gets Mitsuba's alpha")
    ap.add_argument(
        "--noise",
        type=int,
        default=0,
        metavar="N",
        help="also render N images at --noise-spp with seeds 10000, 10001, ... and record "
        "their MSE and relative MSE against the reference in the JSON (Mitsuba's noise)",
    )
    ap.add_argument("--noise-spp", type=int, default=64, help="samples per pixel of the --noise renders")
    args = ap.parse_args()

    try:
        tree = ET.parse(args.scene)
    except (OSError, ET.ParseError) as e:
        die("%s: %s" % (args.scene, e))
    try:
        defines = parse_defines(args.defines)
    except ValueError as e:
        die(str(e))
    if args.ao and args.integrator:
        die("--ao and --integrator exclude each other")
    root = tree.getroot()
    if root.tag != "scene" or "version" not in root.attrib:
        die("%s: not a Mitsuba 3 scene (<scene version=...>); Nori's dialect is not supported" % args.scene)
    if args.ao:
        rewrite_for_ao(root)
    if args.integrator:
        set_integrator(root, args.integrator, args.max_depth)
    prepare(root, args.spp, args.keep_filter, args.alpha)
    xml = ET.tostring(root, encoding="unicode")
    if args.print_xml:
        print(xml)
        return

    import mitsuba as mi

    mi.set_variant(args.variant)
    scene_dir = os.path.dirname(os.path.abspath(args.scene))
    resolver = mi.file_resolver() if hasattr(mi, "file_resolver") else mi.Thread.thread().file_resolver()
    resolver.prepend(scene_dir)

    start = time.perf_counter()
    try:
        scene = mi.load_string(xml, **defines)
    except Exception as e:  # Mitsuba raises RuntimeError with its own message
        die("%s: %s" % (args.scene, e))
    sensor = scene.sensors()[0]
    spp = sensor.sampler().sample_count()
    passes = []
    left = spp
    while left > 0:
        n = min(left, args.pass_spp)
        passes.append(n)
        left -= n
    # A particle tracer (Mitsuba's AdjointIntegrator) splats with weight 0 and scales
    # each render to its own sample count: its passes are averaged by their counts.
    adjoint = isinstance(scene.integrator(), mi.AdjointIntegrator)
    sums = None
    for i, n in enumerate(passes):
        raw = render_raw(mi, scene, sensor, n, args.seed + i)
        if adjoint:
            raw = [v * n / spp for v in raw]
        sums = raw if sums is None else [a + b for a, b in zip(sums, raw)]
    values = develop(sums, args.alpha)
    bitmap = to_bitmap(values, sensor.film().crop_size(), args.alpha, mi)
    out_dir = os.path.dirname(os.path.abspath(args.output))
    os.makedirs(out_dir, exist_ok=True)
    bitmap.write(args.output)
    seconds = time.perf_counter() - start

    noise = None
    if args.noise > 0:
        seeds = [10000 + i for i in range(args.noise)]
        errors = [
            rgb_errors(develop(render_raw(mi, scene, sensor, args.noise_spp, s), args.alpha), values, args.alpha)
            for s in seeds
        ]
        noise = {
            "spp": args.noise_spp,
            "seeds": seeds,
            "mse": [e[0] for e in errors],
            "rel_mse": [e[1] for e in errors],
        }
        for key in ("mse", "rel_mse"):
            print("noise at %d spp: %s %s, mean %.4e" % (
                args.noise_spp, key, ", ".join("%.4e" % m for m in noise[key]),
                sum(noise[key]) / len(noise[key])))

    size = sensor.film().crop_size()
    print(
        "%s: %dx%d, %d spp in %d pass(es), %.1f s, Mitsuba %s (%s)"
        % (args.output, size[0], size[1], spp, len(passes), seconds, mi.__version__, args.variant)
    )

    # Paths in the record are relative to the repository root (this script's parent).
    root_dir = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    record = {
        "command": "python3 tools/mitsuba_ref.py " + " ".join(shlex.quote(a) for a in sys.argv[1:]),
        "scene": os.path.relpath(os.path.abspath(args.scene), root_dir),
        "ao": args.ao,
        "filter": "scene's" if args.keep_filter else "box",
        "alpha": args.alpha,
        "integrator": integrator_description(root, args.scene, defines),
        "defines": defines,
        "spp": spp,
        "passes": len(passes),
        "pass_spp": passes[0],
        "seed": args.seed,
        "width": size[0],
        "height": size[1],
        "variant": args.variant,
        "mitsuba_version": mi.__version__,
        "seconds": round(seconds, 1),
        **({"noise": noise} if noise else {}),
        "date": time.strftime("%Y-%m-%d", time.gmtime()),
        "sha256": {
            os.path.relpath(f, root_dir): sha256(f) for f in scene_files(root, args.scene, defines)
        },
    }
    sidecar = os.path.splitext(args.output)[0] + ".json"
    with open(sidecar, "w") as f:
        json.dump(record, f, indent=2)
        f.write("\n")


if __name__ == "__main__":
    main()
