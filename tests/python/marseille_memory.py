#!/usr/bin/python3
"""Peak memory of importing a Marseille day file (skypol.marseille), printed as figures.

    marseille_memory.py [--frames 100] [--size 1636] [--dir DIR]

Writes a synthetic day file of `frames` rows of size×size uint16 images (image types 0–9 cycling,
so every tenth row starts an acquisition), then, in fresh processes, (1) reads its rows and copies
every image to a spill file, as the importer's two passes do, and (2) imports it whole into a day
stack; each reports its peak resident memory (VmHWM) above the process's memory before the import,
and its wall time.
A day file of the database is 571 rows of 1636×1636 (3.1 GB): the reader's peak does not grow with
the number of rows. tests/python/test_marseille.py runs it on small frames with a bound.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np


def vm(key: str) -> int:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1]) * 1024
    return 0


def write_day(path: str, frames: int, size: int) -> None:
    """The day file (the writer holds its images; the reader under test never does)."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import marseille_miniature as mm
    rng = np.random.default_rng(1)
    img = (rng.integers(1, 4095, (size, size), dtype=np.uint16) << 4).astype(np.uint16)
    rows = []
    for k in range(frames):
        minute, typ = divmod(k, 10)
        rows.append((img.copy(), 100.0 + typ, f"2022-07-30T12-{minute:02d}-{10 + 2 * typ:02d}", typ))
    mm.write_day_file(path, rows)


def child(mode: str, path: str, calib: str, out: str) -> None:
    from skypol import marseille
    from skypol.marseille_pickle import load_object_array
    import time
    base, t0 = vm("VmRSS"), time.perf_counter()
    if mode == "read":
        rows = marseille.read_day(path)
        spill = {r.blob.serial: os.path.join(out, f"{r.index}.u2") for r in rows if r.blob}
        load_object_array(path, spill)
        for f in spill.values():
            os.remove(f)
        n = len(rows)
    else:
        cal = marseille.read_calibration(calib)
        w = marseille.import_day(path, cal, out, sensor_toml=marseille.default_sensor_toml(marseille.AUTHORS_LAYOUT))
        n = sum(len(s.rows) for s in w)
    print(json.dumps({"mode": mode, "peak_above_start_bytes": vm("VmHWM") - base, "rows_or_frames": n,
                      "seconds": time.perf_counter() - t0}))


def calib_for(folder: str, size: int) -> None:
    """A calib folder whose crop is size×size (an equidistant lens filling it)."""
    os.makedirs(folder, exist_ok=True)
    np.save(os.path.join(folder, "dist_center.npy"), np.array([size / 2 + 3.5, size / 2 + 3.5]))
    np.save(os.path.join(folder, "f.npy"), np.array(size / 2 / 1.62))
    np.save(os.path.join(folder, "rot_mat.npy"), np.eye(3))
    np.save(os.path.join(folder, "lat_lon.npy"), np.array([43.287, 5.403]))
    np.save(os.path.join(folder, "params_crop.npy"), np.array([4, 4 + size, 4, 4 + size]))


def main() -> int:
    p = argparse.ArgumentParser()
    p.add_argument("--frames", type=int, default=100)
    p.add_argument("--size", type=int, default=1636)
    p.add_argument("--dir")
    p.add_argument("--child", nargs=4, metavar=("MODE", "DAY", "CALIB", "OUT"), help=argparse.SUPPRESS)
    a = p.parse_args()
    if a.child:
        child(*a.child)
        return 0
    d = a.dir or tempfile.mkdtemp(prefix="skypol-marseille-mem-")
    os.makedirs(d, exist_ok=True)
    day = os.path.join(d, "2022-07-30_raw.npy")
    write_day(day, a.frames, a.size)
    calib = os.path.join(d, "calib")
    calib_for(calib, a.size)
    frame = a.size * a.size * 2
    print(f"day file {os.path.getsize(day) / 1e6:.1f} MB: {a.frames} rows of {a.size}x{a.size} uint16 "
          f"({frame / 1e6:.2f} MB each)")
    results = {}
    for mode in ("read", "import"):
        out = os.path.join(d, "out-" + mode)
        os.makedirs(out, exist_ok=True)
        r = subprocess.run([sys.executable, os.path.abspath(__file__), "--child", mode, day, calib, out],
                           capture_output=True, text=True)
        if r.returncode:
            print(r.stderr, file=sys.stderr)
            return 1
        res = json.loads(r.stdout.strip().splitlines()[-1])
        results[mode] = res
        print(f"{mode:6s}: peak {res['peak_above_start_bytes'] / 1e6:7.1f} MB above the start "
              f"= {res['peak_above_start_bytes'] / frame:5.1f} raw frames ({res['rows_or_frames']} rows/frames) "
              f"in {res['seconds']:.1f} s")
    print(json.dumps(results))
    return 0


if __name__ == "__main__":
    sys.exit(main())
