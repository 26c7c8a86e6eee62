#include "camera/detail/radial_util.h"

#include <cstdio>
#include <numbers>
#include <stdexcept>

#include "sky/units.h"

namespace skypol::camera::detail {

std::optional<Polar> polar_of(const Eigen::Vector3d& d) {
  if (!d.allFinite()) return std::nullopt;
  const double rho = std::hypot(d.x(), d.y());
  if (rho == 0 && !(d.z() > 0)) return std::nullopt;  // zero vector or straight back
  if (rho == 0) return Polar{0, 1, 0};
  return Polar{std::atan2(rho, d.z()), d.x() / rho, d.y() / rho};
}

Eigen::Vector3d direction(double theta, double mx, double my, double r) {
  if (!(r > 0)) return {0, 0, 1};
  // ray_row's arithmetic (ray_kernels.h: its sin and cos, one division), so they agree bit for bit.
  double st, ct;
  sin_cos(theta, st, ct);
  const double k = st / r;
  return {k * mx, k * my, ct};
}

void check_intrinsics(const Intrinsics& k) {
  if (!(std::isfinite(k.fx) && k.fx > 0)) throw std::invalid_argument("fx must be > 0");
  if (!(std::isfinite(k.fy) && k.fy > 0)) throw std::invalid_argument("fy must be > 0");
  if (!std::isfinite(k.cx)) throw std::invalid_argument("cx must be finite");
  if (!std::isfinite(k.cy)) throw std::invalid_argument("cy must be finite");
  if (k.width < 0) throw std::invalid_argument("width must be >= 0");
  if (k.height < 0) throw std::invalid_argument("height must be >= 0");
}

Intrinsics rescale_intrinsics(const Intrinsics& k, double s) {
  if (!(std::isfinite(s) && s > 0)) throw std::invalid_argument("pixel scale must be > 0");
  Intrinsics o;
  o.fx = k.fx * s;
  o.fy = k.fy * s;
  o.cx = s * (k.cx + 0.5) - 0.5;
  o.cy = s * (k.cy + 0.5) - 0.5;
  o.width = static_cast<int>(std::floor(s * k.width + 1e-9));
  o.height = static_cast<int>(std::floor(s * k.height + 1e-9));
  return o;
}

std::string format_deg(double rad) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f°", deg_from_rad(rad));
  return buf;
}

}  // namespace skypol::camera::detail
