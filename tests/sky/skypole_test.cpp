// SkyPole's invariance sets (PNAS 2023, SI eqs. 6 and 10) against the Rayleigh sky: the points
// whose DoLP is the same at two instants, in the paper's closed forms, and the north celestial
// pole's DoLP over a real day (ERFA sun).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

#include "sky/rayleigh.h"
#include "sky/sun.h"
#include "sky_test_util.h"

using namespace skypol::sky;
using namespace skypol::testing;

namespace {
// SI eq. 1: the sun in ENU from latitude, declination and hour angle (radians).
Sun sun_from(double phi, double dec, double ha) {
  Sun s;
  s.direction = {-std::cos(dec) * std::sin(ha), std::sin(dec) * std::cos(phi) - std::cos(dec) * std::sin(phi) * std::cos(ha),
                 std::cos(dec) * std::cos(phi) * std::cos(ha) + std::sin(dec) * std::sin(phi)};
  s.azimuth = azimuth_of(s.direction);
  s.elevation = elevation_of(s.direction);
  return s;
}

// P(α, θ) with α the azimuth (from North towards East) and θ the altitude, as in the SI.
Eigen::Vector3d point(double alpha, double theta) {
  return {std::cos(theta) * std::sin(alpha), std::cos(theta) * std::cos(alpha), std::sin(theta)};
}

double dolp(const RayleighSky& sky, const Eigen::Vector3d& p, const Sun& sun) {
  return sky.stokes(p, perpendicular(p), sun).dolp();
}
}  // namespace

TEST_CASE("SkyPole SI eq. 6: the radial invariance set has the same DoLP at both instants", "[skypole][paper]") {
  const RayleighSky sky({0.8});
  for (double lat : {43.287, -33.87, 5.0}) {
    for (double dec : {-20.0, 0.0, 15.0}) {
      const double phi = lat * kRadPerDeg, d = dec * kRadPerDeg;
      for (auto [h1, h2] : {std::pair{-40.0, -10.0}, std::pair{-5.0, 30.0}, std::pair{20.0, 65.0}}) {
        const double w1 = h1 * kRadPerDeg, w2 = h2 * kRadPerDeg, t = std::tan((w1 + w2) / 2);
        const Sun s1 = sun_from(phi, d, w1), s2 = sun_from(phi, d, w2);
        for (double alpha = -180; alpha < 180; alpha += 15) {
          const double a = alpha * kRadPerDeg;
          const double theta = std::atan((std::cos(a) * std::sin(phi) * t - std::sin(a)) / (std::cos(phi) * t));
          const Eigen::Vector3d p = point(a, theta);
          INFO("lat " << lat << " dec " << dec << " ha " << h1 << "," << h2 << " alpha " << alpha);
          CHECK(dolp(sky, p, s1) == Approx(dolp(sky, p, s2)).margin(1e-12));
        }
        // …and the NCP lies on every such set: at α = 0 it gives θ = φ.
        CHECK(std::atan((std::sin(phi) * t) / (std::cos(phi) * t)) == Approx(phi).margin(1e-15));
      }
    }
  }
}

TEST_CASE("SkyPole SI eq. 10: the plane invariance set has the same DoLP at both instants", "[skypole][paper]") {
  const RayleighSky sky({1.0});
  for (double lat : {43.287, -33.87, 5.0}) {
    for (double dec : {-20.0, 0.0, 15.0}) {
      const double phi = lat * kRadPerDeg, d = dec * kRadPerDeg;
      for (auto [h1, h2] : {std::pair{-40.0, -10.0}, std::pair{-5.0, 30.0}, std::pair{20.0, 65.0}}) {
        const double w1 = h1 * kRadPerDeg, w2 = h2 * kRadPerDeg;
        const Sun s1 = sun_from(phi, d, w1), s2 = sun_from(phi, d, w2);
        const double den = std::cos(d) * std::cos(phi) * (std::cos(w1) + std::cos(w2)) + 2 * std::sin(d) * std::sin(phi);
        for (double alpha = -180; alpha < 180; alpha += 15) {
          const double a = alpha * kRadPerDeg;
          const double num = std::sin(a) * std::cos(d) * (std::sin(w1) + std::sin(w2)) +
                             std::cos(a) * (-2 * std::sin(d) * std::cos(phi) + std::cos(d) * std::sin(phi) * (std::cos(w1) + std::cos(w2)));
          const Eigen::Vector3d p = point(a, std::atan(num / den));
          INFO("lat " << lat << " dec " << dec << " ha " << h1 << "," << h2 << " alpha " << alpha);
          CHECK(p.dot(s1.direction) == Approx(-p.dot(s2.direction)).margin(1e-12));
          CHECK(dolp(sky, p, s1) == Approx(dolp(sky, p, s2)).margin(1e-12));
        }
      }
    }
  }
}

TEST_CASE("with the ERFA sun, DoLP at the celestial pole follows the declination through a day", "[skypole]") {
  const RayleighSky sky;
  for (const Site& site : {Site{43.286987, 5.4032786, 50}, Site{-33.8688, 151.2093, 0}, Site{0.0, 10.0, 0}}) {
    const Eigen::Vector3d ncp = north_celestial_pole(site.latitude_deg);
    const Instant t0 = parse_iso8601("2024-06-21T00:00:00Z");
    double lo = 1, hi = 0;
    for (int h = 0; h < 24; ++h) {
      const Sun sun = sun_position(site, Instant{t0.unix_seconds + 3600.0 * h});
      const double sd = std::sin(sun.declination);
      const double p = dolp(sky, ncp, sun);
      CHECK(p == Approx((1 - sd * sd) / (1 + sd * sd)).margin(1e-9));
      lo = std::min(lo, p);
      hi = std::max(hi, p);
    }
    // At the solstice the declination barely moves: the pole's DoLP is constant to 1e-4.
    CHECK(hi - lo < 1e-4);
    CHECK(lo == Approx(0.72676).margin(0.0002));  // δ = 23.44°: sin²δ = 0.15824, (1 − 0.15824)/(1 + 0.15824)
  }
}
