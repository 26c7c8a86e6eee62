// The float polarization helpers against the standard library and the documented rules.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <random>

#include "stack/polarization_math.h"

using skypol::stack::aolp_of;
using skypol::stack::dolp_of;
using skypol::stack::fast_atan2;

TEST_CASE("fast_atan2 agrees with std::atan2 to float precision everywhere", "[polarization_math]") {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> angle(-3.2f, 3.2f), mag(-30.0f, 30.0f);
  double worst = 0;
  for (int i = 0; i < 2000000; ++i) {
    const float r = std::exp2(mag(rng) / 3), t = angle(rng);
    const float x = r * std::cos(t), y = r * std::sin(t);
    worst = std::max(worst, std::abs(double{fast_atan2(y, x)} - std::atan2(double{y}, double{x})));
  }
  CHECK(worst < 3.2e-7);  // 1.3 ulp of float at π: the polynomial (1.1e-7) plus rounding near π
  // The axes and the signed zeros, exactly as std::atan2 has them.
  CHECK(fast_atan2(0.0f, 1.0f) == 0.0f);
  CHECK(fast_atan2(1.0f, 0.0f) == Approx(std::numbers::pi / 2).epsilon(1e-7));
  CHECK(fast_atan2(0.0f, -1.0f) == Approx(std::numbers::pi).epsilon(1e-7));
  CHECK(fast_atan2(-0.0f, -1.0f) == Approx(-std::numbers::pi).epsilon(1e-7));
  CHECK(fast_atan2(-1.0f, 0.0f) == Approx(-std::numbers::pi / 2).epsilon(1e-7));
  CHECK(fast_atan2(0.0f, 0.0f) == 0.0f);
}

TEST_CASE("undefined polarization follows the documented rules", "[polarization_math]") {
  CHECK(dolp_of(0.0f, 0.0f, 0.0f) == 0.0f);    // no light, no polarization
  CHECK(dolp_of(0.0f, 0.1f, 0.0f) == 0.0f);
  CHECK(dolp_of(1.0f, 1.0f, 1e-7f) == 1.0f);   // clamped against rounding
  CHECK(dolp_of(2.0f, 0.6f, 0.8f) == Approx(0.5f));
  CHECK(aolp_of(0.0f, 0.0f) == 0.0f);
  // AoLP ∈ (−π/2, π/2]: polarization along e90 (S1 < 0, S2 = ±0) is +π/2 from either side.
  CHECK(aolp_of(-1.0f, 0.0f) == Approx(std::numbers::pi / 2));
  CHECK(aolp_of(-1.0f, -0.0f) == Approx(std::numbers::pi / 2));
  CHECK(aolp_of(0.0f, 1.0f) == Approx(std::numbers::pi / 4));
  CHECK(aolp_of(0.0f, -1.0f) == Approx(-std::numbers::pi / 4));
}
