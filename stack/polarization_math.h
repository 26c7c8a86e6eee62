// Derived polarization quantities, with the rules for undefined values that docs/conventions.md
// states: DoLP = 0 where S0 ≤ 0 (clamped to 1 against rounding); AoLP = 0 where S1 = S2 = 0;
// AoLP ∈ (−π/2, π/2].
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "camera/camera.h"
#include "sky/sky_model.h"

namespace skypol::stack {

// atan2 in float without a library call, so that per-pixel loops vectorize: |error| ≤ 3.2e-7 rad
// (1.3 ulp at π) over all inputs (a degree-8 polynomial in a² for atan(a), a ∈ [0, 1], fitted by weighted least
// squares; tests/stack/polarization_math_test checks it against std::atan2). atan2(0, 0) = 0.
inline float fast_atan2(float y, float x) {
  const float ax = std::fabs(x), ay = std::fabs(y);
  const float hi = std::max(ax, ay), lo = std::min(ax, ay);
  const float a = lo / std::max(hi, std::numeric_limits<float>::min());  // 0/min = 0 at the origin
  const float s = a * a;
  float p = 0.0024567079f;
  p = p * s - 0.014401294f;
  p = p * s + 0.039781127f;
  p = p * s - 0.072348498f;
  p = p * s + 0.10498943f;
  p = p * s - 0.14161229f;
  p = p * s + 0.19985907f;
  p = p * s - 0.33332598f;
  p = p * s + 0.99999988f;
  float r = p * a;
  r = ay > ax ? std::numbers::pi_v<float> / 2 - r : r;
  r = x < 0 ? std::numbers::pi_v<float> - r : r;
  return std::signbit(y) ? -r : r;
}

inline float dolp_of(float s0, float s1, float s2) {
  // Unconditional division (by a positive number) keeps the loop branch-free and vectorizable.
  const float ratio = std::sqrt(s1 * s1 + s2 * s2) / std::max(s0, std::numeric_limits<float>::min());
  return s0 > 0 ? std::min(1.0f, ratio) : 0.0f;
}

inline float aolp_of(float s1, float s2) {
  const float a = 0.5f * fast_atan2(s2, s1);
  return a <= -std::numbers::pi_v<float> / 2 ? std::numbers::pi_v<float> / 2 : a;  // half-open interval
}

// The Stokes vector of a sample re-expressed for projected transport (camera/camera.h): same S0
// and degree of polarization, angle mapped by Camera::sensor_angle.
sky::StokesF to_projected(const camera::Camera& camera, const sky::ViewRay& ray, const sky::StokesF& s);

}  // namespace skypol::stack
