// Stokes helpers: the two derived quantities and the single frame rotation (see stokes.h).
#include "sky/stokes.h"

#include <cmath>
#include <numbers>

namespace skypol::sky {

double Stokes::dolp() const {
  if (!(s0 > 0)) return 0.0;  // no light carries no polarization (also catches NaN)
  return std::hypot(s1, s2) / s0;
}

double Stokes::aolp() const {
  if (s1 == 0.0 && s2 == 0.0) return 0.0;  // undefined: documented rule, 0
  double a = 0.5 * std::atan2(s2, s1);     // atan2 ∈ [−π, π] → a ∈ [−π/2, π/2]
  // atan2(−0, negative) = −π gives −π/2, which belongs to π/2 in the half-open interval.
  if (a <= -std::numbers::pi / 2) a += std::numbers::pi;
  return a;
}

Stokes rotate_reference(const Stokes& s, double angle) {
  const double c = std::cos(2.0 * angle);
  const double n = std::sin(2.0 * angle);
  return {s.s0, s.s1 * c + s.s2 * n, -s.s1 * n + s.s2 * c, s.s3};
}

Stokes from_polarization(double s0, double dolp, double aolp) {
  const double p = s0 * dolp;
  return {s0, p * std::cos(2.0 * aolp), p * std::sin(2.0 * aolp), 0.0};
}

}  // namespace skypol::sky
