"""skypol from Python: scenes, rendering into NumPy, stacks, estimators, lenses and the sun.

The C++ library does the work (the extension module skypol._skypol); this file is the interface a
notebook sees, documented in docs/python.md. Conventions are the project's (docs/conventions.md):
ENU world frame, azimuth from North towards East, degrees at every interface, OpenCV pixel centres,
times as Unix seconds (UTC) or ISO 8601 text with a zone.

    import skypol
    scene = skypol.load_scene("scenes/skypole-marseille.toml", overrides={"camera.binning": 8})
    stack = skypol.render_stack(scene)          # frames as NumPy arrays, truth as dicts
    est = skypol.estimate(stack, "classic")     # skypol.Estimate (a dataclass)
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import json
import math
import numbers
from typing import Any, Iterable, Mapping, Sequence

import numpy as np

from . import _skypol
from ._skypol import SceneError, method_names, parse_time, format_time

__all__ = [
    "SceneError", "Scene", "Camera", "Frame", "Stack", "Estimate",
    "load_scene", "parse_scene", "render_frame", "render_stack", "iter_frames", "read_stack", "write_stack",
    "stack_from_arrays", "estimate", "plot_estimate", "method_names", "methods", "sun_position", "parse_time", "format_time",
    "marseille",
]


# ---------------------------------------------------------------------------------------- times

def _unix_seconds(times: Any) -> np.ndarray:
    """Times as a 1-D float64 array of Unix seconds. Accepts numbers (Unix seconds), ISO 8601 text
    with a zone (the rules of scene files), timezone-aware datetime objects and numpy datetime64
    (taken as UTC), alone or in a sequence or array."""
    if isinstance(times, (str, bytes, numbers.Real, _dt.datetime, np.datetime64)):
        times = [times]
    a = np.asarray(times)
    if a.dtype.kind == "M":
        return (a.astype("datetime64[ns]").astype(np.int64) / 1e9).astype(np.float64).ravel()
    if a.dtype.kind in "iuf":
        return a.astype(np.float64).ravel()
    out = []
    for t in a.ravel().tolist():
        if isinstance(t, (bytes, str)):
            out.append(parse_time(t.decode() if isinstance(t, bytes) else t))
        elif isinstance(t, _dt.datetime):
            if t.tzinfo is None:
                raise ValueError(f"time {t!r}: a datetime needs a time zone (e.g. tzinfo=datetime.timezone.utc)")
            out.append(t.timestamp())
        elif isinstance(t, np.datetime64):
            out.append(float(t.astype("datetime64[ns]").astype(np.int64)) / 1e9)
        elif isinstance(t, numbers.Real):
            out.append(float(t))
        else:
            raise TypeError(f"time {t!r}: expected Unix seconds, ISO 8601 text, a datetime or numpy datetime64")
    return np.asarray(out, dtype=np.float64)


# ------------------------------------------------------------------------------------ overrides

def _toml_value(value: Any) -> str:
    """A Python value as the TOML text `--set key=value` takes. Strings are passed as typed on the
    command line (so "equisolid" is a bare word, "2022-09-23" a date and "[1, 2]" an array, exactly
    as with --set); bools, numbers, lists and dicts become TOML."""
    if isinstance(value, str):
        return value
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        if not math.isfinite(float(value)):
            return "nan" if math.isnan(float(value)) else ("inf" if value > 0 else "-inf")
        return repr(float(value))
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_quoted(v) for v in value) + "]"
    if isinstance(value, Mapping):
        return "{" + ", ".join(f"{k} = {_toml_quoted(v)}" for k, v in value.items()) + "}"
    raise TypeError(f"override value {value!r}: expected a string, number, bool, list or dict")


def _toml_quoted(value: Any) -> str:
    """Inside arrays and tables a string is a TOML string, quoted by the scene language's own rule
    (the C++ scene::toml_quoted: control characters escaped too)."""
    if isinstance(value, str):
        return _skypol.toml_quoted(value)
    return _toml_value(value)


def _assignments(overrides: Mapping[str, Any] | Iterable[str] | None) -> list[str]:
    if overrides is None:
        return []
    if isinstance(overrides, Mapping):
        return [f"{k}={_toml_value(v)}" for k, v in overrides.items()]
    if isinstance(overrides, str):
        return [overrides]
    return [str(o) for o in overrides]


# ---------------------------------------------------------------------------------------- scene

class Camera:
    """A calibrated camera (lens, orientation, transport): both ways between pixels and world
    directions, vectorized; the zero-copy twin of `skypol lens`."""

    def __init__(self, handle: _skypol.Camera):
        self._h = handle

    width = property(lambda self: self._h.width)
    height = property(lambda self: self._h.height)
    lens = property(lambda self: self._h.lens, doc="lens model name")
    intrinsics = property(lambda self: self._h.intrinsics, doc="fx, fy, cx, cy, width, height")
    parameters = property(lambda self: dict(self._h.parameters), doc="the lens model's parameters by name")
    field_of_view_deg = property(lambda self: self._h.field_of_view_deg)
    world_from_camera = property(lambda self: self._h.world_from_camera)
    transport = property(lambda self: self._h.transport)

    def pixel_to_direction(self, u: Any, v: Any) -> dict[str, np.ndarray]:
        """World directions seen by pixels (u, v) (OpenCV centres; arrays broadcast together).
        Returns direction (…, 3, ENU unit vectors), azimuth_deg, elevation_deg, off_axis_deg and
        valid (False outside the image circle, where the others are NaN)."""
        u, v = np.broadcast_arrays(np.asarray(u, dtype=np.float64), np.asarray(v, dtype=np.float64))
        r = self._h._rays(np.ascontiguousarray(u).ravel(), np.ascontiguousarray(v).ravel())
        shape = u.shape
        return {k: (a.reshape(shape + (3,)) if k == "direction" else a.reshape(shape)) for k, a in r.items()}

    def direction_to_pixel(self, azimuth_deg: Any = None, elevation_deg: Any = None, *,
                           direction: Any = None) -> dict[str, np.ndarray]:
        """Pixels of world directions, given as azimuth and elevation in degrees (arrays broadcast
        together) or as ENU vectors (direction=…, shape (…, 3)). Returns u, v (NaN where the lens
        cannot image the direction), valid, and on_sensor (the pixel also lies on the sensor)."""
        if direction is not None:
            if azimuth_deg is not None or elevation_deg is not None:
                raise ValueError("direction_to_pixel: give azimuth and elevation, or direction, not both")
            d = np.asarray(direction, dtype=np.float64)
            if d.shape[-1:] != (3,):
                raise ValueError("direction_to_pixel: direction must have shape (..., 3)")
            shape = d.shape[:-1]
        else:
            if azimuth_deg is None or elevation_deg is None:
                raise ValueError("direction_to_pixel: give azimuth_deg and elevation_deg (degrees), or direction")
            az, el = np.broadcast_arrays(np.radians(np.asarray(azimuth_deg, dtype=np.float64)),
                                         np.radians(np.asarray(elevation_deg, dtype=np.float64)))
            d = np.stack([np.cos(el) * np.sin(az), np.cos(el) * np.cos(az), np.sin(el)], axis=-1)
            shape = az.shape
        r = self._h._project(np.ascontiguousarray(d.reshape(-1, 3)))
        return {k: a.reshape(shape) for k, a in r.items()}

    def __repr__(self) -> str:
        return f"<skypol.Camera {self.lens} {self.width}x{self.height}, {self.field_of_view_deg:.1f} deg>"


class Scene:
    """A checked scene (docs/scenes.md). Build with load_scene or parse_scene."""

    def __init__(self, handle: _skypol.Scene):
        self._h = handle
        self._camera: Camera | None = None

    file = property(lambda self: self._h.file)
    text = property(lambda self: self._h.text, doc="the scene as loaded (merged, with overrides)")
    times = property(lambda self: self._h.times, doc="frame times, Unix seconds (UTC)")
    iso_times = property(lambda self: [format_time(t) for t in self._h.times])
    site = property(lambda self: self._h.site)
    sun_options = property(lambda self: self._h.sun_options)
    orientation = property(lambda self: self._h.orientation, doc="heading_deg, tilt_deg, roll_deg")
    bands = property(lambda self: self._h.bands)
    channel_names = property(lambda self: self._h.channel_names, doc="channels a rendered frame holds")
    output_path = property(lambda self: self._h.output_path)
    sky_model = property(lambda self: self._h.sky_model)

    @property
    def camera(self) -> Camera:
        if self._camera is None:
            self._camera = Camera(self._h.camera())
        return self._camera

    def truth(self, time: Any) -> dict:
        """The ground truth of a frame at `time` (sun, orientation, pole and its pixel)."""
        return self._h.truth(self.camera._h, float(_unix_seconds(time)[0]))

    def sun_positions(self, times: Any = None) -> dict[str, np.ndarray]:
        """The sun at the scene's site with its refraction options, for `times` (default: the scene's)."""
        t = self.times if times is None else _unix_seconds(times)
        return self._h.sun_positions(t)

    def render_frame(self, index: int = 0, *, time: Any = None, channels: Sequence[str] | None = None) -> "Frame":
        return render_frame(self, index, time=time, channels=channels)

    def render_stack(self, **kwargs: Any) -> "Stack":
        return render_stack(self, **kwargs)

    def __repr__(self) -> str:
        return f"<skypol.Scene {self.file!r}: {len(self.times)} time(s), {self.camera!r}>"


def load_scene(path: str, overrides: Mapping[str, Any] | Iterable[str] | None = None) -> Scene:
    """A scene file, checked like the CLI checks it. overrides: {"camera.binning": 8, ...} or
    ["camera.binning=8", ...], applied like `--set` (a string value is taken as typed after '=').
    Raises SceneError (file, line, column, key) on any problem."""
    return Scene(_skypol.load_scene(str(path), _assignments(overrides)))


def parse_scene(text: str, file_name: str = "<string>",
                overrides: Mapping[str, Any] | Iterable[str] | None = None) -> Scene:
    """A scene from TOML text; `file_name` appears in errors and resolves includes."""
    return Scene(_skypol.parse_scene(text, file_name, _assignments(overrides)))


# ---------------------------------------------------------------------------------------- stack

@dataclasses.dataclass(frozen=True)
class Frame:
    """One frame: channels as height×width float32 arrays (views of the stack's memory, no copy:
    "S0.Y" … "AoLP.Y" (radians), "mask"), and its truth as a dict."""
    index: int
    time: str
    channels: dict[str, np.ndarray]
    truth: dict

    def __getitem__(self, name: str) -> np.ndarray:
        return self.channels[name]

    @property
    def shape(self) -> tuple[int, int]:
        return next(iter(self.channels.values())).shape if self.channels else (0, 0)


class Stack:
    """A time series seen by one camera, in memory. stack[i] is a Frame; stack.channel("DoLP.Y")
    stacks one channel of every frame into a frames×height×width array (a copy)."""

    def __init__(self, handle: _skypol.StackHandle):
        self._h = handle
        self._frames: list[Frame | None] = [None] * len(handle)

    def __len__(self) -> int:
        return len(self._frames)

    def __getitem__(self, i: int) -> Frame:
        n = len(self)
        if i < 0:
            i += n
        if not 0 <= i < n:
            raise IndexError(f"frame {i} of a stack of {n}")
        f = self._frames[i]
        if f is None:
            truth = self._h.truth(i)
            f = Frame(i, truth["time"], {c: self._h.channel(i, c) for c in self._h.channel_names(i)}, truth)
            self._frames[i] = f
        return f

    def __iter__(self):
        return (self[i] for i in range(len(self)))

    frames = property(lambda self: list(self))
    bands = property(lambda self: self._h.bands)
    camera = property(lambda self: Camera(self._h.camera))
    camera_description = property(lambda self: self._h.camera_description)
    scene_text = property(lambda self: self._h.scene_text)
    # False for a capture (skypol import): nothing to score against, estimates carry score None.
    truth_known = property(lambda self: self._h.truth_known)
    site_known = property(lambda self: self._h.site_known)
    channel_names = property(lambda self: self._h.channel_names(0) if len(self) else [])
    truths = property(lambda self: [f.truth for f in self])
    times = property(lambda self: np.array([f.truth["unix_seconds"] for f in self], dtype=np.float64))

    def channel(self, name: str) -> np.ndarray:
        """One channel of every frame, frames×height×width (a new array)."""
        return np.stack([f[name] for f in self]) if len(self) else np.empty((0, 0, 0), np.float32)

    def estimate(self, method: str | Sequence[str] = "classic", **options: Any):
        return estimate(self, method, **options)

    def write(self, path: str, channels: Sequence[str] | None = None, half: bool = False,
              compression: str = "zip") -> None:
        write_stack(path, self, channels=channels, half=half, compression=compression)

    def __repr__(self) -> str:
        h, w = self._h.size(0) if len(self) else (0, 0)
        return f"<skypol.Stack {len(self)} frame(s) {w}x{h}, channels {self.channel_names}>"


def _frame_selection(frames: Any) -> list[int] | None:
    if frames is None:
        return None
    if isinstance(frames, numbers.Integral):
        return [int(frames)]
    if isinstance(frames, slice):
        raise TypeError("frames: give a list of indices (e.g. range(0, 23, 2)), not a slice")
    return [int(i) for i in frames]


def render_stack(scene: Scene, *, frames: Any = None, times: Any = None,
                 channels: Sequence[str] | None = None) -> Stack:
    """Render a scene into memory: every time of the scene, or frames=[indices], or times=[…]
    (instead of the scene's). channels: a subset of S0, S1, S2, S3, DoLP, AoLP, mask (default: the
    scene's output.channels). Bit for bit what `skypol render` writes at float precision."""
    t = None if times is None else _unix_seconds(times).tolist()
    return Stack(_skypol.render(scene._h, _frame_selection(frames), t,
                                None if channels is None else list(channels)))


def iter_frames(scene: Scene, *, channels: Sequence[str] | None = None, copy: bool = False):
    """The scene's frames one at a time, as `skypol render` renders them: the renderer is set up
    once and, without a [sensor], every frame is rendered into the same memory, so a frame's
    arrays are overwritten by the next one (copy=True gives each frame its own arrays). The way to
    go through a full-resolution series without holding it all (2.8 GB for the paper's scene)."""
    stream = _skypol.FrameStream(scene._h, None if channels is None else list(channels))
    for k in range(len(scene.times)):
        h = stream.render(k)
        arrays = {c: h.channel(0, c) for c in h.channel_names(0)}
        if copy:
            arrays = {c: a.copy() for c, a in arrays.items()}
        truth = h.truth(0)
        yield Frame(k, truth["time"], arrays, truth)


def render_frame(scene: Scene, index: int = 0, *, time: Any = None,
                 channels: Sequence[str] | None = None) -> Frame:
    """One frame: the scene's frame `index`, or the scene at `time`."""
    if time is not None:
        return render_stack(scene, times=time, channels=channels)[0]
    return render_stack(scene, frames=[index], channels=channels)[0]


def read_stack(path: str, channels: Sequence[str] | None = None) -> Stack:
    """A stack file (all channels, or those named); raises SceneError for a file that is not one."""
    return Stack(_skypol.read_stack(str(path), list(channels or [])))


def stack_from_arrays(scene: Scene, times: Any, channels: Mapping[str, Any]) -> Stack:
    """A stack from arrays: channels maps names ("DoLP.Y", "AoLP.Y", "mask", "S0.Y", …) to
    frames×height×width arrays (copied once, as float32); the camera, site and orientation (the
    truth) are the scene's, the frames' times are `times`."""
    t = _unix_seconds(times)
    arrays = {str(k): np.ascontiguousarray(v, dtype=np.float32) for k, v in channels.items()}
    return Stack(_skypol.stack_from_arrays(scene._h, t.tolist(), arrays))


def write_stack(path: str, stack: Stack | Mapping[str, Any], *, scene: Scene | None = None, times: Any = None,
                channels: Sequence[str] | None = None, half: bool = False, compression: str = "zip") -> None:
    """Write a stack file (a temporary name, renamed when complete). `stack` is a Stack, or arrays
    as for stack_from_arrays together with scene= and times=. channels: which to write (default all)."""
    if not isinstance(stack, Stack):
        if scene is None or times is None:
            raise ValueError("write_stack: arrays need scene= and times=")
        stack = stack_from_arrays(scene, times, stack)
    stack._h.write(str(path), list(channels or []), half, compression)


# ------------------------------------------------------------------------------------ estimators

# One field per key of the C++ conversion (python/convert.cpp, estimate_to_dict) plus "score": a new
# field of skypole::PoleEstimate appears here without a change to this file.
Estimate = dataclasses.make_dataclass(
    "Estimate", [(name, Any) for name in _skypol.estimate_fields()], frozen=True,
    namespace={
        "to_dict": lambda self: dataclasses.asdict(self),
        "__module__": __name__,
        "__doc__": "An estimator's result: every field of skypole::PoleEstimate (skypole/estimate.h; "
                   "valid, why_invalid, note, latitude_deg, heading_deg, residual_deg, sigma_bearing_deg, sigma_latitude_deg, sigma_deg, cone95_deg, "
                   "seconds, …) and score (errors against the stack's truth; None when invalid).",
    })


def estimate(data: Stack | Mapping[str, Any] | np.ndarray, method: str | Sequence[str] = "classic", *,
             scene: Scene | None = None, times: Any = None, band: str = "", hemisphere: str = "automatic",
             min_elevation_deg: float = 0.0, heading_undefined_within_deg: float = 0.5,
             attitude: tuple[float, float] | None = None, site: str = "stack", polarizer_model: str = "stack",
             as_dict: bool = False):
    """Estimate north with one estimator (an Estimate) or several (a list; "all" is every one).
    data: a Stack, or arrays with scene= and times= (a dict of channels as for stack_from_arrays,
    or a frames×height×width DoLP array of the scene's first band). attitude: (tilt_deg, roll_deg)
    the estimator may use (default: the truth's). site: "stack" (its site and times, if it knows them)
    or "unknown" (as if it did not: methods that need the site decline, auto is site-free; the CLI's
    --site). polarizer_model: "stack" (fit the sensor's polarizer angle errors on the frames whose
    AoLP assumed their nominal angles), "always" or "never" (the CLI's --polarizer-model). The GIL
    is released while estimating."""
    if not isinstance(data, Stack):
        if scene is None or times is None:
            raise ValueError("estimate: arrays need scene= and times=")
        if not isinstance(data, Mapping):
            data = {f"DoLP.{scene.bands[0]}": data}
        data = stack_from_arrays(scene, times, data)
    methods = list(method_names()) if method == "all" else ([method] if isinstance(method, str) else list(method))
    out = []
    for m in methods:
        d = _skypol.estimate(data._h, m, band, hemisphere, min_elevation_deg, heading_undefined_within_deg,
                             None if attitude is None else (float(attitude[0]), float(attitude[1])), site,
                             polarizer_model)
        out.append(d if as_dict else Estimate(**d))
    return out[0] if isinstance(method, str) and method != "all" else out


def methods() -> list[dict[str, Any]]:
    """The estimators' registry (skypole/method_registry.h; `skypol methods --json`): one dict per
    method, in the order "all" runs them, with name, description, its traits (frame_jackknife_max_groups,
    sector_jackknife, used_by_auto, needs_site, misfit_measured, auto_answers_alone) and calibration
    (a dict; an unbounded gate is None). "auto", their combination, is not one of them."""
    return json.loads(_skypol.methods_json())


def plot_estimate(stack: Stack, estimates: Any, path: str, *, band: str = "", min_elevation_deg: float = 0.0,
                  frame: int | None = None) -> list[str]:
    """The picture `skypol estimate --plot` draws (skypole/estimate_plot.h), of `estimates` (an
    Estimate, a dict of estimate(as_dict=True), or a list of them) on `stack`: a PNG at `path`, or
    one PNG per method in the folder `path` names (a path ending in "/" or an existing folder).
    band and min_elevation_deg as given to estimate(); frame: the frame shown (default: the middle
    one). Returns the files written."""
    items = estimates if isinstance(estimates, (list, tuple)) else [estimates]
    dicts = [e if isinstance(e, Mapping) else e.to_dict() for e in items]
    return _skypol.plot_estimate(stack._h, dicts, str(path), band, float(min_elevation_deg),
                                 None if frame is None else int(frame))


# ------------------------------------------------------------------------------------------- sun

def sun_position(latitude_deg: float, longitude_deg: float, times: Any, *, height_m: float = 0.0,
                 pressure_hpa: float = 0.0, temperature_c: float = 15.0, relative_humidity: float = 0.5,
                 wavelength_um: float = 0.55, ut1_minus_utc_s: float = 0.0, refraction: str = "spa",
                 delta_t_s: float | None = None) -> dict[str, np.ndarray]:
    """The sun's apparent position (ERFA; the options of `skypol sun`) for an array of times:
    azimuth_deg, elevation_deg, declination_deg, hour_angle_deg shaped like `times`, and
    direction (…, 3) in ENU."""
    shape = np.shape(times) if not isinstance(times, (str, bytes)) else ()
    t = _unix_seconds(times)
    r = _skypol.sun_positions(float(latitude_deg), float(longitude_deg), float(height_m), t, float(pressure_hpa),
                              float(temperature_c), float(relative_humidity), float(wavelength_um),
                              float(ut1_minus_utc_s), refraction, delta_t_s)
    return {k: (a.reshape(shape + (3,)) if k == "direction" else a.reshape(shape)) for k, a in r.items()}


# Poughon et al.'s Marseille skylight database into stacks (docs/import.md); imported last: it uses the above.
from . import marseille  # noqa: E402
