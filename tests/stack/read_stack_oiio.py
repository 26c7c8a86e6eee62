#!/usr/bin/python3
"""A skypol stack and its previews, read the way users read them: Debian's OpenImageIO Python
bindings with numpy, and OpenImageIO's own tools, with no special handling.

Renders scenes/urban-canyon.toml with 8x8 binning (306x256 px) into a scratch folder, then checks
every part: channel names, finite values in their documented ranges, the truth in the header,
the occluders in the mask; and that every preview PNG opens as 8-bit RGB.

usage: read_stack_oiio.py SKYPOL_BINARY SCENE.toml SCRATCH_DIR
"""
import math
import os
import shutil
import subprocess
import sys

import numpy as np
import OpenImageIO as oiio

skypol, scene_path, scratch = sys.argv[1:4]
shutil.rmtree(scratch, ignore_errors=True)
os.makedirs(scratch)

# The scene, smaller, written into the scratch folder (its previews beside it).
stack = os.path.join(scratch, "urban.exr")
subprocess.run([skypol, "render", scene_path, "-q", "--set", "camera.binning=8", "-o", stack], check=True)

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


inp = oiio.ImageInput.open(stack)
assert inp, oiio.geterror()
parts = inp.spec().get_int_attribute("oiio:subimages")
check(parts == 4, f"4 parts, found {parts}")
for part in range(parts):
    assert inp.seek_subimage(part, 0)
    spec = inp.spec()
    where = f"part {part}"
    check(spec.width == 306 and spec.height == 256, f"{where}: size {spec.width}x{spec.height}")
    names = set(spec.channelnames)
    check(names == {"S0.Y", "S1.Y", "S2.Y", "DoLP.Y", "AoLP.Y", "mask"}, f"{where}: channels {sorted(names)}")
    pixels = inp.read_image(part, 0, 0, spec.nchannels, "float")
    check(pixels is not None and pixels.shape == (256, 306, spec.nchannels), f"{where}: pixels {getattr(pixels, 'shape', None)}")
    channel = {name: pixels[:, :, i] for i, name in enumerate(spec.channelnames)}
    for name, values in channel.items():
        check(np.isfinite(values).all(), f"{where}: {name} holds NaN or Inf")
    check(((channel["DoLP.Y"] >= 0) & (channel["DoLP.Y"] <= 1)).all(), f"{where}: DoLP outside [0, 1]")
    check((np.abs(channel["AoLP.Y"]) <= math.pi / 2 + 1e-6).all(), f"{where}: AoLP outside [-pi/2, pi/2]")
    mask = channel["mask"]
    check(set(np.unique(mask)) <= {0.0, 1.0}, f"{where}: mask not 0/1 at 1 sample per pixel")
    # Occluded and outside pixels hold no light.
    check((channel["S0.Y"][mask == 0] == 0).all(), f"{where}: light where mask = 0")
    # The street: the image circle (about 0.4 of the frame) is mostly buildings; the sky a strip.
    sky = float(mask.mean())
    check(0.01 < sky < 0.2, f"{where}: sky fraction {sky:.3f}")
    # The truth in the header.
    time = spec.get_string_attribute("skypol:time")
    check(spec.get_string_attribute("oiio:subimagename") == time, f"{where}: part name is not the time {time}")
    el = spec.get_float_attribute("skypol:sunElevationDeg", -999)
    check(-90 <= el <= 90, f"{where}: sun elevation {el}")
    check("[occluders]" in spec.get_string_attribute("skypol:scene"), f"{where}: the scene text lacks its occluders")

previews = sorted(os.listdir(os.path.join(scratch, "urban-preview")))
check(len(previews) == parts, f"{parts} previews, found {previews}")
for name in previews:
    png = oiio.ImageInput.open(os.path.join(scratch, "urban-preview", name))
    check(png is not None and png.spec().nchannels == 3 and png.spec().format == oiio.UINT8, f"preview {name}")

# OpenImageIO's own tools, when Debian's openimageio-tools is installed (scripts/packages.txt).
for tool, args in (("oiiotool", ["--info", "-v"]), ("iinfo", ["-v"])):
    exe = shutil.which(tool)
    if not exe:
        print(f"{tool}: not installed, skipped")
        continue
    out = subprocess.run([exe, *args, stack], capture_output=True, text=True)
    check(out.returncode == 0, f"{tool} failed: {out.stderr}")
    check(f"{parts} subimages" in out.stdout, f"{tool} does not list {parts} subimages")
    check("skypol:sunAzimuthDeg" in out.stdout, f"{tool} does not show the truth attributes")

if failures:
    print("\n".join(failures))
    sys.exit(1)
print(f"OpenImageIO (Python) read {parts} parts and {len(previews)} previews of {stack}")
