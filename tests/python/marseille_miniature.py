"""A miniature of Poughon et al.'s Marseille skylight database in its exact layout, from frames
skypol renders through the colour DoFP sensor (tests/python/test_marseille.py, scripts/real-skies'
test).

It writes what the authors' code writes (docs/import.md): `PolarizedDatabaseM/YYYY-MM-DD_raw.npy`,
np.save of an (N, 4) object array [uint16 image, exposure µs (numpy float64), 'YYYY-MM-DDTHH-MM-SS'
local summer time, image type], its `_raw_annotations.npy` (N, 2) object array [timestamp,
label], and `calib/` (dist_center, f, rot_mat, rotation, lat_lon, params_crop as numeric .npy,
orientation_pixels_ENU and alpha/theta_crop by the authors' formulas). The full sensor is
rendered, its raw mosaic cropped at multiples of 4 and shifted into the top 12 bits of 16.
"""

from __future__ import annotations

import datetime as dt
import math
import os
from dataclasses import dataclass, field

import numpy as np

import skypol

# The authors' 1M rotation (camera → world, x North, y East, z Up), as their rotation.npy's Euler
# angles give it (docs/import.md), re-orthonormalised.
_M = np.array([[-0.715265, 0.697757, -0.039137], [-0.697827, -0.716128, -0.014083], [-0.037854, 0.017238, 0.999135]])
_U, _, _VT = np.linalg.svd(_M)
ROT_MAT = _U @ _VT
LAT, LON = 43.286990365824785, 5.403361407820939
P = np.array([[0.0, 1, 0], [1, 0, 0], [0, 0, 1]])

FULL = (152, 160)            # the miniature's full sensor, rows × columns
CROP = (8, 136, 16, 144)     # rows 8–135, columns 16–143: 128 × 128, at multiples of 4
CENTER = (79.7, 72.2)        # dist_center: column, row on the full sensor
F_PX = 35.9                  # 92.5° off the axis at 58 px: the image circle stays 5 px inside the crop

# The authors' fixed exposures (µs) for image types 5 and 8.
FIXED = {5: 33.456, 8: 1000.032}


def quaternion_of(r):
    w = math.sqrt(max(0.0, 1 + np.trace(r))) / 2
    return [w, (r[2, 1] - r[1, 2]) / (4 * w), (r[0, 2] - r[2, 0]) / (4 * w), (r[1, 0] - r[0, 1]) / (4 * w)]


def sensor_toml(layout, seed=0):
    """The [sensor] of the miniature's camera: the database's camera, clipping at the ADC's top as
    the importer's default does; 12 bits."""
    return (f'preset = "lucid_phx050s_qc"\nmosaic_deg = [{", ".join(f"{a:g}" for a in layout)}]\n'
            f"adc_bits = 12\nblack_level_dn = 0\ndark_current_e_s = 0\nfull_well_e = 1e9\n"
            f"electrons_per_radiance_s = 2e6\nseed = {seed}\n")


def full_scene_text(times_iso, layout, exposure_us, *, sky='model = "rayleigh"', clouds="", seed=0):
    q = quaternion_of(P @ ROT_MAT @ P)
    inst = ", ".join(f'"{t}"' for t in times_iso)
    return (f"[site]\nlatitude_deg = {LAT!r}\nlongitude_deg = {LON!r}\nheight_m = 390.0\n"
            f"[time]\ninstants = [{inst}]\n"
            f"[camera]\nmodel = \"equidistant\"\nwidth = {FULL[1]}\nheight = {FULL[0]}\nfx = {F_PX!r}\n"
            f"cx = {CENTER[0]!r}\ncy = {CENTER[1]!r}\nfov_deg = 185.0\nquaternion = [{', '.join(repr(v) for v in q)}]\n"
            f"[render]\nbands = [\"R\", \"G\", \"B\"]\n"
            f"[sky]\n{sky}\n{clouds}"
            f"[sensor]\n{sensor_toml(layout, seed)}exposure_us = {exposure_us!r}\n")


@dataclass
class Miniature:
    root: str                 # the database folder (holds calib/ and the day files)
    day_files: list
    times: list               # UTC Unix seconds of the frames the importer should choose
    reference: dict = field(default_factory=dict)   # day → list of {channel: full-sensor array}
    scene_text: str = ""      # the full-sensor scene of the chosen frames


def local_stamp(unix):
    return dt.datetime.fromtimestamp(unix, dt.timezone(dt.timedelta(hours=2))).strftime("%Y-%m-%dT%H-%M-%S")


def write_calib(folder):
    os.makedirs(folder, exist_ok=True)
    np.save(os.path.join(folder, "dist_center.npy"), np.array(CENTER))
    np.save(os.path.join(folder, "f.npy"), np.array(F_PX))
    np.save(os.path.join(folder, "rot_mat.npy"), ROT_MAT)
    np.save(os.path.join(folder, "lat_lon.npy"), np.array([LAT, LON]))
    np.save(os.path.join(folder, "params_crop.npy"), np.array(CROP, dtype=np.int64))
    # The authors' per-pixel directions (calcul_Psi_Theta_Mes, sph2cart2, cart2sph2).
    i, j = np.mgrid[0:FULL[0], 0:FULL[1]].astype(np.float64)
    th = np.hypot(i - CENTER[1], j - CENTER[0]) / F_PX
    psi = np.arctan2(j - CENTER[0], i - CENTER[1])
    v = np.stack([np.sin(th) * np.cos(psi), np.sin(th) * np.sin(psi), np.cos(th)], -1) @ ROT_MAT.T
    enu = np.stack([np.arctan2(v[..., 1], v[..., 0]), np.pi / 2 - np.arctan2(v[..., 2], np.hypot(v[..., 0], v[..., 1]))], -1)
    np.save(os.path.join(folder, "orientation_pixels_ENU.npy"), enu)
    r0, r1, c0, c1 = CROP
    np.save(os.path.join(folder, "alpha_crop.npy"), enu[r0:r1, c0:c1, 0])
    np.save(os.path.join(folder, "theta_crop.npy"), enu[r0:r1, c0:c1, 1])


def write_day_file(path, rows):
    """rows: (uint16 image, exposure, stamp, type) — np.save of an (N, 4) object array, as A-RED does."""
    a = np.empty((len(rows), 4), dtype=object)
    for k, (img, expo, stamp, typ) in enumerate(rows):
        a[k, 0], a[k, 1], a[k, 2], a[k, 3] = img, np.float64(expo), stamp, int(typ)
    np.save(path, a)


def write_annotations(path, stamps, labels):
    a = np.empty((len(stamps), 2), dtype=object)
    for k, (s, lab) in enumerate(zip(stamps, labels)):
        a[k, 0], a[k, 1] = s, lab
    np.save(path, a)


def crop_shift(raw):
    r0, r1, c0, c1 = CROP
    return (np.asarray(raw)[r0:r1, c0:c1].astype(np.uint16) << 4).astype(np.uint16)


def make(root, *, day="2022-07-30", hours_local=(8, 10, 12, 14, 16, 18), layout=(0, 45, 135, 90),
         labels="cfcsbo", auto_exposure_us=(800.0, 500.0, 400.0, 400.0, 500.0, 900.0), clouds="",
         fixed_types=True):
    """Writes the miniature's calib folder and one day file with its annotations; returns what the
    importer should give back. Each acquisition holds image types 0 and 3 (auto-exposed; 3 is the
    one the importer chooses) and 5 and 8 (fixed exposures), 2 s apart."""
    db = os.path.join(root, "PolarizedDatabaseM")
    write_calib(os.path.join(db, "calib"))
    y, m, d = (int(v) for v in day.split("-"))
    tz = dt.timezone(dt.timedelta(hours=2))
    starts = [dt.datetime(y, m, d, h, 0, 5, tzinfo=tz).timestamp() for h in hours_local]
    chosen = [t + 2 for t in starts]
    channels = ["S0", "S1", "S2", "DoLP", "AoLP", "mask", "raw"]
    reference, rows = [], []
    iso = [skypol.format_time(t) for t in chosen]
    for k, t0 in enumerate(starts):
        expo = auto_exposure_us[k % len(auto_exposure_us)]
        kinds = [(0, t0, 2 * expo), (3, t0 + 2, expo)]
        if fixed_types:
            kinds += [(5, t0 + 4, FIXED[5]), (8, t0 + 6, FIXED[8])]
        for typ, t, e in kinds:
            # Frame k of the chosen frames' scene, so the type-3 frame is the reference's frame k.
            times = iso if typ == 3 else [skypol.format_time(t)]
            scene = skypol.parse_scene(full_scene_text(times, layout, e, clouds=clouds))
            f = skypol.render_frame(scene, k if typ == 3 else 0, channels=channels if typ == 3 else ["raw"])
            if typ == 3:
                reference.append({c: np.array(a) for c, a in f.channels.items()})
            rows.append((crop_shift(f["raw"]), e, local_stamp(t), typ))
    path = os.path.join(db, f"{day}_raw.npy")
    write_day_file(path, rows)
    per_row = [labels[k // (4 if fixed_types else 2) % len(labels)] for k in range(len(rows))]
    write_annotations(os.path.join(db, f"{day}_raw_annotations.npy"), [r[2] for r in rows], per_row)
    mini = Miniature(db, [path], chosen)
    mini.reference[day] = reference
    mini.scene_text = full_scene_text(iso, layout, auto_exposure_us[0])
    return mini
