// SkyPole SI eqs. 7 and 10 (invariance_sets.h).
#include "skypole/invariance_sets.h"

#include <cmath>

namespace skypol::skypole {

double radial_invariance_altitude(double azimuth, double latitude, double omega1, double omega2) {
  // tan θ = (cos α sin φ tan m − sin α)/(cos φ tan m); multiplied through by cos m so that
  // m = ±π/2 (tan m infinite) and m = 0 stay finite: θ = atan2(cos α sin φ sin m − sin α cos m,
  // cos φ sin m), with the sign of the denominator kept positive (θ is an altitude: |θ| ≤ π/2).
  const double m = 0.5 * (omega1 + omega2);
  double num = std::cos(azimuth) * std::sin(latitude) * std::sin(m) - std::sin(azimuth) * std::cos(m);
  double den = std::cos(latitude) * std::sin(m);
  if (den < 0) {
    num = -num;
    den = -den;
  }
  return std::atan2(num, den);
}

double plane_invariance_altitude(double azimuth, double latitude, double declination,
                                 double omega1, double omega2) {
  const double cd = std::cos(declination), sd = std::sin(declination);
  const double cl = std::cos(latitude), sl = std::sin(latitude);
  const double cs = std::cos(omega1) + std::cos(omega2), ss = std::sin(omega1) + std::sin(omega2);
  double num = std::sin(azimuth) * cd * ss + std::cos(azimuth) * (-2 * sd * cl + cd * sl * cs);
  double den = cd * cl * cs + 2 * sd * sl;
  if (den < 0) {
    num = -num;
    den = -den;
  }
  return std::atan2(num, den);
}

}  // namespace skypol::skypole
