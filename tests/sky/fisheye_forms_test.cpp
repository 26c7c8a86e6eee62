// Sun et al. 2019's Rayleigh pattern written in fisheye image coordinates (eqs. 12–13
// equidistant, 16–17 equisolid, 20–21 stereographic), against the vector-form model. (x, y) is
// the normalised image point (radius 1 at θ = 90°), X East, Y North, φ counted from X towards Y.
// Erratum: eq. 17 as printed ends in cos θs·(1 − √(x² + y²)); with the paper's own eq. 14,
// cos θ = 1 − (x² + y²), so the last factor is (1 − (x² + y²)) — that is what is tested.
// As for eq. 3, α_paper = −AoLP in skypol's meridian basis (see rayleigh_test.cpp).
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <numbers>

#include "sky/rayleigh.h"
#include "sky/units.h"

using namespace skypol::sky;
using skypol::kPi, skypol::kRadPerDeg;

namespace {

struct Forms {
  const char* name;
  std::function<double(double)> theta_of_r;                                   // the lens mapping, inverted
  std::function<double(double, double, double, double)> tan_alpha, cos_gamma;  // (x, y, θs, φs)
};

Forms equidistant() {
  return {"equidistant", [](double r) { return kPi / 2 * r; },
          [](double x, double y, double ts, double ps) {  // eq. 12
            const double r = std::hypot(x, y);
            return (std::cos(kPi / 2 * r) * (x * std::cos(ps) + y * std::sin(ps)) * std::sin(ts) -
                    std::sin(kPi / 2 * r) * std::cos(ts) * r) /
                   ((x * std::sin(ps) - y * std::cos(ps)) * std::sin(ts));
          },
          [](double x, double y, double ts, double ps) {  // eq. 13
            const double r = std::hypot(x, y);
            return std::sin(ts) * std::sin(kPi / 2 * r) * (std::cos(ps) * x / r + std::sin(ps) * y / r) +
                   std::cos(ts) * std::cos(kPi / 2 * r);
          }};
}

Forms equisolid() {
  return {"equisolid", [](double r) { return 2 * std::asin(r / std::sqrt(2.0)); },
          [](double x, double y, double ts, double ps) {  // eq. 16
            const double r2 = x * x + y * y;
            return ((1 - r2) * (x * std::cos(ps) + y * std::sin(ps)) * std::sin(ts) - r2 * std::sqrt(2 - r2) * std::cos(ts)) /
                   ((x * std::sin(ps) - y * std::cos(ps)) * std::sin(ts));
          },
          [](double x, double y, double ts, double ps) {  // eq. 17, corrected (see the top)
            const double r2 = x * x + y * y;
            return std::sin(ts) * std::sqrt(2 - r2) * (x * std::cos(ps) + y * std::sin(ps)) + std::cos(ts) * (1 - r2);
          }};
}

Forms stereographic() {
  return {"stereographic", [](double r) { return 2 * std::atan(r); },
          [](double x, double y, double ts, double ps) {  // eq. 20
            const double r2 = x * x + y * y;
            return ((1 - r2) * (x * std::cos(ps) + y * std::sin(ps)) * std::sin(ts) - 2 * r2 * std::cos(ts)) /
                   ((1 + r2) * (x * std::sin(ps) - y * std::cos(ps)) * std::sin(ts));
          },
          [](double x, double y, double ts, double ps) {  // eq. 21
            const double r2 = x * x + y * y;
            return std::sin(ts) * 2 / (1 + r2) * (x * std::cos(ps) + y * std::sin(ps)) + std::cos(ts) * (1 - r2) / (1 + r2);
          }};
}

Eigen::Vector3d spherical(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}
}  // namespace

TEST_CASE("Sun et al. eqs. 12-13, 16-17, 20-21: the pattern in fisheye image coordinates", "[rayleigh][paper]") {
  const double pmax = 0.85;
  const RayleighSky sky({pmax});
  for (const Forms& f : {equidistant(), equisolid(), stereographic()}) {
    int compared = 0;
    for (double ts : {10.0, 45.0, 80.0, 90.0}) {
      for (double ps : {0.0, 70.0, 200.0}) {
        Sun sun;
        sun.direction = spherical(ts * kRadPerDeg, ps * kRadPerDeg);
        for (double x = -0.95; x <= 0.95; x += 0.1) {
          for (double y = -0.95; y <= 0.95; y += 0.1) {
            const double r = std::hypot(x, y);
            if (r > 1.0 || r < 1e-6) continue;
            const Eigen::Vector3d d = spherical(f.theta_of_r(r), std::atan2(y, x));
            const Eigen::Vector3d up = Eigen::Vector3d::UnitZ() - d.z() * d;  // meridian basis
            const Stokes s = sky.stokes(d, up.normalized(), sun);
            const double cg = f.cos_gamma(x, y, ts * kRadPerDeg, ps * kRadPerDeg);
            INFO(f.name << " θs " << ts << " φs " << ps << " x " << x << " y " << y);
            CHECK(cg == Approx(d.dot(sun.direction)).margin(1e-12));
            CHECK(s.dolp() == Approx(pmax * (1 - cg * cg) / (1 + cg * cg)).margin(1e-12));
            const double den = (x * std::sin(ps * kRadPerDeg) - y * std::cos(ps * kRadPerDeg)) * std::sin(ts * kRadPerDeg);
            if (std::abs(den) > 1e-3 && s.dolp() > 1e-6) {
              const double alpha = std::atan(f.tan_alpha(x, y, ts * kRadPerDeg, ps * kRadPerDeg));
              CHECK(std::remainder(-s.aolp() - alpha, kPi) == Approx(0.0).margin(1e-9));
              ++compared;
            }
          }
        }
      }
    }
    CHECK(compared > 1500);
  }
}
