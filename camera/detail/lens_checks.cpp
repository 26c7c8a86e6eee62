#include "camera/detail/lens_checks.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "sky/units.h"

namespace skypol::camera::detail {

void lens_fail(const std::string& message) { throw std::invalid_argument(message); }

std::string lens_number(double x) {
  std::string s = std::to_string(x);
  s.erase(s.find_last_not_of('0') + 1);
  if (!s.empty() && s.back() == '.') s.pop_back();
  return s;
}

double positive(const std::optional<double>& v, const char* field) {
  if (!(std::isfinite(*v) && *v > 0)) lens_fail(std::string(field) + " must be > 0");
  return *v;
}

Intrinsics pinhole_intrinsics(const LensSpec& s) {
  if (s.width < 1) lens_fail("width must be > 0");
  if (s.height < 1) lens_fail("height must be > 0");
  Intrinsics k;
  k.width = s.width;
  k.height = s.height;
  const bool by_px = s.fx || s.fy, by_mm = s.focal_mm || s.pitch_um;
  if (by_px && by_mm) lens_fail("give either fx/fy or focal_mm/pitch_um, not both");
  if (by_px) {
    if (!s.fx) lens_fail("fx is required when fy is given");
    k.fx = positive(s.fx, "fx");
    k.fy = s.fy ? positive(s.fy, "fy") : k.fx;
  } else if (by_mm) {
    if (!s.focal_mm) lens_fail("focal_mm is required with pitch_um");
    if (!s.pitch_um) lens_fail("pitch_um is required with focal_mm");
    k.fx = k.fy = positive(s.focal_mm, "focal_mm") / (positive(s.pitch_um, "pitch_um") * 1e-3);
  } else {
    lens_fail("model " + s.model + " needs fx (pixels) or focal_mm and pitch_um");
  }
  k.cx = s.cx ? *s.cx : 0.5 * (s.width - 1);
  k.cy = s.cy ? *s.cy : 0.5 * (s.height - 1);
  if (!std::isfinite(k.cx) || k.cx < -0.5 || k.cx > s.width - 0.5)
    lens_fail("principal point off the sensor (cx = " + lens_number(k.cx) + ", width = " + std::to_string(s.width) + ")");
  if (!std::isfinite(k.cy) || k.cy < -0.5 || k.cy > s.height - 0.5)
    lens_fail("principal point off the sensor (cy = " + lens_number(k.cy) + ", height = " + std::to_string(s.height) + ")");
  return k;
}

double half_fov(const LensSpec& s, bool required) {
  if (!s.fov_deg) {
    if (required) lens_fail("fov_deg is required for model " + s.model);
    return 0;
  }
  if (!(std::isfinite(*s.fov_deg) && *s.fov_deg > 0 && *s.fov_deg <= 360))
    lens_fail("fov_deg must be in (0, 360], got " + lens_number(*s.fov_deg));
  return rad_from_deg(0.5 * *s.fov_deg);
}

void need_coefficients(const LensSpec& s, std::size_t n, const char* order) {
  if (s.coefficients.size() != n)
    lens_fail("coefficients: " + s.model + " needs " + std::to_string(n) + " (" + order + "), got " +
              std::to_string(s.coefficients.size()));
}

}  // namespace skypol::camera::detail
