#!/usr/bin/python3
"""The Marseille skylight database import (skypol.marseille, scripts/import-marseille): ctest
python/marseille.

A miniature of the database in its exact layout (marseille_miniature.py) is written from frames
skypol renders through the colour DoFP sensor; importing it must give back the rendered frames'
channels bit for bit, their estimates, the truth and the times. The layout diagnostic must name
the layout synthetic captures were written in and refuse an overcast sky; bad input must fail
cleanly, naming the file and row, with nothing written; reading stays within a few frames of memory.
"""

import json
import os
import pickle
import random
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import skypol
from skypol import marseille
from skypol.marseille_pickle import MarseilleError, load_object_array

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import marseille_miniature as mm  # noqa: E402

ROOT = os.environ.get("SKYPOL_SOURCE_DIR", os.path.join(HERE, "..", ".."))
IMPORT = os.path.join(ROOT, "scripts", "import-marseille")
LAYOUT = (0, 45, 135, 90)


def run_import(*args):
    return subprocess.run([sys.executable, IMPORT, *args], capture_output=True, text=True)


class Tmp(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="skypol-marseille-")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def path(self, *names):
        return os.path.join(self.dir, *names)


class Miniature(Tmp):
    """The miniature imported by the command gives back the rendered frames, estimates, truth, times."""

    @classmethod
    def setUpClass(cls):
        cls.top = tempfile.mkdtemp(prefix="skypol-marseille-mini-")
        cls.mini = mm.make(cls.top)
        cls.out = os.path.join(cls.top, "out")
        # The command with the miniature's own [sensor] numbers, so the demosaic is the render's.
        cal = marseille.read_calibration(os.path.join(cls.mini.root, "calib"))
        cls.written = marseille.import_day(cls.mini.day_files[0], cal, cls.out, windows_min=[0, 240],
                                           sensor_toml=mm.sensor_toml(LAYOUT), half=False)
        cls.stack = skypol.read_stack(cls.written[0].path)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.top, ignore_errors=True)

    def test_channels_are_the_rendered_frames_cropped(self):
        r0, r1, c0, c1 = mm.CROP
        ref = self.mini.reference["2022-07-30"]
        self.assertEqual(len(self.stack), len(ref))
        for k, f in enumerate(self.stack):
            for c in ["S0.R", "S1.G", "S2.B", "DoLP.R", "AoLP.G", "AoLP.B", "mask", "clipped", "R"]:
                want = ref[k][c][r0:r1, c0:c1]
                self.assertTrue(np.array_equal(f[c], want), f"frame {k} channel {c}")
            # every sky pixel of the full sensor lies inside the crop
            self.assertEqual(ref[k]["mask"].sum(), f["mask"].sum())

    def test_times_and_truth_are_the_scenes(self):
        scene = skypol.parse_scene(self.mini.scene_text)
        for k, f in enumerate(self.stack):
            self.assertEqual(f.truth["unix_seconds"], self.mini.times[k])
            want = scene.truth(self.mini.times[k])
            np.testing.assert_allclose(f.truth["world_from_camera"], want["world_from_camera"], atol=1e-12)
            self.assertAlmostEqual(f.truth["heading_deg"], want["heading_deg"], places=9)
            self.assertAlmostEqual(f.truth["sun"]["azimuth_deg"], want["sun"]["azimuth_deg"], places=9)
            # the pole's pixel moves with the crop
            u, v = f.truth["pole_pixel"]
            self.assertAlmostEqual(u, want["pole_pixel"][0] - mm.CROP[2], places=6)
            self.assertAlmostEqual(v, want["pole_pixel"][1] - mm.CROP[0], places=6)
        self.assertTrue(self.stack.truth_known)

    def test_estimates_are_the_rendered_stacks(self):
        scene = skypol.parse_scene(self.mini.scene_text)
        ref = self.mini.reference["2022-07-30"]
        arrays = {c: np.stack([r[c] for r in ref]) for c in ref[0] if c != "raw"}
        rendered = skypol.stack_from_arrays(scene, self.mini.times, arrays)
        valid = 0
        for m in ["great_circle", "sun_vector", "sun_vector_ephemeris", "sun_dolp", "classic"]:
            a, b = skypol.estimate(self.stack, m), skypol.estimate(rendered, m)
            self.assertEqual(a.valid, b.valid, m)
            if a.valid:
                valid += 1
                self.assertAlmostEqual(a.heading_deg, b.heading_deg, delta=1e-6, msg=m)
                self.assertAlmostEqual(a.latitude_deg, b.latitude_deg, delta=1e-6, msg=m)
                self.assertAlmostEqual(a.score["bearing_error_deg"], b.score["bearing_error_deg"], delta=1e-6, msg=m)
        self.assertGreaterEqual(valid, 3)

    def test_header_marks_the_truth_and_the_weather(self):
        import OpenImageIO as oiio
        inp = oiio.ImageInput.open(self.written[0].path)
        labels = []
        k = 0
        while inp.seek_subimage(k, 0):
            spec = inp.spec()
            self.assertIn("sun-fitted calibration", spec.getattribute("skypol:truthSource"))
            self.assertIn("not a survey", spec.getattribute("skypol:truthSource"))
            labels.append(spec.getattribute("skypol:weather"))
            self.assertEqual(spec.getattribute("skypol:imageType"), "3")
            k += 1
        inp.close()
        self.assertEqual(labels, list("cfcsbo"))

    def test_windows(self):
        w4 = [w for w in self.written if w.window_min == 240]
        self.assertEqual([len(w.rows) for w in w4], [2, 2, 2])  # 08, 10 | 12, 14 | 16, 18 local
        self.assertTrue(os.path.basename(w4[0].path).startswith("2022-07-30_240min_0600Z"))

    def test_command_writes_stacks_and_manifest(self):
        out = self.path("cli")
        r = run_import(self.mini.root, "-o", out, "--window", "0", "120", "-q")
        self.assertEqual(r.returncode, 0, r.stderr)
        names = sorted(os.listdir(out))
        self.assertIn("2022-07-30.exr", names)
        self.assertIn("manifest.csv", names)
        self.assertEqual(len([n for n in names if "_120min_" in n]), 6)
        self.assertFalse([n for n in names if n.startswith(".")], names)  # no temporary left
        with open(os.path.join(out, "manifest.csv")) as f:
            lines = f.read().splitlines()
        self.assertEqual(lines[0], "stack,window_min,part,utc,local_timestamp,row,image_type,exposure_us,weather")
        self.assertEqual(lines[1].split(",")[:6], ["2022-07-30.exr", "0", "0", "2022-07-30T06:00:07Z",
                                                   "2022-07-30T08-00-07", "1"])

    def test_binned_import(self):
        """--bin 2: the Stokes images are the full-resolution ones averaged over 2×2 blocks, the
        camera is read out binned (the pole pixel moves to (u + ½)/2 − ½), the estimate stays."""
        cal = marseille.read_calibration(os.path.join(self.mini.root, "calib"))
        w = marseille.import_day(self.mini.day_files[0], cal, self.path("b2"), binning=2, half=False,
                                 sensor_toml=mm.sensor_toml(LAYOUT))
        st = skypol.read_stack(w[0].path)
        self.assertEqual(st[0].shape, (64, 64))
        for k, f in enumerate(self.stack):
            full = f["mask"].reshape(64, 2, 64, 2).min(axis=(1, 3)) > 0
            self.assertTrue(np.array_equal(st[k]["mask"] > 0, full))
            for c in ("S0.B", "S1.R", "S2.G"):
                want = f[c].astype(np.float64).reshape(64, 2, 64, 2).mean(axis=(1, 3))
                np.testing.assert_allclose(st[k][c][full], want[full], rtol=1e-6, atol=1e-7)
            s1, s2, s0 = (st[k][f"S{i}.G"][full].astype(np.float64) for i in (1, 2, 0))
            np.testing.assert_allclose(st[k]["DoLP.G"][full], np.minimum(1, np.hypot(s1, s2) / s0), rtol=1e-5)
            u, v = f.truth["pole_pixel"]
            np.testing.assert_allclose(st[k].truth["pole_pixel"], [(u + 0.5) / 2 - 0.5, (v + 0.5) / 2 - 0.5], atol=1e-6)
        a, b = skypol.estimate(st, "sun_vector_ephemeris"), skypol.estimate(self.stack, "sun_vector_ephemeris")
        self.assertTrue(a.valid and b.valid)
        self.assertLess(abs(a.heading_deg - b.heading_deg), 0.5)
        with self.assertRaises(ValueError):
            marseille.import_day(self.mini.day_files[0], cal, self.path("b3"), binning=3)

    def test_fixed_exposure_frames(self):
        cal = marseille.read_calibration(os.path.join(self.mini.root, "calib"))
        w = marseille.import_day(self.mini.day_files[0], cal, self.path("t8"), frames="type:8", half=False)
        st = skypol.read_stack(w[0].path)
        self.assertEqual([float(t) for t in st.times], [t + 4 for t in self.mini.times])


class RealSkies(unittest.TestCase):
    """scripts/real-skies end to end on a miniature of two days: imports, estimates the real and the
    simulated skies, and writes the report; its errors are `skypol estimate`'s on the same stacks."""

    def test_report(self):
        out = os.environ.get("MARSEILLE_TEST_OUT") or tempfile.mkdtemp(prefix="skypol-real-skies-")
        shutil.rmtree(out, ignore_errors=True)
        db = os.path.join(out, "db")
        mm.make(db, day="2022-07-30", hours_local=(8, 11, 14, 17), labels="cc", fixed_types=False)
        mm.make(db, day="2022-07-31", hours_local=(9, 12, 15), labels="o", fixed_types=False)
        env = dict(os.environ, SKYPOL_CACHE_DIR=os.path.join(out, "cache"))
        r = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "real-skies"), db, "-o", os.path.join(out, "report"),
                            "--window", "420", "0", "--keep-stacks", "-q"], capture_output=True, text=True, env=env)
        self.assertEqual(r.returncode, 0, r.stderr)
        rep = os.path.join(out, "report")
        with open(os.path.join(rep, "real-skies.csv")) as f:
            import csv
            lines = list(csv.DictReader(f))
        methods = set(skypol.method_names())
        for src in ("real", "simulated"):
            self.assertEqual({l["method"] for l in lines if l["source"] == src}, methods)
        day = {(l["source"], l["method"], l["weather"]): l for l in lines if l["window_min"] == "0"}
        self.assertEqual(day[("real", "sun_vector_ephemeris", "all")]["windows"], "2")
        self.assertEqual(day[("real", "sun_vector_ephemeris", "c")]["windows"], "1")
        self.assertEqual(day[("real", "sun_vector_ephemeris", "o")]["windows"], "1")
        # the report's median over the two days, from skypol estimate run here on the imported stacks
        errs = []
        for d in ("2022-07-30", "2022-07-31"):
            e = subprocess.run([os.environ.get("SKYPOL_BIN", os.path.join(ROOT, "build", "skypol")), "estimate",
                                os.path.join(rep, "stacks", f"{d}.exr"), "-m", "sun_vector_ephemeris", "--json", "-q"],
                               capture_output=True, text=True)
            errs.append(abs(json.loads(e.stdout)[0]["bearing_error_deg"]))
        self.assertAlmostEqual(float(day[("real", "sun_vector_ephemeris", "all")]["median_abs_bearing_error_deg"]),
                               float(np.median(errs)), delta=1e-5)
        for l in lines:
            if l["cone95_coverage"]:
                self.assertTrue(0 <= float(l["cone95_coverage"]) <= 1)
        with open(os.path.join(rep, "real-skies.md")) as f:
            md = f.read()
        self.assertIn("sun-fitted calibration", md)
        self.assertIn("## Window: day", md)
        self.assertIn("| sun_vector_ephemeris | all | 2/2 |", md)
        # 420-minute windows: 08–14 h and 17 h local of the first day, 09–15 h of the second; the one
        # frame of 17 h is too few for any estimator (3 at least)
        win = {(l["source"], l["method"], l["weather"]): l for l in lines if l["window_min"] == "420"}
        self.assertEqual([win[("real", "sun_vector_ephemeris", w)][k] for w in ("all", "c") for k in ("windows", "answered")],
                         ["3", "2", "2", "1"])
        self.assertIn("## Window: 420 min", md)
        self.assertTrue(os.path.exists(os.path.join(rep, "sim", "2022-07-31.exr")))


class LayoutDiagnostic(Tmp):
    """Synthetic captures in each layout, a multiple-scattering-like sky (Berry's neutral points),
    decoded as the authors' layout: the diagnostic names the layout they were written in."""

    T = skypol.parse_time("2022-07-30T08:00:00Z")

    @classmethod
    def setUpClass(cls):
        cls.top = tempfile.mkdtemp(prefix="skypol-marseille-diag-")
        mm.write_calib(os.path.join(cls.top, "calib"))
        cls.cal = marseille.read_calibration(os.path.join(cls.top, "calib"))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.top, ignore_errors=True)

    def diagnose(self, layout, clouds=""):
        scene = skypol.parse_scene(mm.full_scene_text([skypol.format_time(self.T)], layout, 500.0,
                                                      sky='model = "berry"', clouds=clouds))
        raw = mm.crop_shift(skypol.render_frame(scene, 0, channels=["raw"])["raw"]) >> 4
        capture = skypol.parse_scene(marseille.scene_text(self.cal, [self.T], marseille.AUTHORS_LAYOUT))
        return marseille.diagnose_layout(raw, capture, self.T)

    def test_each_layout_is_named(self):
        for layout, s1, s2 in [((0, 45, 135, 90), 1, 1), ((90, 45, 135, 0), -1, 1), ((0, 135, 45, 90), 1, -1),
                               ((90, 135, 45, 0), -1, -1)]:
            d = self.diagnose(layout)
            self.assertTrue(d["decided"], d["reason"])
            self.assertEqual(d["layout"], marseille.layout_text(layout))
            self.assertEqual((d["s1_sign"], d["s2_sign"]), (s1, s2))
            best = d["scores"][d["layout"]]
            self.assertGreater(best, 0.9)
            # a turn by 90° inverts cos 2Δ: the layout with both pairs swapped scores −best
            turned = marseille.layout_text(marseille._swap(marseille._swap(layout, 0, 90), 45, 135))
            self.assertAlmostEqual(d["scores"][turned], -best, places=6)

    def test_overcast_is_refused(self):
        d = self.diagnose(LAYOUT, clouds="[sky.clouds]\ncoverage = 1.0\n")
        self.assertFalse(d["decided"])
        self.assertIsNone(d["layout"])
        self.assertIn("too cloudy", d["reason"])

    def test_command_diagnoses_and_writes_nothing(self):
        mini = mm.make(self.path("db2"), layout=(0, 135, 45, 90), hours_local=(9, 12), labels="c", fixed_types=False)
        r = run_import(mini.root, "-o", self.path("none"), "--diagnose", "-q")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stdout.splitlines()[-1], "layout: 0/135/45/90")
        self.assertIn("row 3 2022-07-30T12-00-07 (c): decided 0/135/45/90 scores", r.stdout)
        self.assertFalse(os.path.exists(self.path("none")))

    def test_import_auto_layout(self):
        mini = mm.make(self.path("db"), layout=(90, 45, 135, 0), hours_local=(9, 12, 15), labels="c")
        cal = marseille.read_calibration(os.path.join(mini.root, "calib"))
        notes = []
        w = marseille.import_day(mini.day_files[0], cal, self.path("out"), layout="auto", half=False,
                                 sensor_toml=mm.sensor_toml((90, 45, 135, 0)), progress=notes.append)
        self.assertTrue(any("90/45/135/0 scores" in n for n in notes), notes)
        st = skypol.read_stack(w[0].path)
        r0, r1, c0, c1 = mm.CROP
        self.assertTrue(np.array_equal(st[0]["AoLP.B"], mini.reference["2022-07-30"][0]["AoLP.B"][r0:r1, c0:c1]))


def small_day(path, rows=6, size=8, stamps=None):
    rng = np.random.default_rng(0)
    out = []
    for k in range(rows):
        img = (rng.integers(0, 4096, (size, size), dtype=np.uint16) << 4).astype(np.uint16)
        out.append((img, 100.0 + k, stamps[k] if stamps else f"2022-07-30T12-00-{10 + 2 * k:02d}", k))
    mm.write_day_file(path, out)


class BadInput(Tmp):
    """Each problem: exit 2, one line naming the file (and the row), no stack, no manifest."""

    def setUp(self):
        super().setUp()
        self.mini = mm.make(self.path("top"), hours_local=(10, 12), fixed_types=False)
        self.day = self.mini.day_files[0]
        self.out = self.path("out")

    def fails(self, *names):
        r = run_import(self.mini.root, "-o", self.out, "-q")
        self.assertEqual(r.returncode, 2, r.stderr)
        line = r.stderr.strip()
        self.assertEqual(len(line.splitlines()), 1, line)
        self.assertTrue(line.startswith("import-marseille: error: "), line)
        for n in names:
            self.assertIn(n, line)
        self.assertFalse(os.path.exists(self.out) and os.listdir(self.out), os.listdir(self.out) if os.path.exists(self.out) else "")
        return line

    def test_truncated_day_file(self):
        with open(self.day, "rb") as f:
            data = f.read()
        with open(self.day, "wb") as f:
            f.write(data[: len(data) * 2 // 3])
        self.fails(self.day, "truncated")

    def test_foreign_pickle_is_not_run(self):
        marker = self.path("ran")

        class Evil:
            def __reduce__(self):
                return (os.system, (f"touch {marker}",))

        a = np.empty((1, 4), dtype=object)
        a[0] = [Evil(), 1.0, "2022-07-30T12-00-00", 0]
        np.save(self.day, a)
        self.fails(self.day, "is not allowed")
        self.assertFalse(os.path.exists(marker))

    def test_missing_calib_file(self):
        os.remove(os.path.join(self.mini.root, "calib", "rot_mat.npy"))
        self.fails(os.path.join("calib", "rot_mat.npy"), "missing")

    def test_crop_that_does_not_fit_the_images(self):
        calib = os.path.join(self.mini.root, "calib")
        np.save(os.path.join(calib, "params_crop.npy"), np.array([8, 132, 16, 144]))
        self.assertIn("alpha_crop.npy: has shape (128, 128), expected (124, 128)", self.fails("alpha_crop.npy"))
        os.remove(os.path.join(calib, "alpha_crop.npy"))
        os.remove(os.path.join(calib, "theta_crop.npy"))
        self.fails(self.day, "row 0", "params_crop.npy")

    def test_crop_beyond_the_sensor(self):
        np.save(os.path.join(self.mini.root, "calib", "params_crop.npy"), np.array([100, 228, 16, 144]))
        self.fails("params_crop.npy", "does not fit")

    def test_timestamps_out_of_order(self):
        rows = [(mm.crop_shift(np.zeros(mm.FULL)), 100.0, s, t) for s, t in
                [("2022-07-30T12-00-00", 0), ("2022-07-30T12-00-02", 3), ("2022-07-30T11-59-58", 0)]]
        mm.write_day_file(self.day, rows)
        os.remove(self.day.replace("_raw.npy", "_raw_annotations.npy"))
        self.fails(self.day, "row 2", "before row 1")

    def test_annotations_that_do_not_match(self):
        ann = self.day.replace("_raw.npy", "_raw_annotations.npy")
        top, _ = load_object_array(ann)
        stamps = [top.data[2 * i] for i in range(top.shape[0])]
        stamps[1] = "2022-07-30T00-00-00"
        mm.write_annotations(ann, stamps, ["c"] * len(stamps))
        self.fails(ann, "row 1")

    def test_values_not_shifted(self):
        top_rows = marseille.read_day(self.day)
        rows = [(mm.crop_shift(np.zeros(mm.FULL)) + (1 if k == 1 else 0), r.exposure_us, r.stamp, r.image_type)
                for k, r in enumerate(top_rows)]
        mm.write_day_file(self.day, rows)
        self.fails(self.day, "row 1", "shifted")


class Fuzz(Tmp):
    """500 mutations of a small day file: each reads or fails with MarseilleError, nothing else."""

    def test_mutated_day_files(self):
        base = self.path("2022-07-30_raw.npy")
        small_day(base)
        with open(base, "rb") as f:
            good = f.read()
        rng = random.Random(7)
        outcomes = {"read": 0, "error": 0}
        path = self.path("m_raw.npy")
        for i in range(500):
            b = bytearray(good)
            kind = i % 4
            if kind == 0:  # flip bytes
                for _ in range(rng.randint(1, 8)):
                    b[rng.randrange(len(b))] = rng.randrange(256)
            elif kind == 1:  # truncate
                b = b[: rng.randrange(len(b))]
            elif kind == 2:  # drop a slice
                s = rng.randrange(len(b))
                del b[s: s + rng.randint(1, 64)]
            else:  # duplicate a slice
                s = rng.randrange(len(b))
                b[s:s] = b[s: s + rng.randint(1, 64)]
            with open(path, "wb") as f:
                f.write(bytes(b))
            try:
                marseille.read_day(path)
                outcomes["read"] += 1
            except MarseilleError as e:
                self.assertIn(path, str(e))
                outcomes["error"] += 1
        self.assertEqual(sum(outcomes.values()), 500)
        self.assertGreater(outcomes["error"], 250)


class Reader(Tmp):
    def test_restricted_unpickler_reads_what_numpy_wrote(self):
        path = self.path("d_raw.npy")
        small_day(path, rows=3, size=200)  # 80 kB images: stepped over, then spilled
        rows = marseille.read_day(path)
        self.assertEqual([r.image_type for r in rows], [0, 1, 2])
        self.assertEqual([r.exposure_us for r in rows], [100.0, 101.0, 102.0])
        spill = {rows[1].blob.serial: self.path("img1")}
        load_object_array(path, spill)
        want = np.load(path, allow_pickle=True)[1, 0]  # our own file: numpy's reader as the oracle
        got = np.fromfile(self.path("img1"), dtype="<u2").reshape(200, 200)
        self.assertTrue(np.array_equal(got, want))

    def test_build_cannot_patch_the_readers_classes(self):
        """BUILD with slot state on an allowed class (numpy.dtype → the reader's DtypeProxy) would set
        a class attribute for the rest of the process: refused, the class untouched."""
        from skypol import marseille_pickle
        path = self.path("patch_raw.npy")
        with open(path, "wb") as f:
            np.lib.format.write_array_header_1_0(f, {"descr": "|O", "fortran_order": False, "shape": (1, 4)})
            f.write(b"\x80\x03cnumpy\ndtype\nN}X\x07\x00\x00\x00resolveK\x01s\x86b.")
        with self.assertRaises(MarseilleError) as e:
            marseille.read_day(path)
        self.assertIn("BUILD of a type", str(e.exception))
        self.assertTrue(callable(marseille_pickle.DtypeProxy.resolve))

    def test_big_endian_images(self):
        path = self.path("be_raw.npy")
        img = (np.arange(200 * 200, dtype=np.uint16).reshape(200, 200) % 4096 << 4).astype(">u2")
        mm.write_day_file(path, [(img, 100.0, "2022-07-30T12-00-00", 0)])
        (row,) = marseille.read_day(path)
        self.assertEqual(row.dtype, ">u2")
        load_object_array(path, {row.blob.serial: self.path("be")})
        got = np.fromfile(self.path("be"), dtype=row.dtype).reshape(200, 200)
        self.assertTrue(np.array_equal(got, img))
        self.assertTrue(np.array_equal(marseille._dn(got, path, 0), img.astype(np.uint16) >> 4))

    def test_other_pickle_protocols(self):
        """np.save writes protocol 3; protocols 2 (bytes as _codecs.encode, so held in memory) and 4
        (frames) read alike."""
        path = self.path("d_raw.npy")
        small_day(path, rows=3, size=200)
        want = np.load(path, allow_pickle=True)
        for protocol in (2, 4):
            p = self.path(f"p{protocol}_raw.npy")
            with open(p, "wb") as f:
                np.lib.format.write_array_header_1_0(f, {"descr": "|O", "fortran_order": False, "shape": want.shape})
                pickle.dump(want, f, protocol=protocol)
            rows = marseille.read_day(p)
            self.assertEqual([r.stamp for r in rows], list(want[:, 2]), protocol)
            if protocol == 2:  # the bytes come as latin-1 text: read whole, not streamed
                got = rows[2].small
            else:
                spill = {rows[2].blob.serial: self.path(f"img{protocol}")}
                load_object_array(p, spill)
                got = np.fromfile(spill[rows[2].blob.serial], dtype="<u2").reshape(200, 200)
            self.assertTrue(np.array_equal(got, want[2, 0]), protocol)

    def test_writer_attributes_stay_in_their_namespace(self):
        top = self.path("cal")
        mm.write_calib(top)
        cal = marseille.read_calibration(top)
        t = skypol.parse_time("2022-07-30T10:00:00Z")
        scene = skypol.parse_scene(marseille.scene_text(cal, [t], LAYOUT))
        zero = {c: np.zeros(cal.size, np.float32) for c in ["mask"]}
        out = self.path("a.exr")
        for name in ("skypol:time", "weather"):
            with self.assertRaises(skypol.SceneError) as e:
                skypol._skypol.write_stream(scene._h, out, [t], ["mask"], lambda i: zero, "capture", [(name, "x")])
            self.assertIn(f"header attribute '{name}'", str(e.exception))
            self.assertFalse(os.listdir(self.dir) != ["cal"], os.listdir(self.dir))

    def test_stamps_are_local_summer_time(self):
        self.assertEqual(skypol.format_time(marseille.parse_stamp("2022-08-23T10-04-27")), "2022-08-23T08:04:27Z")
        with self.assertRaises(ValueError):
            marseille.parse_stamp("2022-08-23T10-04-27/")

    def test_world_from_camera_maps_the_authors_directions(self):
        """A pixel's ray through skypol's camera (P·M·P, the crop's centre) is the authors' formula's."""
        top = self.path("cal")
        mm.write_calib(top)
        cal = marseille.read_calibration(top)
        scene = skypol.parse_scene(marseille.scene_text(cal, [skypol.parse_time("2022-07-30T10:00:00Z")], LAYOUT))
        u, v = np.array([10.0, 64.0, 100.0]), np.array([70.0, 64.0, 20.0])
        d = scene.camera.pixel_to_direction(u, v)
        az, zen = marseille.authors_directions(cal, v + mm.CROP[0], u + mm.CROP[2])
        np.testing.assert_allclose(np.radians(d["azimuth_deg"]) % (2 * np.pi), az % (2 * np.pi), atol=1e-9)
        np.testing.assert_allclose(np.radians(90 - d["elevation_deg"]), zen, atol=1e-9)


class Memory(Tmp):
    def test_reading_a_100_frame_day_stays_within_a_few_frames(self):
        r = subprocess.run([sys.executable, os.path.join(HERE, "marseille_memory.py"), "--frames", "100", "--size", "400",
                            "--dir", self.dir], capture_output=True, text=True)
        self.assertEqual(r.returncode, 0, r.stderr)
        res = json.loads(r.stdout.strip().splitlines()[-1])
        frame = 400 * 400 * 2
        self.assertLess(res["read"]["peak_above_start_bytes"], 4 * frame)  # the file is 100 frames
        # the import holds one output frame (20 float channels) in Python and once more in C++
        self.assertLess(res["import"]["peak_above_start_bytes"], 8 * 20 * 4 * 400 * 400)


if __name__ == "__main__":
    unittest.main(verbosity=2)
