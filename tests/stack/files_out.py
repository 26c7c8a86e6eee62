#!/usr/bin/python3
"""skypol's files read by other people's tools: `skypol export` writes single-part EXR and TIFF
that OpenImageIO opens and NPY that numpy.load opens, each holding exactly the values of the
multi-part stack (read independently, by OpenImageIO); `skypol info --json` holds every header
attribute at full precision (compared with OpenImageIO's reading of the same headers);
`skypol lens --json` round-trips a pixel through its direction to 1e-9 px; `skypol --version`.

usage: files_out.py SKYPOL_BINARY SCRATCH_DIR
"""
import glob
import json
import math
import os
import shutil
import subprocess
import sys

import numpy as np
import OpenImageIO as oiio

skypol, scratch = sys.argv[1:3]
shutil.rmtree(scratch, ignore_errors=True)
os.makedirs(scratch)
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


def run(*args):
    return subprocess.run([skypol, *args], check=True, capture_output=True, text=True).stdout


scene = os.path.join(scratch, "small.toml")
with open(scene, "w") as f:
    f.write("""[site]
latitude_deg = 43.3
longitude_deg = 5.4
[time]
instants = ["2022-06-21T06:00:00Z", "2022-06-21T07:30:00.5Z", "2022-06-21T09:00:00Z"]
[camera]
model = "equidistant"
width = 96
height = 64
fx = 20.123456789012345
cx = 47.25
cy = 31.5
fov_deg = 185
heading_deg = 37.1
tilt_deg = 4.5
""")
stack = os.path.join(scratch, "small.exr")
run("render", "-q", scene, "-o", stack)

# The stack as OpenImageIO reads it: the reference for everything below.
inp = oiio.ImageInput.open(stack)
assert inp, oiio.geterror()
reference, headers = [], []
for part in range(3):
    assert inp.seek_subimage(part, 0)
    spec = inp.spec()
    px = inp.read_image(part, 0, 0, spec.nchannels, "float")
    reference.append({n: px[:, :, i] for i, n in enumerate(spec.channelnames)})
    headers.append({a.name: a.value for a in spec.extra_attribs})
inp.close()
channels = ["S0.Y", "S1.Y", "S2.Y", "DoLP.Y", "AoLP.Y"]

# info --json: every skypol: attribute, the same values (doubles exactly: %.17g round-trips).
info = json.loads(run("info", "--json", stack))
check(info["frames"] == 3 and info["width"] == 96 and info["height"] == 64, f"info --json size {info['frames']} {info['width']}")
check(info["truth_known"] is True, "info --json: truth_known")
for part in range(3):
    js = info["parts"][part]
    for name, value in headers[part].items():
        if not name.startswith("skypol:"):
            continue
        got = js.get(name)
        if isinstance(value, float):
            check(got == value, f"part {part} {name}: json {got} vs OpenImageIO {value}")
        elif isinstance(value, str):
            check(got == value, f"part {part} {name}: json {got!r} vs OpenImageIO {value!r}")
        elif isinstance(value, tuple):
            flat = np.array(got, dtype=float).ravel()
            check(np.array_equal(flat, np.array(value, dtype=float).ravel()), f"part {part} {name}: {got} vs {value}")
    check(js["skypol:headingDeg"] == 37.1 and js["skypol:tiltDeg"] == 4.5, f"part {part}: heading/tilt {js['skypol:headingDeg']}")
check(info["parts"][1]["skypol:unixTime"] == 1655796600.5, f"unixTime of part 1: {info['parts'][1]['skypol:unixTime']}")

# export: npy (rows, cols, channels), single-part EXR, TIFF one channel per file (the form every
# reader of docs/exr-format.md opens), PNG of DoLP; each frame's values are the stack's exactly
# (PNG: round(DoLP * 65535)).
import cv2  # python3-opencv (scripts/packages.txt): the reader the TIFF default is chosen for
from PIL import Image  # python3-pil
for fmt in ["npy", "exr", "tiff"]:
    out = os.path.join(scratch, fmt)
    subprocess.run([skypol, "export", "-q", stack, "-f", fmt, "-o", out], check=True)
    files = sorted(glob.glob(os.path.join(out, "small_*." + fmt)))
    check(len(files) == (15 if fmt == "tiff" else 3), f"{fmt}: {len(files)} files")
    for part in range(3):
        if fmt == "tiff":
            # small_NNN_TIME.<channel>.tiff, one float32 channel each, in OpenImageIO, OpenCV and Pillow.
            first = next(f for f in files if f"_{part:03d}_" in f and f.endswith(f".{channels[0]}.tiff"))
            stem = first[: -len(f".{channels[0]}.tiff")]
            for name in channels:
                path = f"{stem}.{name}.tiff"
                check(path in files, f"{path}: not written")
                i = oiio.ImageInput.open(path)
                assert i, oiio.geterror()
                spec = i.spec()
                a = i.read_image(0, 0, 0, 1, "float")[:, :, 0]
                i.close()
                check(spec.nchannels == 1 and spec.format == oiio.FLOAT, f"{path}: {spec.nchannels} {spec.format}")
                check(np.array_equal(a, reference[part][name]), f"{path}: OpenImageIO: {name} differs from the stack")
                c = cv2.imread(path, cv2.IMREAD_UNCHANGED)
                check(c is not None and c.dtype == np.float32 and c.shape == (64, 96), f"{path}: OpenCV read {None if c is None else (c.dtype, c.shape)}")
                if c is not None:
                    check(np.array_equal(c, reference[part][name]), f"{path}: OpenCV: {name} differs from the stack")
                with Image.open(path) as im:
                    check(im.mode == "F" and np.array_equal(np.asarray(im), reference[part][name]), f"{path}: Pillow: {im.mode}")
            continue
        path = files[part]
        if fmt == "npy":
            a = np.load(path)
            check(a.dtype == np.float32 and a.shape == (64, 96, 5), f"{path}: {a.dtype} {a.shape}")
        else:
            i = oiio.ImageInput.open(path)
            assert i, oiio.geterror()
            check(i.spec().get_int_attribute("oiio:subimages", 1) == 1, f"{path}: not single-part")
            names = list(i.spec().channelnames)
            a = i.read_image(0, 0, 0, 5, "float")
            i.close()
            # OpenEXR keeps the names (and sorts them): take the channels by name.
            check(sorted(names) == sorted(channels), f"{path}: channels {names}")
            a = np.stack([a[:, :, names.index(n)] for n in channels], axis=2)
        for c, name in enumerate(channels):
            check(np.array_equal(a[:, :, c], reference[part][name]), f"{path}: {name} differs from the stack")
    # The times in the names and in times.csv (one line per file).
    with open(os.path.join(out, "times.csv")) as f:
        lines = f.read().split("\n")
    row = 6 if fmt == "tiff" else 2  # the second frame's first file
    check(lines[0] == "file,time" and lines[row].endswith(",2022-06-21T07:30:00.500Z"), f"{fmt}: times.csv {lines[:7]}")
    check("20220621T073000.500Z" in files[row - 1], f"{fmt}: name {files[row - 1]}")

out = os.path.join(scratch, "png")
subprocess.run([skypol, "export", "-q", stack, "-f", "png", "-c", "DoLP", "-o", out], check=True)
files = sorted(glob.glob(os.path.join(out, "*.png")))
check(len(files) == 3, f"png: {len(files)} files")
i = oiio.ImageInput.open(files[0])
check(i.spec().format == oiio.UINT16 and i.spec().nchannels == 1, f"png: {i.spec().format} {i.spec().nchannels}")
a = i.read_image(0, 0, 0, 1, oiio.UINT16)[:, :, 0]
i.close()
check(np.array_equal(a, np.round(reference[0]["DoLP.Y"].astype(np.float64) * 65535).astype(np.uint16)), "png: DoLP * 65535")

# lens --json: the scene's numbers at full precision; a pixel to its direction and back.
lens = json.loads(run("lens", "--json", scene, "-p", "30.125,20.5"))
check(lens["fx"] == 20.123456789012345 and lens["cx"] == 47.25, f"lens --json fx {lens['fx']!r}")
ans = lens["answers"][0]
check(ans["from"] == "pixel" and ans["inside"], f"lens --json answer {ans}")
back = json.loads(run("lens", "--json", scene, "-d", f"{ans['azimuth_deg']!r},{ans['elevation_deg']!r}"))["answers"][0]
check(math.hypot(back["pixel"][0] - 30.125, back["pixel"][1] - 20.5) < 1e-9, f"lens --json round trip {back['pixel']}")

version = run("--version").strip()
check(version.startswith("skypol 0.1.0"), f"--version: {version!r}")
# Every part's header carries the same text (stack/version.h: one source for both).
for part in range(3):
    check(headers[part]["skypol:version"] == version, f"part {part} skypol:version {headers[part]['skypol:version']!r} vs --version {version!r}")

for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
