// COLMAP cameras.txt line → LensSpec (colmap_import.h).
#include "camera/colmap_import.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "camera/calibration_import.h"
#include "camera/kannala_brandt.h"
#include "sky/units.h"

namespace skypol::camera {

LensSpec lens_spec_from_colmap(std::string_view line) {
  std::istringstream in{std::string(line)};
  std::string id, model;
  int width = 0, height = 0;
  if (!(in >> id >> model >> width >> height))
    throw std::invalid_argument("COLMAP camera line: expected \"CAMERA_ID MODEL WIDTH HEIGHT PARAMS...\"");
  std::vector<double> p;
  std::string tok;
  while (in >> tok) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(tok, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != tok.size() || !std::isfinite(v))
      throw std::invalid_argument("COLMAP camera line: parameter \"" + tok + "\" is not a number");
    p.push_back(v);
  }
  auto need = [&](std::size_t n, const char* order) {
    if (p.size() != n)
      throw std::invalid_argument("COLMAP " + model + " needs " + std::to_string(n) + " parameters (" +
                                  order + "), got " + std::to_string(p.size()));
  };
  LensSpec s;
  s.width = width;
  s.height = height;
  std::array<double, 4> kb{};  // the Kannala-Brandt coefficients of the three radial fisheye models
  if (model == "OPENCV_FISHEYE") {
    need(8, "fx, fy, cx, cy, k1, k2, k3, k4");
    s.model = "kannala_brandt";
    s.fx = p[0];
    s.fy = p[1];
    s.cx = p[2] - 0.5;
    s.cy = p[3] - 0.5;
    kb = {p[4], p[5], p[6], p[7]};
  } else if (model == "SIMPLE_RADIAL_FISHEYE" || model == "RADIAL_FISHEYE") {
    // θd = θ·(1 + k·θ²) and θ·(1 + k1·θ² + k2·θ⁴): Kannala-Brandt with the higher terms zero.
    const bool simple = model == "SIMPLE_RADIAL_FISHEYE";
    need(simple ? 4 : 5, simple ? "f, cx, cy, k" : "f, cx, cy, k1, k2");
    s.model = "kannala_brandt";
    s.fx = s.fy = p[0];
    s.cx = p[1] - 0.5;
    s.cy = p[2] - 0.5;
    kb = {p[3], simple ? 0.0 : p[4], 0.0, 0.0};
  } else if (model == "THIN_PRISM_FISHEYE") {
    need(12, "fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, sx1, sy1");
    s.model = "thin_prism_fisheye";
    s.fx = p[0];
    s.fy = p[1];
    s.cx = p[2] - 0.5;
    s.cy = p[3] - 0.5;
    s.coefficients.assign(p.begin() + 4, p.end());
  } else if (model == "PINHOLE" || model == "SIMPLE_PINHOLE") {
    const bool simple = model == "SIMPLE_PINHOLE";
    need(simple ? 3 : 4, simple ? "f, cx, cy" : "fx, fy, cx, cy");
    s.model = "perspective";
    s.fx = p[0];
    s.fy = simple ? p[0] : p[1];
    s.cx = p[simple ? 1 : 2] - 0.5;
    s.cy = p[simple ? 2 : 3] - 0.5;
  } else {
    throw std::invalid_argument("COLMAP camera model \"" + model +
                                "\" is not supported (supported: SIMPLE_RADIAL_FISHEYE, RADIAL_FISHEYE, OPENCV_FISHEYE, "
                                "THIN_PRISM_FISHEYE, PINHOLE, SIMPLE_PINHOLE)");
  }
  if (!(*s.fx > 0) || !(*s.fy > 0)) throw std::invalid_argument("COLMAP camera line: focal lengths must be > 0");
  if (width < 1 || height < 1) throw std::invalid_argument("COLMAP camera line: width and height must be > 0");

  if (s.model == "thin_prism_fisheye") {
    fit_fov_to_sensor(s);
    return s;
  }
  if (s.model == "kannala_brandt") s.coefficients = {kb[0], kb[1], kb[2], kb[3]};
  // Field of view: the angle of the farthest sensor corner (pixel-edge corners).
  double r_corner = 0;
  for (double u : {-0.5, width - 0.5})
    for (double v : {-0.5, height - 0.5})
      r_corner = std::max(r_corner, std::hypot((u - *s.cx) / *s.fx, (v - *s.cy) / *s.fy));
  double theta = 0;
  if (s.model == "perspective") {
    theta = std::atan(r_corner);
  } else {
    Intrinsics k;
    k.fx = *s.fx;
    k.fy = *s.fy;
    k.cx = *s.cx;
    k.cy = *s.cy;
    const KannalaBrandtLens lens(k, kb, std::numbers::pi, KannalaBrandtLens::OnTurnover::clamp_fov);
    const auto d = lens.ray({k.cx + k.fx * r_corner, k.cy});
    theta = d ? std::atan2(std::hypot(d->x(), d->y()), d->z()) : lens.max_field_angle();
    s.clamp_fov_to_monotone = true;
  }
  s.fov_deg = deg_from_rad(2 * theta);
  return s;
}

}  // namespace skypol::camera
