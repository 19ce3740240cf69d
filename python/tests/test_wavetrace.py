"""The Python package against the CLI: same images bit for bit, a steady camera
loop, errors as exceptions, Ctrl-C. Small renders throughout (lavapipe in CI)."""

import os
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import wavetrace as wt

from conftest import CBOX

RES, SPP, SEED = 32, 4, 7


def cli_render(cli, scene, out, *args):
    """The CLI's render on the driver this process has: a machine's driver record
    (`wavetrace driver --calibrate`) would start the CLI again under a newer driver,
    which rounds differently, and the library never switches drivers."""
    subprocess.run(
        [str(cli), "render", str(scene), "-q", "-o", str(out), *args],
        check=True,
        capture_output=True,
        env={**os.environ, "WAVETRACE_DRIVER": "system"},
    )
    return wt.read(out)


def rgb(image):
    """The R, G, B channels of an image, in that order (EXR files sort them)."""
    return np.stack([np.asarray(image)[:, :, image.channels.index(c)] for c in "RGB"], -1)


def cbox_dict(file_scene):
    """The Cornell box of cbox_path.xml as a Mitsuba scene dictionary; the camera's
    matrix is the one the file's lookat gives (a float32 matrix, exactly)."""
    meshes = CBOX.parent / "meshes"

    def mesh(name, bsdf, **extra):
        return {"type": "obj", "filename": str(meshes / f"{name}.obj"),
                "bsdf": {"type": "ref", "id": bsdf}, **extra}

    def diffuse(r, g, b):
        return {"type": "diffuse", "reflectance": {"type": "rgb", "value": [r, g, b]}}

    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 6},
        "sensor": {
            "type": "perspective",
            "fov_axis": "smaller",
            "near_clip": 10.0,
            "far_clip": 2800.0,
            "fov": 39.3077,
            "to_world": file_scene.camera_to_world,
            "sampler": {"type": "independent", "sample_count": SPP},
            "film": {"type": "hdrfilm", "width": RES, "height": RES,
                     "rfilter": {"type": "box"}, "component_format": "float32"},
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


def test_load_file_and_load_dict_match_the_cli_bit_for_bit(cli, cbox_f32, tmp_path):
    ref = cli_render(cli, cbox_f32, tmp_path / "cli.exr",
                     "-D", f"res={RES}", "-D", f"spp={SPP}", "--seed", str(SEED))
    scene = wt.load_file(cbox_f32, res=RES, spp=SPP)
    image = wt.render(scene, seed=SEED)
    assert image.dtype == np.float32 and image.shape == (RES, RES, 3)
    assert image.channels == ["R", "G", "B"]
    assert np.asarray(image).mean() > 0.01
    np.testing.assert_array_equal(rgb(image), rgb(ref))

    from_dict = wt.load_dict(cbox_dict(scene))
    assert from_dict.info()["triangles"] == scene.info()["triangles"]
    np.testing.assert_array_equal(rgb(wt.render(from_dict, seed=SEED)), rgb(ref))

    # Another seed is another image; the same seed again the same one.
    other = wt.render(scene, seed=SEED + 1)
    assert not np.array_equal(rgb(other), rgb(ref))
    np.testing.assert_array_equal(rgb(wt.render(scene, seed=SEED)), rgb(ref))


def test_write_read_and_png(tmp_path, cbox_f32):
    image = wt.render(wt.load_file(cbox_f32, res=16, spp=1))
    wt.write(tmp_path / "a.exr", image)
    np.testing.assert_array_equal(rgb(wt.read(tmp_path / "a.exr")), np.asarray(image))
    png = image._repr_png_()
    assert png.startswith(b"\x89PNG")
    wt.write(tmp_path / "a.png", image)
    assert (tmp_path / "a.png").read_bytes() == png


def rss_bytes():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    raise RuntimeError("no VmRSS")


def test_200_camera_poses_keep_memory_flat_and_time_steady(cbox_f32):
    scene = wt.load_file(cbox_f32, res=RES, spp=1)
    base = scene.camera_to_world
    centre = np.array([278.0, 273.0, 280.0])
    times, rss = [], None
    for i in range(210):
        a = 0.3 * np.sin(i * 0.1)
        origin = centre + np.array([1080 * np.sin(a), 0.0, -1080 * np.cos(a)])
        scene.set_camera(to_world=wt.look_at(origin, centre, [0, 1, 0]))
        t = time.perf_counter()
        image = wt.render(scene, spp=2, seed=i)
        times.append(time.perf_counter() - t)
        assert np.isfinite(np.asarray(image)).all()
        if i == 9:  # after the first renders have set everything up
            rss = rss_bytes()
    grown = rss_bytes() / rss - 1
    assert grown < 0.05, f"RSS grew {grown:.1%} over 200 renders"
    # Steady: the fastest renders (what the machine's other load leaves alone) of the
    # last 50 no slower than those of the first 50 after set-up; the medians, which
    # the load does move, within a looser bound.
    early, late = np.array(times[10:60]), np.array(times[-50:])
    fast = lambda t: np.sort(t)[:10].mean()  # noqa: E731
    assert fast(late) < 1.5 * fast(early) + 0.002, (
        f"per-render time {fast(early) * 1e3:.1f} -> {fast(late) * 1e3:.1f} ms (fastest 10)")
    assert np.median(late) < 3 * np.median(early) + 0.010, (
        f"per-render time {np.median(early) * 1e3:.1f} -> {np.median(late) * 1e3:.1f} ms (median)")
    # The camera moved: the scene's matrix is the last pose, not the file's.
    assert not np.allclose(scene.camera_to_world, base)


@pytest.mark.parametrize(
    "bad, key",
    [
        ({"type": "scene", "s": {"type": "sphere", "bsdf": {"type": "no_such_bsdf"}}},
         "scene['s']['bsdf']"),
        ({"type": "scene", "s": {"type": "sphere", "radius": {1, 2}}}, "scene['s']['radius']"),
        ({"type": "scene", "s": {"type": "sphere", "bsdf": {"kind": "diffuse"}}},
         "scene['s']['bsdf']"),
        ({"type": "scene", "s": {"type": "sphere", "bsdf": {"type": "diffuse",
          "reflectance": {"type": "rgb", "value": "red"}}}},
         "scene['s']['bsdf']['reflectance']['value']"),
        # An error the loader finds (an unknown parameter), reported at its key.
        ({"type": "scene", "s": {"type": "sphere", "bsdf": {"type": "diffuse",
          "colour": 0.5}}}, "scene['s']['bsdf']['colour']"),
        ({"type": "scene", "s": 3}, "scene['s']"),
        ({"type": "integrator"}, "scene['type']"),
    ],
)
def test_a_bad_dict_raises_value_error_naming_the_key(bad, key):
    with pytest.raises(ValueError) as e:
        wt.load_dict(bad)
    assert key in str(e.value), str(e.value)


def test_errors_are_python_exceptions(tmp_path, cbox_f32):
    with pytest.raises(ValueError, match="no_such_file.xml"):
        wt.load_file(tmp_path / "no_such_file.xml")
    bad = tmp_path / "bad.xml"
    bad.write_text('<scene version="3.0.0">\n<shape type="sphere">\n'
                   '<float name="radius" value="x"/>\n</shape>\n</scene>\n')
    with pytest.raises(ValueError, match=r"bad.xml:3"):
        wt.load_file(bad)
    scene = wt.load_file(cbox_f32, res=8, spp=1)
    with pytest.raises(ValueError):
        wt.render(scene, spp=0)
    with pytest.raises(ValueError):
        wt.render(scene, integrator="no_such_integrator")
    with pytest.raises(ValueError):
        scene.set_camera(fov=400)
    with pytest.raises(IndexError):
        scene.set_emitter_radiance(5, 1.0)
    # The scene still renders after all that.
    assert np.isfinite(np.asarray(wt.render(scene))).all()


def test_parameter_updates(cbox_f32):
    scene = wt.load_file(cbox_f32, res=RES, spp=SPP)
    a = np.asarray(wt.render(scene, seed=1)).copy()
    scene.set_emitter_radiance(0, [34, 24, 8])
    b = np.asarray(wt.render(scene, seed=1))
    np.testing.assert_allclose(b, 2 * a, rtol=1e-4, atol=1e-6)
    scene.set_emitter_radiance(0, [17, 12, 4])
    red = scene.info()["bsdfs"].index("diffuse")
    scene.set_bsdf_color(red, [0, 0, 0])
    assert np.asarray(wt.render(scene, seed=1)).mean() < a.mean()
    scene.fov = 20.0
    assert abs(scene.fov - 20.0) < 1e-6


def test_progress_callback(cbox_f32):
    calls = []
    wt.render(wt.load_file(cbox_f32, res=16, spp=4), progress=lambda d, t: calls.append((d, t)))
    assert calls and calls[-1][0] == calls[-1][1]


def test_ctrl_c_stops_a_long_render_within_a_second(cbox_f32):
    scene = wt.load_file(cbox_f32, res=64, spp=1)
    wt.render(scene, spp=1)  # set up outside the timed part
    sent = []

    def interrupt():
        sent.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)

    timer = threading.Timer(0.5, interrupt)
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        wt.render(scene, spp=100000)
    late = time.perf_counter() - sent[0]
    timer.join()
    assert late < 1.0, f"KeyboardInterrupt {late:.2f} s after SIGINT"
    image = wt.render(scene, spp=2)
    assert np.isfinite(np.asarray(image)).all() and np.asarray(image).mean() > 0


def test_devices_and_info(cbox_f32):
    devs = wt.devices()
    assert devs and all({"index", "name", "kind"} <= set(d) for d in devs)
    info = wt.load_file(cbox_f32).info()
    assert info["emitters"] == 1 and info["triangles"] > 0 and info["film_size"] == (128, 128)
