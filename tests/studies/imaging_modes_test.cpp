// studies/imaging_modes.h: the paper's AoP per pixel against Sun et al.'s own closed form in
// equidistant image coordinates (eq. 12), and the similarity ε's identities.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "sky/units.h"
#include "studies/imaging_modes.h"
#include "sky/rayleigh.h"

using namespace skypol;

namespace {
}  // namespace

TEST_CASE("equidistant AoP per pixel is Sun et al. eq. 12", "[render][imaging_modes][paper]") {
  const sky::RayleighSky sky;
  const int size = 61;
  for (double az_deg : {0.0, 90.0, 215.0}) {
    for (double el_deg : {0.0, 30.0, 70.0}) {
      const sky::Sun sun = sky::sun_from_horizontal(az_deg * kRadPerDeg, el_deg * kRadPerDeg, 31.85);
      const studies::ModeImage m = studies::render_mode(camera::Mapping::equidistant, size, 180, sky, sun);
      // The paper's frame: X East, Y North, φ from X towards Y, horizon at radius 1.
      const double ts = (90 - el_deg) * kRadPerDeg, ps = (90 - az_deg) * kRadPerDeg;
      const double c = 0.5 * (size - 1), radius = 0.5 * size;
      int compared = 0;
      for (int v = 0; v < size; v += 3)
        for (int u = 0; u < size; u += 3) {
          const std::size_t i = static_cast<std::size_t>(v * size + u);
          if (!m.inside[i]) continue;
          // Heading 0: image right = West, image down = South.
          const double x = -(u - c) / radius, y = -(v - c) / radius;
          const double r = std::hypot(x, y);
          const double den = (x * std::sin(ps) - y * std::cos(ps)) * std::sin(ts);
          if (r < 1e-9 || std::abs(den) < 1e-3 || m.dop[i] < 1e-4f) continue;
          const double num = std::cos(kPi / 2 * r) * (x * std::cos(ps) + y * std::sin(ps)) * std::sin(ts) -
                             std::sin(kPi / 2 * r) * std::cos(ts) * r;
          const double alpha = std::atan(num / den) / kRadPerDeg;
          INFO("sun az " << az_deg << " el " << el_deg << " pixel " << u << "," << v);
          CHECK(std::remainder(static_cast<double>(m.aop_deg[i]) - alpha, 180.0) == Approx(0).margin(2e-3));
          CHECK(static_cast<double>(m.theta_deg[i]) == Approx(90 * r).margin(1e-4));
          ++compared;
        }
      CHECK(compared > 100);
    }
  }
}

TEST_CASE("similarity: a mode against itself is 100 %, the anti-sun half holds half the pixels",
          "[render][imaging_modes]") {
  const sky::RayleighSky sky;
  const sky::Sun sun = sky::sun_from_horizontal(1.0, 0.5, 40);
  const auto ei = studies::render_mode(camera::Mapping::equidistant, 101, 140, sky, sun);
  const auto vp = studies::render_mode(camera::Mapping::orthographic, 101, 140, sky, sun);
  const studies::Similarity self = studies::similarity(ei, ei, sun, {70, false});
  CHECK(self.epsilon == 1.0);
  CHECK(self.pixels > 7000);  // π·50.5² ≈ 8012 pixels in the circle
  const studies::Similarity half = studies::similarity(ei, ei, sun, {70, true});
  CHECK(static_cast<double>(half.pixels) == Approx(0.5 * static_cast<double>(self.pixels)).epsilon(0.03));
  // Different mappings see different zenith angles at the same pixel: ε < 1, and the difference
  // image is antisymmetric.
  const studies::Similarity d = studies::similarity(ei, vp, sun, {70, false});
  CHECK(d.epsilon < 0.95);
  CHECK(d.pixels == self.pixels);
  const auto ab = studies::aop_difference_deg(ei, vp), ba = studies::aop_difference_deg(vp, ei);
  for (std::size_t i = 0; i < ab.size(); ++i)
    if (std::abs(ab[i]) < 89.0f) CHECK(ab[i] == Approx(-ba[i]).margin(1e-4));
  CHECK_THROWS(studies::similarity(ei, studies::render_mode(camera::Mapping::equidistant, 51, 140, sky, sun),
                                  sun, {}));
}
