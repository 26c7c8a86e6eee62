#include "python/convert.h"

#include <pybind11/stl.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "scene/scene_error.h"
#include "sky/units.h"

namespace skypol::python {
namespace {

py::object none_or(const std::optional<double>& v) { return v ? py::object(py::float_(*v)) : py::object(py::none()); }

// The exception type, created once when the module is imported and kept for the process's life.
PyObject* scene_error_type = nullptr;
}  // namespace

py::array_t<double> to_array(const Eigen::Vector3d& v) {
  py::array_t<double> a(3);
  for (py::ssize_t i = 0; i < 3; ++i) a.mutable_at(i) = v(i);
  return a;
}

py::array_t<double> to_array(const Eigen::Matrix3d& m) {
  py::array_t<double> a({3, 3});
  for (py::ssize_t r = 0; r < 3; ++r) {
    for (py::ssize_t c = 0; c < 3; ++c) a.mutable_at(r, c) = m(r, c);
  }
  return a;
}

py::object optional_pixel(const std::optional<Eigen::Vector2d>& pixel) {
  if (!pixel) return py::none();
  return py::make_tuple(pixel->x(), pixel->y());
}

py::dict truth_to_dict(const scene::Truth& t) {
  py::dict sun;
  sun["azimuth_deg"] = t.sun.azimuth * kDegPerRad;
  sun["elevation_deg"] = t.sun.elevation * kDegPerRad;
  sun["declination_deg"] = t.sun.declination * kDegPerRad;
  sun["hour_angle_deg"] = t.sun.hour_angle * kDegPerRad;
  sun["direction"] = to_array(t.sun.direction);
  py::dict site;
  site["latitude_deg"] = t.site.latitude_deg;
  site["longitude_deg"] = t.site.longitude_deg;
  site["height_m"] = t.site.height_m;
  py::dict d;
  d["time"] = sky::format_iso8601(t.time);
  d["unix_seconds"] = t.time.unix_seconds;
  d["site"] = site;
  d["sun"] = sun;
  d["world_from_camera"] = to_array(t.world_from_camera);
  d["heading_deg"] = t.heading_deg;
  d["tilt_deg"] = t.tilt_deg;
  d["roll_deg"] = t.roll_deg;
  d["pole_enu"] = to_array(t.pole_enu);
  d["pole_is_north"] = t.pole_is_north;
  d["pole_pixel"] = optional_pixel(t.pole_pixel);
  return d;
}

py::dict estimate_to_dict(const skypole::PoleEstimate& e) {
  py::dict d;
  d["method"] = e.method;
  d["valid"] = e.valid;
  d["why_invalid"] = e.why_invalid;
  d["note"] = e.note;
  d["pole_camera"] = to_array(e.pole_camera);
  d["pole_level"] = to_array(e.pole_level);
  d["pixel"] = optional_pixel(e.pixel);
  d["azimuth_rel_deg"] = e.azimuth_rel_deg;
  d["altitude_deg"] = e.altitude_deg;
  d["latitude_deg"] = e.latitude_deg;
  d["heading_deg"] = none_or(e.heading_deg);
  d["is_north"] = e.is_north;
  d["residual_deg"] = e.residual_deg;
  d["sigma_bearing_deg"] = e.sigma_bearing_deg;
  d["sigma_latitude_deg"] = e.sigma_latitude_deg;
  d["sigma_deg"] = e.sigma_deg;
  d["cone95_deg"] = e.cone95_deg;
  d["seconds"] = e.seconds;
  return d;
}

skypole::PoleEstimate estimate_from_dict(const py::dict& d) {
  const auto get = [&](const char* key) -> py::object {
    if (!d.contains(key)) throw std::invalid_argument(std::string("estimate: the key '") + key + "' is missing");
    return d[key];
  };
  const auto vector3 = [&](const char* key) {
    const auto a = get(key).cast<std::vector<double>>();
    if (a.size() != 3) throw std::invalid_argument(std::string("estimate: '") + key + "' needs 3 numbers");
    return Eigen::Vector3d(a[0], a[1], a[2]);
  };
  skypole::PoleEstimate e;
  e.method = get("method").cast<std::string>();
  e.valid = get("valid").cast<bool>();
  e.why_invalid = get("why_invalid").cast<std::string>();
  e.note = get("note").cast<std::string>();
  e.pole_camera = vector3("pole_camera");
  e.pole_level = vector3("pole_level");
  if (const py::object px = get("pixel"); !px.is_none()) {
    const auto uv = px.cast<std::vector<double>>();
    if (uv.size() != 2) throw std::invalid_argument("estimate: 'pixel' needs 2 numbers or None");
    e.pixel = Eigen::Vector2d(uv[0], uv[1]);
  }
  e.azimuth_rel_deg = get("azimuth_rel_deg").cast<double>();
  e.altitude_deg = get("altitude_deg").cast<double>();
  e.latitude_deg = get("latitude_deg").cast<double>();
  if (const py::object h = get("heading_deg"); !h.is_none()) e.heading_deg = h.cast<double>();
  e.is_north = get("is_north").cast<bool>();
  e.residual_deg = get("residual_deg").cast<double>();
  e.sigma_bearing_deg = get("sigma_bearing_deg").cast<double>();
  e.sigma_latitude_deg = get("sigma_latitude_deg").cast<double>();
  e.sigma_deg = get("sigma_deg").cast<double>();
  e.cone95_deg = get("cone95_deg").cast<double>();
  e.seconds = get("seconds").cast<double>();
  return e;
}

py::dict score_to_dict(const skypole::Score& s) {
  py::dict d;
  d["bearing_error_deg"] = none_or(s.bearing_error_deg);
  d["latitude_error_deg"] = s.latitude_error_deg;
  d["angular_error_deg"] = s.angular_error_deg;
  return d;
}

py::array_t<float> channel_view(std::vector<float>& channel, int width, int height, py::handle owner) {
  if (channel.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height)) {
    throw std::logic_error("channel_view: channel size does not match the frame");
  }
  const auto w = static_cast<py::ssize_t>(width), h = static_cast<py::ssize_t>(height);
  const auto f = static_cast<py::ssize_t>(sizeof(float));
  return py::array_t<float>({h, w}, {w * f, f}, channel.data(), owner);
}

sky::Instant instant_of(double unix_seconds) {
  if (!std::isfinite(unix_seconds)) throw std::invalid_argument("time: expected a finite number of Unix seconds");
  return sky::Instant{unix_seconds};
}

std::string key_of_message(const std::string& message) {
  // SceneError's text is "<loc>: error: <message>"; the key is quoted after "key '" in the message.
  const std::string::size_type body = message.find(": error: ");
  const std::string::size_type from = body == std::string::npos ? 0 : body;
  const std::string::size_type k = message.find("key '", from);
  if (k == std::string::npos) return "";
  const std::string::size_type begin = k + 5;
  const std::string::size_type end = message.find('\'', begin);
  if (end == std::string::npos) return "";
  return message.substr(begin, end - begin);
}

void register_errors(py::module_& m) {
  scene_error_type = PyErr_NewExceptionWithDoc(
      "skypol.SceneError",
      "A scene or stack file that skypol cannot use: str() is the CLI's message, file:line:col: error: ...; "
      "attributes file, line, column (None when unknown) and key (None when the message names none).",
      PyExc_ValueError, nullptr);
  if (scene_error_type == nullptr) throw py::error_already_set();
  m.attr("SceneError") = py::handle(scene_error_type);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const scene::SceneError& e) {
      const scene::FileLoc& loc = e.where();
      py::object type = py::reinterpret_borrow<py::object>(scene_error_type);
      py::object exc = type(e.what());
      exc.attr("file") = loc.file;
      exc.attr("line") = loc.line > 0 ? py::object(py::int_(loc.line)) : py::object(py::none());
      exc.attr("column") = loc.line > 0 ? py::object(py::int_(loc.column)) : py::object(py::none());
      const std::string key = key_of_message(e.what());
      exc.attr("key") = key.empty() ? py::object(py::none()) : py::object(py::str(key));
      PyErr_SetObject(scene_error_type, exc.ptr());
    }
  });
}

}  // namespace skypol::python
