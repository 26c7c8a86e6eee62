#include "camera/detail/ray_table.h"

#include <numbers>

#include "camera/detail/radial_util.h"

namespace skypol::camera::detail {

const SinCosTable& sincos_table() {
  static const SinCosTable t = [] {
    SinCosTable s{};
    for (int i = 0; i <= SinCosTable::kNodes; ++i) {
      s.theta[i] = i * (std::numbers::pi / SinCosTable::kNodes);
      s.s[i] = std::sin(s.theta[i]);
      s.c[i] = std::cos(s.theta[i]);
    }
    return s;
  }();
  return t;
}

std::unique_ptr<const RadialTable> odd_polynomial_table(const std::array<double, 4>& k, double theta_max) {
  const auto fwd = [k](double t, double& r, double& dr) {
    const double t2 = t * t;
    r = t * (1 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3]))));
    dr = 1 + t2 * (3 * k[0] + t2 * (5 * k[1] + t2 * (7 * k[2] + t2 * 9 * k[3])));
  };
  const auto value = [&](double t) {
    double r, dr;
    fwd(t, r, dr);
    return r;
  };
  const auto slope = [&](double t) {
    double r, dr;
    fwd(t, r, dr);
    return dr;
  };
  if (first_turning_point(slope, theta_max)) return nullptr;
  return std::make_unique<const RadialTable>(theta_max, value(theta_max), fwd, [&](double r) {
    return solve_increasing(value, slope, r, 0.0, theta_max, r).value_or(theta_max);
  });
}

}  // namespace skypol::camera::detail
