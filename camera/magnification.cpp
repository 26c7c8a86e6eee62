// Central-difference magnifications of any lens (magnification.h).
#include "camera/magnification.h"

#include <algorithm>
#include <cmath>

namespace skypol::camera {
namespace {
Eigen::Vector3d dir(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}
}  // namespace

std::optional<Magnification> magnification(const Lens& lens, double theta, double phi) {
  const double tmax = lens.max_field_angle();
  if (!std::isfinite(theta) || !std::isfinite(phi) || theta < 0 || theta > tmax) return std::nullopt;
  constexpr double h = 1e-5;  // rad: truncation ~h², rounding ~1e-16·r/h, both ≪ 1e-6 relative
  // Radial: central where possible, one-sided at the edges of [0, θmax].
  const double t0 = std::max(0.0, theta - h), t1 = std::min(tmax, theta + h);
  const auto a = lens.project(dir(t0, phi)), b = lens.project(dir(t1, phi));
  if (!a || !b) return std::nullopt;
  Magnification m;
  m.radial_px = (*b - *a).norm() / (t1 - t0);
  if (theta < 1e-6) {  // on the axis: the tangential limit is the radial one
    m.tangential_px = m.radial_px;
    return m;
  }
  const auto c = lens.project(dir(theta, phi - h)), d = lens.project(dir(theta, phi + h));
  if (!c || !d) return std::nullopt;
  m.tangential_px = (*d - *c).norm() / (2 * h * std::sin(theta));
  return m;
}

}  // namespace skypol::camera
