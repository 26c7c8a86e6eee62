// A scene's or a stack's camera both ways, vectorized (camera/camera.h): the world direction each
// pixel sees and the pixel each world direction images at — what `skypol lens` prints for one
// point, for whole arrays. Undefined results are NaN with valid = False, never garbage.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "camera/camera.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "sky/sun.h"
#include "sky/units.h"

namespace skypol::python {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

template <class F>
void parallel(py::ssize_t n, F&& f) {
  py::gil_scoped_release release;
  tbb::parallel_for(tbb::blocked_range<py::ssize_t>(0, n, 4096), [&](const tbb::blocked_range<py::ssize_t>& r) {
    for (py::ssize_t i = r.begin(); i != r.end(); ++i) f(i);
  });
}

// Pixels (flat u, v) → world directions, azimuth, elevation, angle off the optical axis.
py::dict rays(const camera::Camera& cam, const Doubles& u, const Doubles& v) {
  if (u.size() != v.size()) throw std::invalid_argument("pixel_to_direction: u and v differ in size");
  const py::ssize_t n = u.size();
  Doubles dir({n, py::ssize_t{3}}), az(n), el(n), off(n);
  py::array_t<bool> valid(n);
  const double* pu = u.data();
  const double* pv = v.data();
  double* pd = dir.mutable_data();
  double *pa = az.mutable_data(), *pe = el.mutable_data(), *po = off.mutable_data();
  bool* ok = valid.mutable_data();
  const Eigen::Matrix3d camera_from_world = cam.world_from_camera().transpose();
  parallel(n, [&](py::ssize_t i) {
    const std::optional<camera::CameraRay> r =
        std::isfinite(pu[i]) && std::isfinite(pv[i]) ? cam.ray(Eigen::Vector2d(pu[i], pv[i])) : std::nullopt;
    ok[i] = r.has_value();
    if (!r) {
      pd[3 * i] = pd[3 * i + 1] = pd[3 * i + 2] = pa[i] = pe[i] = po[i] = kNaN;
      return;
    }
    for (int k = 0; k < 3; ++k) pd[3 * i + k] = r->d(k);
    pa[i] = sky::azimuth_of(r->d) * kDegPerRad;  // 0 at the zenith (sky/sun.h's rule)
    pe[i] = sky::elevation_of(r->d) * kDegPerRad;
    po[i] = std::acos(std::clamp((camera_from_world * r->d).z(), -1.0, 1.0)) * kDegPerRad;
  });
  py::dict out;
  out["direction"] = dir;
  out["azimuth_deg"] = az;
  out["elevation_deg"] = el;
  out["off_axis_deg"] = off;
  out["valid"] = valid;
  return out;
}

// World directions (N×3 ENU, any length > 0) → pixels; valid where the lens images the direction,
// on_sensor where the pixel also lies on the sensor (centres at integers: [−½, width − ½)).
py::dict project(const camera::Camera& cam, const Doubles& d) {
  if (d.ndim() != 2 || d.shape(1) != 3) throw std::invalid_argument("direction_to_pixel: expected an N×3 array of ENU vectors");
  const py::ssize_t n = d.shape(0);
  Doubles u(n), v(n);
  py::array_t<bool> valid(n), on_sensor(n);
  const double* pd = d.data();
  double *pu = u.mutable_data(), *pv = v.mutable_data();
  bool *ok = valid.mutable_data(), *on = on_sensor.mutable_data();
  const double w = cam.width(), h = cam.height();
  parallel(n, [&](py::ssize_t i) {
    const Eigen::Vector3d dir(pd[3 * i], pd[3 * i + 1], pd[3 * i + 2]);
    const bool usable = dir.allFinite() && dir.norm() > 0;
    const std::optional<Eigen::Vector2d> px = usable ? cam.project(dir.normalized()) : std::nullopt;
    ok[i] = px.has_value();
    pu[i] = px ? px->x() : kNaN;
    pv[i] = px ? px->y() : kNaN;
    on[i] = px && px->x() >= -0.5 && px->y() >= -0.5 && px->x() < w - 0.5 && px->y() < h - 0.5;
  });
  py::dict out;
  out["u"] = u;
  out["v"] = v;
  out["valid"] = valid;
  out["on_sensor"] = on_sensor;
  return out;
}

}  // namespace

void bind_camera(py::module_& m) {
  py::class_<camera::Camera, std::shared_ptr<camera::Camera>>(m, "Camera",
                                                               "A calibrated camera: lens, orientation, transport")
      .def_property_readonly("width", &camera::Camera::width)
      .def_property_readonly("height", &camera::Camera::height)
      .def_property_readonly("lens", [](const camera::Camera& c) { return c.lens().name(); })
      .def_property_readonly("intrinsics",
                             [](const camera::Camera& c) {
                               const camera::Intrinsics& k = c.lens().intrinsics();
                               py::dict d;
                               d["fx"] = k.fx;
                               d["fy"] = k.fy;
                               d["cx"] = k.cx;
                               d["cy"] = k.cy;
                               d["width"] = k.width;
                               d["height"] = k.height;
                               return d;
                             })
      .def_property_readonly("parameters", [](const camera::Camera& c) { return c.lens().parameters(); })
      .def_property_readonly("field_of_view_deg", [](const camera::Camera& c) { return 2 * c.lens().max_field_angle() * kDegPerRad; })
      .def_property_readonly("world_from_camera", [](const camera::Camera& c) { return to_array(c.world_from_camera()); })
      .def_property_readonly("transport",
                             [](const camera::Camera& c) {
                               return c.transport() == camera::Transport::meridional ? "meridional" : "projected";
                             })
      .def("_rays", &rays, py::arg("u"), py::arg("v"))
      .def("_project", &project, py::arg("directions"));
}

}  // namespace skypol::python
