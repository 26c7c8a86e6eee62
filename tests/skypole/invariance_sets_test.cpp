// skypole/invariance_sets.h: SkyPole SI eqs. 7 and 10 as altitude(azimuth) functions, against
// their defining equations S1·P = ±S2·P with the sun of SI eq. 1, including the hour angles where
// the printed tan-form divides by zero.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <utility>

#include <Eigen/Core>

#include "sky/units.h"
#include "skypole/invariance_sets.h"

using skypol::kRadPerDeg;

namespace {

// SI eq. 1: the sun in ENU from latitude, declination and hour angle (radians).
Eigen::Vector3d sun(double phi, double dec, double ha) {
  return {-std::cos(dec) * std::sin(ha),
          std::sin(dec) * std::cos(phi) - std::cos(dec) * std::sin(phi) * std::cos(ha),
          std::cos(dec) * std::cos(phi) * std::cos(ha) + std::sin(dec) * std::sin(phi)};
}
Eigen::Vector3d point(double az, double alt) {
  return {std::cos(alt) * std::sin(az), std::cos(alt) * std::cos(az), std::sin(alt)};
}
}  // namespace

TEST_CASE("Set 1 and Set 2 points have equal |cos γ| at both times", "[skypole][invariance_sets]") {
  int checked = 0;
  for (double lat : {43.287, -33.87, 5.0, 80.0}) {
    for (double dec : {-20.0, 0.0, 15.0}) {
      // (−45, 45): m = 0, the printed form divides by zero; (60, 120): m = 90°, tan m is infinite.
      for (auto [h1, h2] : {std::pair{-40.0, -10.0}, std::pair{-45.0, 45.0}, std::pair{60.0, 120.0},
                            std::pair{-170.0, -100.0}}) {
        const double phi = lat * kRadPerDeg, d = dec * kRadPerDeg, w1 = h1 * kRadPerDeg, w2 = h2 * kRadPerDeg;
        const Eigen::Vector3d s1 = sun(phi, d, w1), s2 = sun(phi, d, w2);
        for (double az = -180; az < 180; az += 7.5) {
          const double a1 = skypol::skypole::radial_invariance_altitude(az * kRadPerDeg, phi, w1, w2);
          const double a2 = skypol::skypole::plane_invariance_altitude(az * kRadPerDeg, phi, d, w1, w2);
          INFO("lat " << lat << " dec " << dec << " ha " << h1 << "," << h2 << " az " << az);
          REQUIRE(std::isfinite(a1));
          REQUIRE(std::isfinite(a2));
          CHECK(std::abs(a1) <= std::numbers::pi / 2);
          // Where the circle passes through the zenith (|θ| = 90°) the azimuth is moot.
          if (std::abs(std::abs(a1) - std::numbers::pi / 2) > 1e-9) {
            const Eigen::Vector3d p = point(az * kRadPerDeg, a1);
            CHECK(p.dot(s1) == Approx(p.dot(s2)).margin(1e-12));
            ++checked;
          }
          const Eigen::Vector3d q = point(az * kRadPerDeg, a2);
          CHECK(q.dot(s1) == Approx(-q.dot(s2)).margin(1e-12));
        }
        // Every radial circle passes through the celestial pole (α = 0, θ = φ) unless it is the
        // meridian itself (m = 0), which contains the pole too.
        if (std::abs(h1 + h2) > 1e-9)
          CHECK(skypol::skypole::radial_invariance_altitude(0.0, phi, w1, w2) == Approx(phi).margin(1e-12));
      }
    }
  }
  CHECK(checked > 1000);
}
