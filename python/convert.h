// What the bindings share: C++ values as Python ones (dicts of degrees and NumPy arrays, the way a
// notebook wants them), instants from Python, NumPy views that share a frame's memory, and
// skypol.SceneError, the Python face of scene::SceneError.
//
// Each C++ result type is turned into Python in exactly one function here (truth_to_dict,
// estimate_to_dict, score_to_dict): a new field of the C++ struct is one line in that function,
// and the Python side (skypol.Estimate's fields, the dicts) follows without further changes.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "scene/truth.h"
#include "skypole/estimate.h"
#include "sky/time.h"

namespace skypol::python {

namespace py = pybind11;

// Person-facing: degrees, ISO 8601 times, None for an undefined value (never NaN).
py::dict truth_to_dict(const scene::Truth& truth);
py::dict estimate_to_dict(const skypole::PoleEstimate& estimate);
py::dict score_to_dict(const skypole::Score& score);
// The inverse of estimate_to_dict (its keys; others, such as "score", are ignored), for an estimate
// handed back to C++ (skypol.plot_estimate). Throws std::invalid_argument naming a missing key.
skypole::PoleEstimate estimate_from_dict(const py::dict& d);

py::array_t<double> to_array(const Eigen::Vector3d& v);
py::array_t<double> to_array(const Eigen::Matrix3d& m);
py::object optional_pixel(const std::optional<Eigen::Vector2d>& pixel);  // (u, v) or None

// A float channel of a frame as a height×width NumPy array over the same memory (no copy). `owner`
// is the Python object that keeps the vector alive (the stack holding the frame); the vector must
// never be resized while an array exists (stacks in python/ never resize a frame's channels).
py::array_t<float> channel_view(std::vector<float>& channel, int width, int height, py::handle owner);

// Unix seconds (float) → Instant, checked finite.
sky::Instant instant_of(double unix_seconds);

// skypol.SceneError(ValueError) with file, line, column (None when unknown) and key (None when the
// message names none), whose str() is exactly what the CLI prints for the same error.
void register_errors(py::module_& m);

// The key a SceneError message names ("key 'camera.fov_deg': …", "unknown key 'x'", "missing key
// 'y' …"), or "" when it names none.
std::string key_of_message(const std::string& message);

}  // namespace skypol::python
