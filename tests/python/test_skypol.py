#!/usr/bin/python3
"""The Python module as a notebook uses it, checked against the CLI (ctest python/module).

Run by ctest with Debian's /usr/bin/python3 and the environment tests/python/CMakeLists.txt sets:
PYTHONPATH (the build's python/ folder), SKYPOL_BIN (the CLI under test), SKYPOL_SOURCE_DIR.
Expected values come from the CLI's own files and output, never from the module under test.
"""

import json
import os
import re
import shutil
import subprocess
import tempfile
import threading
import unittest

import numpy as np

import skypol

SKYPOL = os.environ.get("SKYPOL_BIN", "build/skypol")
ROOT = os.environ.get("SKYPOL_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
MARSEILLE = os.path.join(ROOT, "scenes", "skypole-marseille.toml")
DOFP = os.path.join(ROOT, "scenes", "skypole-marseille-dofp.toml")


def cli(*args, check=True):
    r = subprocess.run([SKYPOL, *args], capture_output=True, text=True)
    if check and r.returncode != 0:
        raise AssertionError(f"skypol {' '.join(args)} failed ({r.returncode}): {r.stderr}")
    return r


def same_bits(a, b):
    """Equal bit for bit (NaN-safe, −0 ≠ +0): the float32 arrays as uint32."""
    a = np.ascontiguousarray(a, dtype=np.float32)
    b = np.ascontiguousarray(b, dtype=np.float32)
    return a.shape == b.shape and np.array_equal(a.view(np.uint32), b.view(np.uint32))


class Tmp(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="skypol-py-")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def path(self, name):
        return os.path.join(self.dir, name)


class RenderMatchesCli(Tmp):
    """A stack rendered into NumPy equals, bit for bit, the stack `skypol render` writes."""

    def check_scene(self, scene_file, overrides):
        # Bit for bit at float precision: the file's default pixel type is half (docs/scenes.md).
        overrides = dict(overrides, **{"output.pixel_type": '"float"'})
        out = self.path("cli.exr")
        cli("render", "-q", scene_file, *sum((["--set", f"{k}={v}"] for k, v in overrides.items()), []), "-o", out)
        scene = skypol.load_scene(scene_file, overrides=overrides)
        mine = skypol.render_stack(scene)
        theirs = skypol.read_stack(out)
        self.assertEqual(len(mine), len(scene.times))
        self.assertEqual(len(mine), len(theirs))
        self.assertEqual(sorted(mine.channel_names), sorted(theirs.channel_names))
        for a, b in zip(mine, theirs):
            self.assertEqual(a.time, b.time)
            for name in theirs.channel_names:
                self.assertTrue(same_bits(a[name], b[name]), f"frame {a.index} channel {name} differs")
            self.assertAlmostEqual(a.truth["sun"]["azimuth_deg"], b.truth["sun"]["azimuth_deg"], places=9)
            self.assertEqual(a.truth["pole_pixel"] is None, b.truth["pole_pixel"] is None)
        return out, mine

    def test_ideal_stokes_bit_for_bit(self):
        out, mine = self.check_scene(MARSEILLE, {"camera.binning": 16})
        # The same file through an independent reader (OpenImageIO), where Debian's is installed.
        try:
            import OpenImageIO as oiio
        except ImportError:
            return
        inp = oiio.ImageInput.open(out)
        self.assertIsNotNone(inp)
        try:
            for i in (0, len(mine) - 1):
                self.assertTrue(inp.seek_subimage(i, 0))
                names = list(inp.spec().channelnames)
                pixels = inp.read_image(format="float")
                for name in ("S0.Y", "DoLP.Y", "AoLP.Y", "mask"):
                    self.assertTrue(same_bits(pixels[:, :, names.index(name)], mine[i][name]), name)
        finally:
            inp.close()

    def test_sensor_scene_bit_for_bit(self):
        # The DoFP sensor's noise is keyed by frame index: frames=[…] keeps the CLI's keys.
        self.check_scene(DOFP, {"camera.binning": 16, "time.step_min": 240})

    def test_frame_subset_keeps_the_scene_index(self):
        scene = skypol.load_scene(DOFP, overrides={"camera.binning": 16, "time.step_min": 240})
        whole = skypol.render_stack(scene)
        one = skypol.render_frame(scene, 2)
        for name in whole.channel_names:
            self.assertTrue(same_bits(whole[2][name], one[name]), name)

    def test_iter_frames_is_render_stack(self):
        for scene_file, overrides, band in ((MARSEILLE, {"camera.binning": 16}, "Y"),
                                            (DOFP, {"camera.binning": 16, "time.step_min": 240}, "R")):
            scene = skypol.load_scene(scene_file, overrides=overrides)
            whole = skypol.render_stack(scene)
            frames = list(skypol.iter_frames(scene, copy=True))
            self.assertEqual(len(frames), len(whole))
            for a, b in zip(frames, whole):
                self.assertEqual(a.time, b.time)
                for name in whole.channel_names:
                    self.assertTrue(same_bits(a[name], b[name]), f"{scene_file} frame {a.index} {name}")
        # Without a sensor (and without copy) every frame is rendered into the same memory.
        scene = skypol.load_scene(MARSEILLE, overrides={"camera.binning": 16})
        self.assertEqual(len({f["S0.Y"].__array_interface__["data"][0] for f in skypol.iter_frames(scene)}), 1)

    def test_arrays_share_the_stack_memory(self):
        scene = skypol.load_scene(MARSEILLE, overrides={"camera.binning": 16})
        stack = skypol.render_stack(scene, frames=[0, 5])
        a = stack[1]["DoLP.Y"]
        self.assertFalse(a.flags.owndata)  # a view of the frame's vector, not a copy
        self.assertEqual(a.dtype, np.float32)
        again = stack._h.channel(1, "DoLP.Y")
        self.assertEqual(a.__array_interface__["data"][0], again.__array_interface__["data"][0])
        self.assertEqual(a.shape, (scene.camera.height, scene.camera.width))

    def test_render_releases_the_gil(self):
        scene = skypol.load_scene(MARSEILLE, overrides={"camera.binning": 2})
        started = threading.Event()

        def work():
            started.set()
            skypol.render_stack(scene, frames=range(4))

        t = threading.Thread(target=work)
        t.start()
        started.wait()
        spins = 0
        while t.is_alive():
            spins += 1
        t.join()
        self.assertGreater(spins, 1000, "the main thread did not run while rendering: GIL held?")


class ErrorsWithLocation(Tmp):
    """Bad input raises skypol.SceneError carrying file, line, column and key; its text is the CLI's."""

    def cli_error(self, *args):
        r = cli(*args, check=False)
        self.assertEqual(r.returncode, 2, r.stderr)
        return r.stderr.strip().splitlines()[0]

    def test_unknown_key_in_a_file(self):
        bad = self.path("bad.toml")
        with open(MARSEILLE) as f:
            text = f.read().replace("tilt_deg = 0 ", "tilt_deg = 0\nfov_degs = 3 ", 1)
        with open(bad, "w") as f:
            f.write(text)
        line = next(i for i, l in enumerate(text.splitlines(), 1) if l.startswith("fov_degs"))
        with self.assertRaises(skypol.SceneError) as c:
            skypol.load_scene(bad)
        e = c.exception
        self.assertIsInstance(e, ValueError)
        self.assertEqual(e.file, bad)
        self.assertEqual(e.line, line)
        self.assertEqual(e.column, 1)
        self.assertEqual(e.key, "camera.fov_degs")
        self.assertEqual(str(e), self.cli_error("render", bad, "-o", self.path("x.exr")))

    def test_value_out_of_range_in_an_override(self):
        with self.assertRaises(skypol.SceneError) as c:
            skypol.load_scene(MARSEILLE, overrides={"camera.tilt_deg": 500})
        e = c.exception
        self.assertEqual(e.file, "--set")
        self.assertEqual(e.key, "camera.tilt_deg")
        self.assertIsNotNone(e.line)
        self.assertEqual(str(e), self.cli_error("render", MARSEILLE, "--set", "camera.tilt_deg=500", "-o",
                                                self.path("x.exr")))

    def test_strings_in_a_list_override_are_quoted_as_toml(self):
        # Inside a list a string becomes a TOML basic string (the C++ scene::toml_quoted): quote,
        # backslash and control characters escaped, so that Python's own TOML reader gives the list back.
        import tomllib
        strings = ['a"b\\c', "tab\there", "line\nbreak", "\x01\x7f", "é"]
        text = skypol._toml_value(strings)
        self.assertEqual(text, '["a\\"b\\\\c", "tab\\there", "line\\nbreak", "\\u0001\\u007f", "é"]')
        self.assertEqual(tomllib.loads("x = " + text)["x"], strings)
        # A newline in a channel's name reaches the loader as the name (a raw newline would be a TOML
        # syntax error), which names the key, as the CLI does for the same assignment.
        with self.assertRaises(skypol.SceneError) as c:
            skypol.load_scene(MARSEILLE, overrides={"output.channels": ["S0", "Do\nLP"]})
        self.assertEqual(c.exception.key, "output.channels")
        self.assertIn("unknown channel 'Do\nLP'", str(c.exception))
        self.assertEqual(str(c.exception).splitlines()[0],
                         self.cli_error("render", MARSEILLE, "--set", 'output.channels=["S0", "Do\\nLP"]', "-o",
                                        self.path("x.exr")))

    def test_toml_syntax_in_text(self):
        with self.assertRaises(skypol.SceneError) as c:
            skypol.parse_scene("[site]\nlatitude_deg = = 3\n", "notebook.toml")
        self.assertEqual((c.exception.file, c.exception.line), ("notebook.toml", 2))
        self.assertTrue(str(c.exception).startswith("notebook.toml:2:"))

    def test_not_a_stack(self):
        junk = self.path("junk.exr")
        with open(junk, "w") as f:
            f.write("not an EXR file")
        with self.assertRaises(skypol.SceneError) as c:
            skypol.read_stack(junk)
        self.assertEqual(c.exception.file, junk)
        self.assertIsNone(c.exception.line)
        self.assertEqual(str(c.exception), self.cli_error("estimate", junk))

    def test_bad_estimator_name(self):
        scene = skypol.load_scene(MARSEILLE, overrides={"camera.binning": 16, "time.step_min": 240})
        with self.assertRaisesRegex(ValueError, "classic"):
            skypol.estimate(skypol.render_stack(scene), "clasic")


class CaptureHasNoScore(Tmp):
    """An imported capture (skypol import) says its truth is unknown, and Python scores nothing."""

    def test_capture_truth_unknown(self):
        rendered = self.path("rendered.exr")
        cli("render", "-q", DOFP, "--set", "camera.binning=16", "--set", 'time.day_end="08:00"',
            "--set", 'output.channels=["DoLP","AoLP","mask","raw"]', "-o", rendered)
        raw = self.path("raw")
        cli("export", rendered, "-c", "raw", "-f", "npy", "-o", raw)
        capture = self.path("capture.toml")
        with open(capture, "w") as f:
            f.write('[capture]\nframes = ["raw/rendered_*.npy"]\ntimes = "name"\n'
                    'time_format = "rendered_*_%Y%m%dT%H%M%SZ.npy"\n'
                    '[camera]\nlens_preset = "fujinon_fe185c057ha1"\nsensor_preset = "lucid_phx050s_qc"\n'
                    'binning = 16\n[sensor]\npreset = "lucid_phx050s_qc"\n')
        out = self.path("capture.exr")
        cli("import", capture, "-o", out)
        cap, ren = skypol.read_stack(out), skypol.read_stack(rendered)
        self.assertFalse(cap.truth_known)
        self.assertFalse(cap.site_known)
        self.assertTrue(ren.truth_known)
        e = skypol.estimate(cap, "great_circle")
        self.assertIsNone(e.score)
        r = skypol.estimate(ren, "great_circle")
        if r.valid:
            self.assertIsNotNone(r.score)
            # The same north within the stated cone, not to the bit: the imported stack carries
            # S0, which the sky mask reads (saturated and dark pixels), the rendered one does not.
            self.assertTrue(e.valid)
            self.assertLess(abs(e.heading_deg - r.heading_deg), r.cone95_deg)


class EstimatesMatchCli(Tmp):
    """A stack rendered in Python and one rendered by the CLI estimate the same north."""

    SCENE = {"camera.binning": 8, "camera.heading_deg": 30}

    def test_same_north(self):
        out = self.path("cli.exr")
        cli("render", "-q", MARSEILLE, "--set", "camera.binning=8", "--set", "camera.heading_deg=30",
            "--set", 'output.pixel_type="float"', "-o", out)  # the same bits as render_stack's floats
        methods = ["classic", "great_circle", "sun_vector"]
        theirs = json.loads(cli("estimate", out, "-m", ",".join(methods), "--json").stdout)
        theirs = {r["method"]: r for r in theirs}
        stack = skypol.render_stack(skypol.load_scene(MARSEILLE, overrides=self.SCENE))
        for e in skypol.estimate(stack, methods):
            self.assertIsInstance(e, skypol.Estimate)
            self.assertTrue(e.valid, e.why_invalid)
            t = theirs[e.method]
            self.assertTrue(t["valid"], t)
            # The CLI prints 6 decimals; the inputs are the same bits, so only printing separates them.
            self.assertAlmostEqual(e.heading_deg, t["heading_deg"], delta=1e-5, msg=e.method)
            self.assertAlmostEqual(e.latitude_deg, t["latitude_deg"], delta=1e-5, msg=e.method)
            self.assertLess(abs(e.score["bearing_error_deg"]), 2.0, e.method)
            self.assertGreater(e.seconds, 0)

    def test_registry_and_site(self):
        # The registry is the CLI's (`skypol methods --json`), and method_names() its names and auto.
        reg = skypol.methods()
        self.assertEqual(reg, json.loads(cli("methods", "--json").stdout))
        self.assertEqual(list(skypol.method_names()), [m["name"] for m in reg] + ["auto"])
        site = [m["name"] for m in reg if m["needs_site"]]
        self.assertEqual(site, ["sun_vector_ephemeris"])
        self.assertIsNone(next(m for m in reg if m["name"] == "classic")["calibration"]["max_residual_deg"])
        # site="unknown" as --site unknown: the ephemeris refuses the input, saying why (as on a capture
        # without its site); auto leaves it out.
        scene = skypol.load_scene(MARSEILLE, overrides={"camera.binning": 16, "time.step_min": 60})
        stack = skypol.render_stack(scene)
        with self.assertRaisesRegex(ValueError, "--site unknown"):
            skypol.estimate(stack, "sun_vector_ephemeris", site="unknown")
        self.assertTrue(skypol.estimate(stack, "sun_vector_ephemeris").valid)
        a = skypol.estimate(stack, "auto", site="unknown")
        self.assertNotIn("sun_vector_ephemeris", a.note)
        with self.assertRaisesRegex(ValueError, "stack or unknown"):
            skypol.estimate(stack, "auto", site="nowhere")

    def test_arrays_and_times(self):
        scene = skypol.load_scene(MARSEILLE, overrides=self.SCENE)
        stack = skypol.render_stack(scene, channels=["DoLP", "AoLP", "mask"])
        on_stack = skypol.estimate(stack, "classic")
        arrays = {name: stack.channel(name) for name in ("DoLP.Y", "mask")}
        on_arrays = skypol.estimate(arrays, "classic", scene=scene, times=scene.iso_times)
        self.assertAlmostEqual(on_arrays.heading_deg, on_stack.heading_deg, delta=1e-9)
        self.assertAlmostEqual(on_arrays.latitude_deg, on_stack.latitude_deg, delta=1e-9)
        # A bare DoLP array is the DoLP of the scene's first band.
        bare = skypol.estimate(stack.channel("DoLP.Y"), "classic", scene=scene, times=stack.times)
        self.assertTrue(bare.valid, bare.why_invalid)
        self.assertLess(abs(bare.score["bearing_error_deg"]), 2.0)
        d = skypol.estimate(stack, "classic", as_dict=True)
        self.assertEqual(set(d), set(skypol.Estimate.__dataclass_fields__))
        self.assertEqual(d["heading_deg"], on_stack.heading_deg)

    def test_write_arrays_read_back(self):
        scene = skypol.load_scene(MARSEILLE, overrides={"camera.binning": 16, "time.step_min": 120})
        stack = skypol.render_stack(scene)
        arrays = {name: stack.channel(name) for name in stack.channel_names}
        out = self.path("arrays.exr")
        skypol.write_stack(out, arrays, scene=scene, times=stack.times)
        back = skypol.read_stack(out)
        self.assertEqual(len(back), len(stack))
        for a, b in zip(stack, back):
            self.assertEqual(a.time, b.time)
            for name in stack.channel_names:
                self.assertTrue(same_bits(a[name], b[name]), name)
        info = cli("info", out).stdout  # the CLI reads it as its own
        self.assertIn(stack[0].time, info)


class Lens(unittest.TestCase):
    """pixel → direction → pixel returns the pixel; both agree with `skypol lens`."""

    def test_round_trip_and_cli(self):
        scene = skypol.load_scene(MARSEILLE, overrides={"camera.binning": 4, "camera.heading_deg": 30,
                                                        "camera.tilt_deg": 10})
        cam = scene.camera
        v, u = np.mgrid[0:cam.height:7, 0:cam.width:5].astype(np.float64)
        d = cam.pixel_to_direction(u, v)
        self.assertEqual(d["direction"].shape, u.shape + (3,))
        ok = d["valid"]
        self.assertGreater(ok.mean(), 0.3)  # the image circle on a 4:3 sensor: 44 % of the pixels
        self.assertTrue(np.isnan(d["azimuth_deg"][~ok]).all())
        back = cam.direction_to_pixel(d["azimuth_deg"][ok], d["elevation_deg"][ok])
        self.assertTrue(back["valid"].all())
        # Floored by the degrees round trip and the lens inverse: far below a pixel.
        self.assertLess(np.abs(back["u"] - u[ok]).max(), 1e-6)
        self.assertLess(np.abs(back["v"] - v[ok]).max(), 1e-6)
        enu = cam.direction_to_pixel(direction=d["direction"][ok])
        self.assertLess(np.abs(enu["u"] - u[ok]).max(), 1e-6)

        scene_file = os.path.join(tempfile.mkdtemp(prefix="skypol-py-"), "s.toml")
        try:
            with open(scene_file, "w") as f:
                f.write(scene.text)
            out = cli("lens", scene_file, "-p", "200.5,180.25", "-d", "123.4,56.7").stdout
            m = re.search(r"direction az\s+([-\d.]+) el\s+([-\d.]+) deg \(([-\d.]+) deg off", out)
            p = cam.pixel_to_direction(200.5, 180.25)
            self.assertAlmostEqual(float(p["azimuth_deg"]), float(m.group(1)), delta=6e-4)
            self.assertAlmostEqual(float(p["elevation_deg"]), float(m.group(2)), delta=6e-4)
            self.assertAlmostEqual(float(p["off_axis_deg"]), float(m.group(3)), delta=6e-4)
            m = re.search(r"pixel \(([-\d.]+), ([-\d.]+)\)", out.splitlines()[-1])
            q = cam.direction_to_pixel(123.4, 56.7)
            self.assertAlmostEqual(float(q["u"]), float(m.group(1)), delta=6e-5)
            self.assertAlmostEqual(float(q["v"]), float(m.group(2)), delta=6e-5)
        finally:
            shutil.rmtree(os.path.dirname(scene_file))


class Sun(unittest.TestCase):
    """The sun for arrays of times equals `skypol sun` for each."""

    def test_matches_cli(self):
        times = ["2022-09-23T06:00:00Z", "2022-09-23T12:30:00+02:00", "2010-06-15T00:30:00Z"]
        r = skypol.sun_position(43.28699, 5.40336, times, height_m=60, pressure_hpa=1013)
        self.assertEqual(r["azimuth_deg"].shape, (3,))
        self.assertEqual(r["direction"].shape, (3, 3))
        for i, t in enumerate(times):
            out = cli("sun", "--lat", "43.28699", "--lon", "5.40336", "--height", "60", "--pressure", "1013",
                      "-t", t).stdout
            for key, name in (("azimuth_deg", "azimuth"), ("elevation_deg", "elevation"),
                              ("declination_deg", "declination"), ("hour_angle_deg", "hour angle")):
                expected = float(re.search(rf"^{name}\s+([-\d.]+)", out, re.M).group(1))
                self.assertAlmostEqual(float(r[key][i]), expected, delta=6e-7, msg=f"{key} at {t}")

    def test_time_forms_agree(self):
        import datetime as dt
        t = skypol.parse_time("2022-09-23T10:30:00Z")
        forms = [t, "2022-09-23T12:30:00+02:00", np.datetime64("2022-09-23T10:30:00"),
                 dt.datetime(2022, 9, 23, 10, 30, tzinfo=dt.timezone.utc)]
        az = [float(skypol.sun_position(43.3, 5.4, f)["azimuth_deg"]) for f in forms]
        self.assertEqual(len(set(az)), 1)
        with self.assertRaisesRegex(ValueError, "zone"):
            skypol.sun_position(43.3, 5.4, "2022-09-23T10:30:00")

    def test_scene_truth_is_the_sun(self):
        scene = skypol.load_scene(MARSEILLE, overrides={"camera.binning": 16})
        s = scene.sun_positions()
        self.assertAlmostEqual(scene.truth(scene.times[3])["sun"]["azimuth_deg"], s["azimuth_deg"][3], places=12)


class PlotMatchesCli(Tmp):
    """skypol.plot_estimate draws what `skypol estimate --plot` draws, from the same C++."""

    def test_same_picture_and_marks(self):
        import matplotlib.image as mpimg
        out = self.path("m.exr")
        cli("render", "-q", MARSEILLE, "--set", "camera.binning=16", "--set", "camera.heading_deg=30", "-o", out)
        # The channels `skypol estimate` reads (skypole/report.h estimator_channels).
        stack = skypol.read_stack(out)
        names = [c for c in stack.channel_names if c == "mask" or c.startswith(("DoLP.", "AoLP."))]
        stack = skypol.read_stack(out, names)
        e = skypol.estimate(stack, "sun_vector")
        self.assertTrue(e.valid, e.why_invalid)
        mine = self.path("py.png")
        self.assertEqual(skypol.plot_estimate(stack, e, mine), [mine])
        theirs = self.path("cli.png")
        cli("estimate", "-q", out, "-m", "sun_vector", "--plot", theirs)
        a, b = mpimg.imread(mine), mpimg.imread(theirs)
        self.assertEqual(a.shape, b.shape)
        self.assertTrue(np.array_equal(a, b), "the Python picture differs from the CLI's")
        # The answer's magenta x and the truth's white + in the first panel (the left third), as far
        # apart in picture pixels as the estimate's pixel and the truth's (one picture pixel per frame
        # pixel at this size).
        rgb = np.round(a[..., :3] * 255)
        # Above the legend, whose colour swatches (the first thing at x = 20 below the title) repeat the marks' colours.
        background = rgb[0, 0]
        legend_top = next(y for y in range(60, rgb.shape[0]) if not np.array_equal(rgb[y, 20], background))
        left = rgb[:legend_top, : rgb.shape[1] // 3]
        def centre(colour):
            ys, xs = np.nonzero(np.all(np.abs(left - colour) <= 1, axis=-1))
            self.assertGreater(len(xs), 9, colour)
            return np.array([xs.mean(), ys.mean()])
        truth = stack.truths[0]["pole_pixel"]
        shift = centre([255, 0, 255]) - centre([255, 255, 255])
        self.assertLess(np.hypot(*(shift - (np.array(e.pixel) - np.array(truth)))), 1.0)
        # A folder: one picture per estimate, named by its method; dicts work as Estimates do.
        folder = self.path("plots") + "/"
        d = skypol.estimate(stack, "great_circle", as_dict=True)
        self.assertEqual(skypol.plot_estimate(stack, [e, d], folder),
                         [folder + "sun_vector.png", folder + "great_circle.png"])


if __name__ == "__main__":
    unittest.main(verbosity=2)
