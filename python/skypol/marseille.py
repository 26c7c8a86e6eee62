"""Poughon et al.'s Marseille skylight database (a PHX050S-QC colour DoFP camera behind a 1.8 mm
fisheye at La Timone, 2022) into skypol stacks: docs/import.md walks it through, and
../shared/datasets/marseille-skylight-database.md (in the project's notes) describes the format.

    from skypol import marseille
    cal = marseille.read_calibration("PolarizedDatabaseM/calib")
    written = marseille.import_day("PolarizedDatabaseM/2022-07-06_raw.npy", cal, "out/")

Each acquisition (about 15 images 2–3 s apart, every 10 minutes) becomes one frame: its last
auto-exposed image (image type < 5) by default, or the image of a chosen type. The frame goes
through skypol's own DoFP demosaic (camera/dofp_sensor.h, as `skypol import` runs it), the camera is
the calibration's equidistant lens with the crop applied, and the truth is the calibration's
rotation and site, marked in every part as a sun-fitted calibration. Day files are read with a
restricted, streaming unpickler (skypol.marseille_pickle), never with np.load(allow_pickle=True).
"""

from __future__ import annotations

import csv
import datetime as _dt
import math
import os
import re
import shutil
import tempfile
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np

from . import _skypol, format_time, parse_scene, sun_position
from .marseille_pickle import ArrayProxy, Blob, MarseilleError, load_object_array

__all__ = ["MarseilleError", "Calibration", "Row", "read_calibration", "read_day", "read_annotations",
           "acquisitions", "plan_day", "import_day", "write_manifest", "diagnose_day", "verdict", "diagnose_layout", "parse_layout", "layout_text", "scene_text",
           "AUTHORS_LAYOUT", "WEATHER", "UTC_OFFSET_H", "SITE_HEIGHT_M"]

# The authors' code labels the 2×2 polarizer block 0° 45° over 135° 90° (docs/import.md).
AUTHORS_LAYOUT = (0.0, 45.0, 135.0, 90.0)
# Local French summer time (ephemeride.py: "Difference between local and UTC hour - 2h on summer").
UTC_OFFSET_H = 2
# La Timone's height in the authors' ephemeris (ephemeride.py's EarthLocation).
SITE_HEIGHT_M = 390.0
# The PHX050S-QC's full sensor, rows × columns, when the calib folder does not say.
SENSOR_SHAPE = (2048, 2448)
WEATHER = {"n": "dark_sky", "c": "clear_sky", "m": "mist", "f": "few_clouds", "s": "scattered_clouds",
           "b": "broken_clouds", "o": "overcast_clouds", "?": "unlabelled"}
# The stored values are 12 bits shifted left by 4 inside uint16.
RIGHT_SHIFT = 4
# Image types below this are auto-exposed (the README); the rest are fixed exposures.
FIRST_FIXED_TYPE = 5
# A new acquisition starts when the image type does not increase or this many seconds pass.
ACQUISITION_GAP_S = 120.0
# The lens' real field (Fujinon FE185C057HA-1): the crop's corners lie beyond it.
FOV_DEG = 185.0

_STAMP = re.compile(r"^(\d{4})-(\d{2})-(\d{2})T(\d{2})-(\d{2})-(\d{2})$")


def parse_stamp(stamp: str) -> float:
    """'YYYY-MM-DDTHH-MM-SS' in local summer time (UTC+2) → Unix seconds. ValueError if malformed."""
    m = _STAMP.match(stamp) if isinstance(stamp, str) else None
    if not m:
        raise ValueError(f"timestamp {stamp!r:.40} is not 'YYYY-MM-DDTHH-MM-SS'")
    y, mo, d, h, mi, s = (int(g) for g in m.groups())
    local = _dt.datetime(y, mo, d, h, mi, s, tzinfo=_dt.timezone(_dt.timedelta(hours=UTC_OFFSET_H)))
    return local.timestamp()


def parse_layout(text: str | Sequence[float]) -> tuple[float, float, float, float]:
    """'0/45/135/90' (pixels (0,0) (0,1) (1,0) (1,1) of each 2×2 block) → four angles."""
    parts = text.split("/") if isinstance(text, str) else list(text)
    try:
        angles = tuple(float(p) for p in parts)
    except ValueError:
        angles = ()
    if len(angles) != 4 or sorted(a % 180 for a in angles) != [0, 45, 90, 135]:
        raise ValueError(f"layout {text!r}: give the four polarizer angles 0, 45, 90, 135 of pixels "
                         "(0,0)/(0,1)/(1,0)/(1,1), e.g. 0/45/135/90")
    return angles  # type: ignore[return-value]


def layout_text(layout: Sequence[float]) -> str:
    return "/".join(f"{a:g}" for a in layout)


# ----------------------------------------------------------------------------------- calibration

@dataclass
class Calibration:
    """The calib folder: an equidistant fisheye (f, centre) on the full sensor, its orientation and
    site, and the crop the day files' images were cut with."""
    folder: str
    center_col: float           # dist_center[0], full-sensor pixels (x0 = column)
    center_row: float           # dist_center[1] (y0 = row)
    f_px: float
    rot_mat: np.ndarray         # camera → world in the authors' frames (x North, y East, z Up)
    latitude_deg: float
    longitude_deg: float
    crop: tuple[int, int, int, int]  # row0, row1, col0, col1 (ends exclusive)
    sensor_shape: tuple[int, int] = SENSOR_SHAPE
    notes: list[str] = field(default_factory=list)

    @property
    def size(self) -> tuple[int, int]:
        """(height, width) of the stored images."""
        return self.crop[1] - self.crop[0], self.crop[3] - self.crop[2]

    @property
    def cx(self) -> float:
        return self.center_col - self.crop[2]

    @property
    def cy(self) -> float:
        return self.center_row - self.crop[0]

    def world_from_camera(self) -> np.ndarray:
        """skypol's rotation ENU ← camera (x image right, y image down, z the axis). The authors'
        camera frame is (row, column, axis) and their world (North, East, Up): both are skypol's
        with the first two axes swapped, so the rotation is P·M·P with P that swap."""
        p = np.array([[0.0, 1, 0], [1, 0, 0], [0, 0, 1]])
        return p @ self.rot_mat @ p

    def quaternion(self) -> tuple[float, float, float, float]:
        return _quaternion(self.world_from_camera())


def _quaternion(r: np.ndarray) -> tuple[float, float, float, float]:
    """Hamilton (w, x, y, z) of a rotation matrix (Shepperd's method: the largest pivot)."""
    t = np.trace(r)
    if t > 0:
        s = 2 * math.sqrt(1 + t)
        q = (0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s)
    else:
        i = int(np.argmax(np.diag(r)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2 * math.sqrt(1 + r[i, i] - r[j, j] - r[k, k])
        v = [0.0, 0.0, 0.0]
        v[i] = 0.25 * s
        v[j] = (r[j, i] + r[i, j]) / s
        v[k] = (r[k, i] + r[i, k]) / s
        q = ((r[k, j] - r[j, k]) / s, *v)
    return tuple(float(x) for x in q)  # type: ignore[return-value]


def _calib_array(folder: str, name: str, shape: tuple | None, required: bool = True) -> np.ndarray | None:
    path = os.path.join(folder, name)
    if not os.path.exists(path):
        if required:
            raise MarseilleError(path, "missing: a calib folder holds dist_center.npy, f.npy, rot_mat.npy, "
                                       "lat_lon.npy and params_crop.npy")
        return None
    try:
        a = np.load(path, allow_pickle=False)  # plain numeric arrays: never a pickle
    except Exception as e:
        raise MarseilleError(path, f"not a numeric .npy array ({e})") from None
    if shape is not None and (a.shape != shape and not (shape == () and a.shape == (1,))):
        raise MarseilleError(path, f"has shape {a.shape}, expected {shape}")
    if a.dtype.kind not in "iuf" or not np.all(np.isfinite(a)):
        raise MarseilleError(path, f"must hold finite numbers, holds {a.dtype}")
    return a


def read_calibration(folder: str) -> Calibration:
    """Reads a calib folder (np.load without pickles). Errors name the file."""
    folder = str(folder)
    center = _calib_array(folder, "dist_center.npy", (2,))
    f = float(_calib_array(folder, "f.npy", ()).reshape(()))
    rot = _calib_array(folder, "rot_mat.npy", (3, 3)).astype(np.float64)
    latlon = _calib_array(folder, "lat_lon.npy", (2,))
    crop = _calib_array(folder, "params_crop.npy", (4,))
    path = os.path.join(folder, "rot_mat.npy")
    if not np.allclose(rot @ rot.T, np.eye(3), atol=1e-6) or np.linalg.det(rot) < 0:
        raise MarseilleError(path, "is not a rotation (orthonormal, determinant +1)")
    if not f > 0:
        raise MarseilleError(os.path.join(folder, "f.npy"), f"focal length {f} px must be > 0")
    if not (-90 <= latlon[0] <= 90 and -180 <= latlon[1] <= 360):
        raise MarseilleError(os.path.join(folder, "lat_lon.npy"), f"{latlon.tolist()} is not [latitude, longitude] in degrees")
    path = os.path.join(folder, "params_crop.npy")
    if np.any(crop != np.round(crop)):
        raise MarseilleError(path, f"{crop.tolist()} are not whole pixels")
    r0, r1, c0, c1 = (int(v) for v in crop)
    sensor = SENSOR_SHAPE
    enu = os.path.join(folder, "orientation_pixels_ENU.npy")
    if os.path.exists(enu):
        try:
            sensor = tuple(np.load(enu, mmap_mode="r", allow_pickle=False).shape[:2])
        except Exception as e:
            raise MarseilleError(enu, f"not a numeric .npy array ({e})") from None
    if not (0 <= r0 < r1 <= sensor[0] and 0 <= c0 < c1 <= sensor[1]):
        raise MarseilleError(path, f"crop rows {r0}–{r1}, columns {c0}–{c1} does not fit the {sensor[0]}×{sensor[1]} sensor")
    if r0 % 4 or c0 % 4:
        raise MarseilleError(path, f"crop starts at row {r0}, column {c0}: not multiples of 4, so the colour-polarization "
                                   "super-pixels would not start at the image's corner")
    cal = Calibration(folder, float(center[0]), float(center[1]), f, rot, float(latlon[0]), float(latlon[1]),
                      (r0, r1, c0, c1), sensor)
    cal.notes += _check_directions(cal)
    return cal


def authors_directions(cal: Calibration, rows: np.ndarray, cols: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Azimuth and zenith angle (radians) of full-sensor pixels by the authors' formulas
    (calcul_Psi_Theta_Mes, sph2cart2, cart2sph2): what orientation_pixels_ENU.npy holds."""
    di, dj = rows - cal.center_row, cols - cal.center_col
    th, psi = np.hypot(di, dj) / cal.f_px, np.arctan2(dj, di)
    v = np.stack([np.sin(th) * np.cos(psi), np.sin(th) * np.sin(psi), np.cos(th)], axis=-1) @ cal.rot_mat.T
    return np.arctan2(v[..., 1], v[..., 0]), np.pi / 2 - np.arctan2(v[..., 2], np.hypot(v[..., 0], v[..., 1]))


def _check_directions(cal: Calibration) -> list[str]:
    """theta_crop.npy / alpha_crop.npy, when present, against the equidistant model: a note with
    the largest difference (the model is what the stack's camera uses)."""
    notes = []
    h, w = cal.size
    for name, k in (("alpha_crop.npy", 0), ("theta_crop.npy", 1)):
        a = _calib_array(cal.folder, name, (h, w), required=False)
        if a is None:
            continue
        rr, cc = np.mgrid[0:h:max(1, h // 64), 0:w:max(1, w // 64)]
        model = authors_directions(cal, rr + cal.crop[0], cc + cal.crop[2])[k]
        d = np.abs(np.angle(np.exp(1j * (a[rr, cc] - model)))) if k == 0 else np.abs(a[rr, cc] - model)
        # azimuth is undefined at the zenith: compare it only where the zenith angle is > 1°
        if k == 0:
            d = d[authors_directions(cal, rr + cal.crop[0], cc + cal.crop[2])[1] > math.radians(1)]
        notes.append(f"{name}: the equidistant model differs by at most {math.degrees(float(d.max())):.2g}°")
    return notes


# ------------------------------------------------------------------------------------- day files

@dataclass(frozen=True)
class Row:
    index: int
    stamp: str              # local summer time, as stored
    unix_seconds: float     # UTC
    image_type: int
    exposure_us: float
    shape: tuple[int, int]
    blob: Blob | None       # where the image's bytes are (None for a tiny in-pickle image)
    small: np.ndarray | None = None
    dtype: str = "<u2"      # the image's uint16 with its byte order


def read_day(path: str) -> list[Row]:
    """The rows of a day file without their pixels (pass 1: images are stepped over). Errors name
    the file and the row: a row that is not (uint16 2-D image, exposure, timestamp, type), images of
    different sizes, timestamps out of order."""
    top, _ = load_object_array(path)
    if len(top.shape) != 2 or top.shape[1] != 4:
        raise MarseilleError(path, f"holds an object array {top.shape}, expected (N, 4): image, exposure, timestamp, type")
    rows: list[Row] = []
    items = top.data
    for i in range(top.shape[0]):
        img, expo, stamp, typ = items[4 * i: 4 * i + 4]
        if not (isinstance(img, ArrayProxy) and img.dtype is not None and img.dtype.kind == "u" and img.dtype.itemsize == 2
                and len(img.shape) == 2):
            raise MarseilleError(path, "column 0 is not a 2-D uint16 image", row=i)
        if isinstance(expo, (bool, np.bool_)) or not isinstance(expo, (int, float, np.integer, np.floating)) \
                or not (math.isfinite(float(expo)) and float(expo) > 0):
            raise MarseilleError(path, f"column 1 (exposure, µs) is {expo!r:.40}, expected a positive number", row=i)
        if isinstance(typ, (bool, np.bool_)) or not isinstance(typ, (int, np.integer)) or not 0 <= int(typ) < 1000:
            raise MarseilleError(path, f"column 3 (image type) is {typ!r:.40}, expected a whole number ≥ 0", row=i)
        try:
            t = parse_stamp(stamp)
        except ValueError as e:
            raise MarseilleError(path, f"column 2: {e}", row=i) from None
        if rows and img.shape != rows[0].shape:
            raise MarseilleError(path, f"image is {img.shape[0]}×{img.shape[1]}, row 0's is {rows[0].shape[0]}×{rows[0].shape[1]}", row=i)
        if rows and t < rows[-1].unix_seconds:
            raise MarseilleError(path, f"timestamp {stamp} is before row {i - 1}'s {rows[-1].stamp}: rows must be in time order", row=i)
        blob = img.data if isinstance(img.data, Blob) else None
        small = None if blob else img.small_array().astype(np.uint16)
        rows.append(Row(i, stamp, t, int(typ), float(expo), img.shape, blob, small, img.dtype.str))
    if not rows:
        raise MarseilleError(path, "holds no rows")
    return rows


def read_annotations(path: str, rows: Sequence[Row]) -> list[str]:
    """One label letter per row ('?' for a row never labelled: the notebook's 0.0). Rows must match
    the day file's timestamps one for one."""
    top, _ = load_object_array(path)
    if len(top.shape) != 2 or top.shape[1] != 2 or top.shape[0] != len(rows):
        raise MarseilleError(path, f"holds {top.shape}, expected ({len(rows)}, 2): one (timestamp, label) per day-file row")
    labels = []
    for i, r in enumerate(rows):
        stamp, label = top.data[2 * i: 2 * i + 2]
        if stamp != r.stamp:
            raise MarseilleError(path, f"timestamp {stamp!r:.40} differs from the day file's {r.stamp}", row=i)
        if isinstance(label, str) and label in WEATHER and label != "?":
            labels.append(label)
        elif isinstance(label, (float, np.floating, int)) and float(label) == 0:
            labels.append("?")
        else:
            raise MarseilleError(path, f"label {label!r:.20} is not one of {', '.join(k for k in WEATHER if k != '?')}", row=i)
    return labels


def acquisitions(rows: Sequence[Row]) -> list[list[Row]]:
    """Rows grouped into acquisitions: a new one starts when the image type does not increase or
    more than ACQUISITION_GAP_S pass."""
    groups: list[list[Row]] = []
    for r in rows:
        if groups and r.image_type > groups[-1][-1].image_type and r.unix_seconds - groups[-1][-1].unix_seconds <= ACQUISITION_GAP_S:
            groups[-1].append(r)
        else:
            groups.append([r])
    return groups


def choose(group: Sequence[Row], frames: str) -> Row | None:
    """The row an acquisition contributes: 'auto' its last auto-exposed image, 'type:N' its image
    of type N (None when it has none)."""
    if frames == "auto":
        auto = [r for r in group if r.image_type < FIRST_FIXED_TYPE]
        return auto[-1] if auto else None
    m = re.fullmatch(r"type:(\d+)", frames)
    if not m:
        raise ValueError(f"frames {frames!r}: 'auto' or 'type:N'")
    hit = [r for r in group if r.image_type == int(m.group(1))]
    return hit[0] if hit else None


# ------------------------------------------------------------------------------------ the scene

def default_sensor_toml(layout: Sequence[float]) -> str:
    """The [sensor] of an imported frame: the PHX050S-QC (colour RGGB blocks over the polarizers),
    12 bits, the database's values as they are (no dark or black-level correction is known), a
    pixel counting as clipped only at the ADC's top (the authors' sat_level is 65500 of 65520)."""
    return (f"preset = \"lucid_phx050s_qc\"\nmosaic_deg = [{', '.join(f'{a:g}' for a in layout)}]\n"
            "adc_bits = 12\nblack_level_dn = 0\ndark_current_e_s = 0\nfull_well_e = 1e9\n")


def scene_text(cal: Calibration, unix_times: Sequence[float], layout: Sequence[float], *,
               sensor_toml: str | None = None, sky: str = "", comment: str = "", binning: int = 1) -> str:
    """A scene whose camera is the calibration's (equidistant f and centre, the crop applied,
    orientation from rot_mat, read out with b×b binning), at the calibration's site, at these times."""
    h, w = cal.size
    q = cal.quaternion()
    instants = ", ".join(f'"{format_time(t)}"' for t in unix_times)
    head = "".join(f"# {line}\n" for line in comment.splitlines())
    return (f"{head}[site]\nlatitude_deg = {cal.latitude_deg!r}\nlongitude_deg = {cal.longitude_deg!r}\n"
            f"height_m = {SITE_HEIGHT_M!r}\n\n[time]\ninstants = [{instants}]\n\n"
            f"[camera]\nmodel = \"equidistant\"\nwidth = {w}\nheight = {h}\nfx = {cal.f_px!r}\n"
            f"cx = {cal.cx!r}\ncy = {cal.cy!r}\nfov_deg = {FOV_DEG!r}\n"
            f"quaternion = [{', '.join(repr(v) for v in q)}]\n" + (f"binning = {binning}\n" if binning != 1 else "") + "\n"
            f"[render]\nbands = [\"R\", \"G\", \"B\"]\n\n"
            + (f"[sensor]\n{sensor_toml if sensor_toml is not None else default_sensor_toml(layout)}\n" if sensor_toml != "" else "")
            + sky)


def lens_mask(scene) -> np.ndarray:
    """Pixels whose centre the lens images, eroded by the reach of the scene's sensor's demosaic
    (the demosaic mixes neighbours: 1 pixel mono, 3 colour), as `skypol import` masks a capture."""
    cam = scene.camera
    inside = np.zeros((cam.height, cam.width), dtype=np.float32)
    u = np.arange(cam.width, dtype=np.float64)
    for y0 in range(0, cam.height, 64):  # in bands: the directions of a whole frame are 150 MB
        v = np.arange(y0, min(cam.height, y0 + 64), dtype=np.float64)
        inside[y0:y0 + len(v)] = cam.pixel_to_direction(u[None, :], v[:, None])["valid"].astype(np.float32)
    return _skypol.erode_for_demosaic(scene._h, inside)


CHANNELS = [f"{s}.{b}" for b in "RGB" for s in ("S0", "S1", "S2", "DoLP", "AoLP")] + ["R", "G", "B", "mask", "clipped"]


# ---------------------------------------------------------------------------------- the import

def _dn(raw: np.ndarray, path: str, row: int) -> np.ndarray:
    """Stored values → 12-bit DN; a value that is not a multiple of 16 is not the database's."""
    if np.any(raw & ((1 << RIGHT_SHIFT) - 1)):
        k = int(np.flatnonzero(raw.ravel() & ((1 << RIGHT_SHIFT) - 1))[0])
        r, c = divmod(k, raw.shape[1])
        raise MarseilleError(path, f"pixel (row {r}, col {c}) holds {int(raw.ravel()[k])}: the database's values are "
                                   f"12 bits shifted left by {RIGHT_SHIFT} (multiples of 16)", row=row)
    return (raw >> RIGHT_SHIFT).astype(np.uint16)  # native order for the demosaic


@dataclass
class Written:
    path: str
    window_min: int       # 0: the whole day
    rows: list[Row]
    labels: list[str]
    layout: tuple[float, ...]


def _windows(times: Sequence[float], window_min: int) -> list[list[int]]:
    if window_min <= 0:
        return [list(range(len(times)))] if times else []
    out: dict[int, list[int]] = {}
    for i, t in enumerate(times):
        out.setdefault(int((t - times[0]) // (60 * window_min)), []).append(i)
    return list(out.values())


def _stack_name(day: str, window_min: int, first: float) -> str:
    if window_min <= 0:
        return f"{day}.exr"
    return f"{day}_{window_min}min_{_dt.datetime.fromtimestamp(first, _dt.timezone.utc):%H%M}Z.exr"


def plan_day(day_path: str, cal: Calibration, *, frames: str = "auto", min_sun_elevation_deg: float = 0.0,
             annotations_path: str | None = None) -> tuple[list[Row], list[str], list[Row]]:
    """A day file's rows, their labels and the rows import_day would make frames of, checked
    against the calibration (pass 1 only: the images are stepped over)."""
    day_path = str(day_path)
    rows = read_day(day_path)
    if rows[0].shape != cal.size:
        raise MarseilleError(day_path, f"image is {rows[0].shape[0]}×{rows[0].shape[1]}, the crop in "
                                       f"{os.path.join(cal.folder, 'params_crop.npy')} is {cal.size[0]}×{cal.size[1]}", row=0)
    if annotations_path is None:
        candidate = day_path[:-len("_raw.npy")] + "_raw_annotations.npy" if day_path.endswith("_raw.npy") else ""
        annotations_path = candidate if candidate and os.path.exists(candidate) else None
    labels = read_annotations(annotations_path, rows) if annotations_path else ["?"] * len(rows)
    chosen = [r for g in acquisitions(rows) if (r := choose(g, frames)) is not None]
    if chosen:
        el = sun_position(cal.latitude_deg, cal.longitude_deg, [r.unix_seconds for r in chosen],
                          height_m=SITE_HEIGHT_M)["elevation_deg"]
        chosen = [r for r, e in zip(chosen, np.atleast_1d(el)) if e >= min_sun_elevation_deg]
    for a, b in zip(chosen, chosen[1:]):
        if not b.unix_seconds > a.unix_seconds:
            raise MarseilleError(day_path, f"two acquisitions at the same time {b.stamp}", row=b.index)
    if not chosen:
        raise MarseilleError(day_path, f"no acquisition with a frame '{frames}' while the sun is above {min_sun_elevation_deg}°")
    return rows, labels, chosen


def import_day(day_path: str, cal: Calibration, out_dir: str, *, layout: Sequence[float] | str = AUTHORS_LAYOUT,
               frames: str = "auto", windows_min: Sequence[int] = (0,), min_sun_elevation_deg: float = 0.0,
               annotations_path: str | None = None, sensor_toml: str | None = None, half: bool = True,
               binning: int = 1, progress: Callable[[str], None] | None = None) -> list[Written]:
    """One day file → stacks in out_dir: for each window length (minutes; 0 = the whole day) one
    stack per window of consecutive acquisitions, named YYYY-MM-DD.exr or
    YYYY-MM-DD_<L>min_<HHMM>Z.exr. Acquisitions whose sun is below min_sun_elevation_deg are left
    out. The annotation file (default: beside the day file) gives every part's skypol:weather.
    layout: the polarizer angles of pixels (0,0) (0,1) (1,0) (1,1), or "auto" to let
    diagnose_layout decide from the day's clearest frames. binning b > 1: each frame is demosaicked
    at full resolution, then its Stokes images averaged over b×b blocks (bin_frame) and written with
    the camera read out binned (camera.binning = b): 4 gives the 409 × 409 frames of the authors'
    own analysis, 16× fewer pixels for the estimators.

    Reads the day file twice, never holding it: once for its rows (images stepped over), once
    copying the chosen images to a temporary folder; every row, label and image is checked
    before the first stack is written, and each stack is written under a temporary name."""
    day_path = str(day_path)
    say = progress or (lambda s: None)
    base = os.path.basename(day_path)
    m = re.fullmatch(r"(\d{4}-\d{2}-\d{2})_raw\.npy", base)
    day = m.group(1) if m else os.path.splitext(base)[0]
    rows, labels, chosen = plan_day(day_path, cal, frames=frames, min_sun_elevation_deg=min_sun_elevation_deg,
                                    annotations_path=annotations_path)
    if binning < 1 or cal.size[0] % binning or cal.size[1] % binning:
        raise ValueError(f"binning {binning}: must divide the images' {cal.size[0]}×{cal.size[1]}")
    say(f"{base}: {len(rows)} rows, {len(chosen)} acquisitions chosen ({frames})")

    tmp = tempfile.mkdtemp(prefix=".skypol-marseille-", dir=out_dir if os.path.isdir(out_dir) else None)
    try:
        spill = {r.blob.serial: os.path.join(tmp, f"{r.index}.u2") for r in chosen if r.blob}
        if spill:
            load_object_array(day_path, spill)
        dn: dict[int, np.ndarray] = {}
        for r in chosen:  # every image checked before anything is written
            raw = (np.memmap(spill[r.blob.serial], dtype=r.dtype, mode="r", shape=r.shape) if r.blob else r.small)
            _dn(np.asarray(raw), day_path, r.index)
            dn[r.index] = raw
        if isinstance(layout, str) and layout == "auto":
            layout = _auto_layout(cal, chosen, labels, dn, day_path, say)
        layout = parse_layout(layout) if isinstance(layout, str) else tuple(layout)
        os.makedirs(out_dir, exist_ok=True)
        written = []
        comment = (f"Imported by skypol.marseille from {base} (Poughon et al., Marseille skylight database)\n"
                   f"calibration: {cal.folder}; frames: {frames}; layout {layout_text(layout)}")
        for L in windows_min:
            times = [r.unix_seconds for r in chosen]
            for idx in _windows(times, int(L)):
                sel = [chosen[i] for i in idx]
                path = os.path.join(out_dir, _stack_name(day, int(L), sel[0].unix_seconds))
                _write_stack(path, cal, sel, labels, dn, layout, sensor_toml, comment, base, half, day_path, binning)
                written.append(Written(path, int(L), sel, [labels[r.index] for r in sel], layout))
                say(f"  {os.path.basename(path)}: {len(sel)} frame(s)")
        return written
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _write_stack(path, cal, sel, labels, dn, layout, sensor_toml, comment, base, half, day_path, binning=1) -> None:
    times = [r.unix_seconds for r in sel]
    scene = parse_scene(scene_text(cal, times, layout, sensor_toml=sensor_toml, comment=comment), file_name=path)
    mask = lens_mask(scene)
    out_scene = scene if binning == 1 else parse_scene(
        scene_text(cal, times, layout, sensor_toml=sensor_toml, comment=comment, binning=binning), file_name=path)
    truth_source = ("sun-fitted calibration: rot_mat.npy and lat_lon.npy of " + os.path.abspath(cal.folder) +
                    " (Poughon et al. fitted the camera's rotation to the sun's image positions against an "
                    "ephemeris; not a survey)")
    attributes = [("skypol:truthSource", truth_source), ("skypol:source", "Marseille skylight database, " + base)]
    parts = [[("skypol:weather", labels[r.index]), ("skypol:weatherName", WEATHER[labels[r.index]]),
              ("skypol:sourceRow", str(r.index)), ("skypol:sourceTimestamp", r.stamp + " (local, UTC+2)"),
              ("skypol:imageType", str(r.image_type)), ("skypol:exposureUs", repr(r.exposure_us))] for r in sel]

    def produce(i: int) -> dict:
        r = sel[i]
        ch = _skypol.demosaic_frame(scene._h, _dn(np.asarray(dn[r.index]), day_path, r.index), mask, r.exposure_us)
        return ch if binning == 1 else bin_frame(ch, mask, binning, scene.bands)

    _skypol.write_stream(out_scene._h, path, times, CHANNELS, produce, "capture", attributes, parts, half, "zip")


def bin_frame(ch: dict, lens: np.ndarray, b: int, bands: Sequence[str]) -> dict:
    """A demosaicked frame's channels over b×b blocks, as a sensor read out binned would see it:
    S0, S1, S2 the blocks' means (Stokes add), zero where a block reaches outside the lens' mask;
    DoLP and AoLP from them by docs/conventions.md's rules (DoLP 0 where S0 ≤ 0, clamped to 1;
    AoLP ½·atan2(S2, S1) in (−90°, 90°], 0 where S1 = S2 = 0); mask 1 where every pixel of the
    block is sky, clipped 1 where any is clipped sky."""
    h, w = lens.shape[0] // b, lens.shape[1] // b

    def blocks(a: np.ndarray) -> np.ndarray:
        return np.asarray(a)[:h * b, :w * b].reshape(h, b, w, b)

    inside = blocks(lens).min(axis=(1, 3)) > 0
    out = {}
    for band in bands:
        s0, s1, s2 = (np.where(inside, blocks(ch[f"S{k}.{band}"]).mean(axis=(1, 3), dtype=np.float64), 0.0) for k in range(3))
        dolp = np.where(s0 > 0, np.minimum(1.0, np.hypot(s1, s2) / np.where(s0 > 0, s0, 1.0)), 0.0)
        aolp = 0.5 * np.arctan2(s2, s1)
        aolp[aolp <= -np.pi / 2] = np.pi / 2
        for name, a in (("S0", s0), ("S1", s1), ("S2", s2), ("DoLP", dolp), ("AoLP", aolp)):
            out[f"{name}.{band}"] = a.astype(np.float32)
        if band in ch:
            out[band] = out[f"S0.{band}"]
    out["mask"] = (blocks(ch["mask"]).min(axis=(1, 3)) > 0).astype(np.float32)
    out["clipped"] = blocks(ch["clipped"]).max(axis=(1, 3)).astype(np.float32)
    return out


# ---------------------------------------------------------------------------- layout diagnostic

def _split_section(text: str, name: str) -> tuple[list[str], list[str]]:
    """The lines of a scene's [name] section (its sub-tables included) and the other lines."""
    inside, mine, rest = False, [], []
    for ln in text.splitlines():
        header = re.match(r"\s*\[\[?\s*([A-Za-z0-9_.]+)\s*\]", ln)
        if header:
            inside = header.group(1) == name or header.group(1).startswith(name + ".")
        (mine if inside else rest).append(ln)
    return mine, rest


def _swap(layout: Sequence[float], a: float, b: float) -> tuple[float, ...]:
    return tuple(b if x % 180 == a else a if x % 180 == b else x for x in layout)


def diagnose_layout(raw_dn: np.ndarray, scene, unix_seconds: float, assumed: Sequence[float] = AUTHORS_LAYOUT, *,
                    min_score: float = 0.5, min_margin: float = 0.25, min_pixels: int = 200) -> dict:
    """Which polarizer layout a raw frame (12-bit DN, the scene camera's size) was taken with.

    The sky's AoLP is predicted from the sun (skypol's ephemeris at the scene's site) through the
    scene's calibrated camera: a single-scattering sky, whose angle is perpendicular to the
    scattering plane. Away from the neutral points (predicted DoLP ≥ 0.2) every order of scattering
    keeps that angle's symmetry, so the test does not depend on the sky model's details. The frame
    is decoded with the `assumed` layout; a 0°/90° swap changes the sign of S1, a wrong 45° sign
    that of S2, so the four hypotheses (±S1, ±S2) turn or mirror the measured pattern. Each is
    scored by the mean of cos 2(AoLP_measured − AoLP_predicted) over the sky (1: a perfect fit, 0:
    unrelated). The best is reported when it scores ≥ min_score and beats the next by ≥ min_margin;
    otherwise (clouds, too little sky) decided is False and nothing is guessed."""
    sensor_lines, other_lines = _split_section(scene.text, "sensor")
    if not sensor_lines:
        raise ValueError("diagnose_layout: the scene has no [sensor] (its colour filter, ADC and gains)")
    sensor_lines = [ln for ln in sensor_lines if not re.match(r"\s*mosaic_deg\s*=", ln)]
    sensor_lines.insert(1, f"mosaic_deg = [{', '.join(f'{a:g}' for a in assumed)}]")
    sensor_scene = parse_scene("\n".join(other_lines + sensor_lines) + "\n")
    mask = lens_mask(sensor_scene)
    meas = _skypol.demosaic_frame(sensor_scene._h, np.ascontiguousarray(raw_dn, dtype=np.uint16), mask, 1000.0)
    bands = sensor_scene.bands
    s1 = sum(meas[f"S1.{b}"] for b in bands)
    s2 = sum(meas[f"S2.{b}"] for b in bands)
    model_lines = [ln for ln in _split_section("\n".join(other_lines), "sky")[1] if not re.match(r"\s*bands\s*=", ln)]
    model = parse_scene("\n".join(model_lines) + '\n[sky]\nmodel = "rayleigh"\n')
    pred = model.render_frame(time=unix_seconds, channels=["DoLP", "AoLP", "mask"])
    use = (meas["mask"] > 0) & (pred["mask"] > 0) & (pred["DoLP.Y"] >= 0.2)
    n = int(use.sum())
    a_pred = pred["AoLP.Y"][use].astype(np.float64)
    hyps = {(1, 1): tuple(assumed), (1, -1): _swap(assumed, 45, 135), (-1, 1): _swap(assumed, 0, 90),
            (-1, -1): _swap(_swap(assumed, 0, 90), 45, 135)}
    scores = {}
    for (g1, g2), lay in hyps.items():
        a = 0.5 * np.arctan2(g2 * s2[use].astype(np.float64), g1 * s1[use].astype(np.float64))
        scores[layout_text(lay)] = float(np.mean(np.cos(2 * (a - a_pred)))) if n else 0.0
    ranked = sorted(scores.items(), key=lambda kv: -kv[1])
    best, second = ranked[0], ranked[1]
    out = {"assumed": layout_text(assumed), "scores": scores, "pixels": n, "layout": None, "decided": False,
           "s1_sign": None, "s2_sign": None}
    if n < min_pixels:
        out["reason"] = f"only {n} sky pixels away from the neutral points and the sun (need {min_pixels})"
    elif best[1] < min_score or best[1] - second[1] < min_margin:
        out["reason"] = (f"too cloudy to tell: the best fit {best[0]} scores {best[1]:.2f} and the next {second[0]} "
                         f"{second[1]:.2f} (need ≥ {min_score} and a margin ≥ {min_margin})")
    else:
        (g1, g2) = next(k for k, v in hyps.items() if layout_text(v) == best[0])
        out.update(layout=best[0], decided=True, s1_sign=g1, s2_sign=g2,
                   reason=f"{best[0]} scores {best[1]:.3f}, the next ({second[0]}) {second[1]:.3f}")
    return out


def _clearest(cal: Calibration, chosen: Sequence[Row], labels: Sequence[str], count: int) -> list[Row]:
    """Up to `count` frames for the layout diagnostic: clear labels first, then few clouds and mist,
    each nearest to local solar noon (the sky's pattern is then in the middle of the image)."""
    noon_h = 12 - cal.longitude_deg / 15
    def rank(r: Row):
        hour = (r.unix_seconds % 86400) / 3600
        return ({"c": 0, "f": 1, "m": 2}.get(labels[r.index], 3), abs(hour - noon_h))
    return sorted(chosen, key=rank)[:count]


def diagnose_day(day_path: str, cal: Calibration, *, count: int = 5, frames: str = "auto",
                 progress: Callable[[str], None] | None = None) -> list[dict]:
    """diagnose_layout on a day's clearest frames (see _clearest), decoded as the authors' layout:
    one result per frame, with its row, timestamp and label. Reads the day file twice (its rows,
    then those frames' images); writes nothing but a temporary copy of the images."""
    rows, labels, chosen = plan_day(day_path, cal, frames=frames)
    picks = _clearest(cal, chosen, labels, count)
    tmp = tempfile.mkdtemp(prefix=".skypol-marseille-")
    try:
        spill = {r.blob.serial: os.path.join(tmp, f"{r.index}.u2") for r in picks if r.blob}
        if spill:
            load_object_array(day_path, spill)
        out = []
        for r in picks:
            raw = np.fromfile(spill[r.blob.serial], dtype=r.dtype).reshape(r.shape) if r.blob else r.small
            out.append(_diagnose_row(cal, r, labels[r.index], _dn(raw, day_path, r.index), progress))
        return out
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _diagnose_row(cal: Calibration, r: Row, label: str, dn: np.ndarray, progress) -> dict:
    scene = parse_scene(scene_text(cal, [r.unix_seconds], AUTHORS_LAYOUT))
    d = diagnose_layout(dn, scene, r.unix_seconds)
    d.update(row=r.index, timestamp=r.stamp, weather=label)
    if progress:
        progress(f"  layout diagnostic, row {r.index} {r.stamp} ({label}): {d['reason']}")
    return d


def verdict(results: Sequence[dict]) -> str | None:
    """The layout most of the decided diagnostics name (None when none decided)."""
    votes: dict[str, int] = {}
    for d in results:
        if d["decided"]:
            votes[d["layout"]] = votes.get(d["layout"], 0) + 1
    return max(votes.items(), key=lambda kv: kv[1])[0] if votes else None


def _auto_layout(cal, chosen, labels, dn, day_path, say) -> tuple[float, ...]:
    """The layout most of the day's clearest frames decide."""
    results = [_diagnose_row(cal, r, labels[r.index], _dn(np.asarray(dn[r.index]), day_path, r.index), say)
               for r in _clearest(cal, chosen, labels, 5)]
    best = verdict(results)
    if best is None:
        raise MarseilleError(day_path, "the layout diagnostic could not decide on any of the day's clearest frames: "
                                       "give the layout (e.g. --layout 0/45/135/90)")
    return parse_layout(best)


def write_manifest(path: str, written: Sequence[Written]) -> None:
    """One CSV line per part of every stack written (temporary name, renamed)."""
    tmp = path + ".tmp"
    with open(tmp, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stack", "window_min", "part", "utc", "local_timestamp", "row", "image_type", "exposure_us", "weather"])
        for s in written:
            for k, (r, lab) in enumerate(zip(s.rows, s.labels)):
                w.writerow([os.path.basename(s.path), s.window_min, k, format_time(r.unix_seconds), r.stamp, r.index,
                            r.image_type, r.exposure_us, lab])
    os.replace(tmp, path)
