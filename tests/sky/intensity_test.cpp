// Radiance models: the pattern is kept, the radiance replaced; Preetham's luminance against
// values worked out by hand (Python, from the coefficient table of Preetham et al. 1999, App. A.2).
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "sky/berry.h"
#include "sky/intensity.h"
#include "sky/rayleigh.h"
#include "sky_test_util.h"

using namespace skypol::sky;
using namespace skypol::testing;

namespace {
IntensityParams preetham(double t) {
  IntensityParams p;
  p.model = IntensityModel::preetham;
  p.turbidity = t;
  return p;
}
}  // namespace

TEST_CASE("Preetham luminance against hand-computed values", "[intensity]") {
  // T = 3, sun at the zenith, view 60° from the zenith: F(60°, 60°)/F(0°, 0°) = 0.35235116263.
  CHECK(sky_radiance(preetham(3), enu_direction(0.3, 30 * kRadPerDeg), sun_at(0, 90)) ==
        Approx(0.3523511626346728).epsilon(1e-9));
  // Sun at 30° elevation in the south, view east at 45°: T = 3 → 1.08384188664, T = 8 → 0.89794770792.
  const Eigen::Vector3d view = enu_direction(90 * kRadPerDeg, 45 * kRadPerDeg);
  CHECK(sky_radiance(preetham(3), view, sun_at(180, 30)) == Approx(1.0838418866434085).epsilon(1e-9));
  CHECK(sky_radiance(preetham(8), view, sun_at(180, 30)) == Approx(0.8979477079161806).epsilon(1e-9));
}

TEST_CASE("Preetham: 1 at the zenith, symmetric about the solar vertical, horizon value below it", "[intensity]") {
  for (double t : {2.0, 3.0, 6.0, 10.0}) {
    for (double el : {-5.0, 5.0, 30.0, 60.0, 89.0}) {
      const Sun sun = sun_at(130, el);
      CHECK(sky_radiance(preetham(t), Eigen::Vector3d::UnitZ(), sun) == Approx(1.0).epsilon(1e-14));
      for (double off = 10; off < 180; off += 25) {
        for (double vel = 0; vel < 90; vel += 20) {
          const double a = sky_radiance(preetham(t), enu_direction((130 + off) * kRadPerDeg, vel * kRadPerDeg), sun);
          const double b = sky_radiance(preetham(t), enu_direction((130 - off) * kRadPerDeg, vel * kRadPerDeg), sun);
          CHECK(a == Approx(b).epsilon(1e-12));
          CHECK(a > 0);
        }
      }
      // Below the horizon: the horizon's value in the same azimuth, finite.
      const double horizon = sky_radiance(preetham(t), enu_direction(40 * kRadPerDeg, 0), sun);
      const double below = sky_radiance(preetham(t), enu_direction(40 * kRadPerDeg, -30 * kRadPerDeg), sun);
      CHECK(std::isfinite(below));
      CHECK(below > 0);
      CHECK(std::isfinite(horizon));
    }
  }
}

TEST_CASE("a different radiance keeps DoLP and AoLP of the pattern", "[intensity]") {
  std::mt19937_64 rng(9);
  std::normal_distribution<double> n;
  const Sun sun = sun_at(250, 20);
  for (IntensityModel m : {IntensityModel::uniform, IntensityModel::rayleigh, IntensityModel::preetham}) {
    IntensityParams p = preetham(4);
    p.model = m;
    const IntensitySky sky(std::make_unique<BerrySky>(BerryParams{0.75, 18.0}), p);
    const BerrySky bare({0.75, 18.0});
    CHECK(sky.name() == "berry");
    for (int i = 0; i < 500; ++i) {
      const Eigen::Vector3d d = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
      const Stokes a = sky.stokes(d, perpendicular(d), sun), b = bare.stokes(d, perpendicular(d), sun);
      CHECK(a.s0 == Approx(sky_radiance(p, d, sun)).epsilon(1e-12));
      CHECK(a.dolp() == Approx(b.dolp()).margin(1e-12));
      if (b.dolp() > 1e-6) CHECK(std::remainder(a.aolp() - b.aolp(), kPi) == Approx(0.0).margin(1e-12));
      if (m == IntensityModel::uniform) CHECK(a.s0 == 1.0);
      if (m == IntensityModel::rayleigh) {
        CHECK(a.s1 == Approx(b.s1).margin(1e-12));  // the pattern's own radiance: nothing changes
        CHECK(a.s2 == Approx(b.s2).margin(1e-12));
      }
    }
  }
}

TEST_CASE("intensity batch path equals the scalar path", "[intensity][batch]") {
  std::mt19937_64 rng(13);
  std::normal_distribution<double> n;
  for (IntensityModel m : {IntensityModel::uniform, IntensityModel::rayleigh, IntensityModel::preetham}) {
    IntensityParams p = preetham(2.5);
    p.model = m;
    const IntensitySky sky(std::make_unique<RayleighSky>(RayleighParams{0.7}), p);
    const Sun sun = sun_at(33, 12);
    std::vector<ViewRay> rays;
    for (int i = 0; i < 700; ++i) {
      const Eigen::Vector3d d = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
      rays.push_back({d.cast<float>(), perpendicular(d).cast<float>()});
    }
    // The hard directions too: the sun, the anti-sun, the zenith, the horizon, below it.
    for (const Eigen::Vector3d& d : {sun.direction, Eigen::Vector3d(-sun.direction), Eigen::Vector3d(Eigen::Vector3d::UnitZ()),
                                     enu_direction(1.0, 0.0), enu_direction(2.0, -0.3), Eigen::Vector3d(0, 0, -1)}) {
      rays.push_back({d.cast<float>(), perpendicular(d).cast<float>()});
    }
    // The batch path uses float polynomial acos/exp (vectorizable), the scalar path libm.
    for (const auto& [batch, scalar] : batch_and_scalar(sky, rays, sun)) {
      CHECK(std::isfinite(batch.s0));
      CHECK(batch.s0 == Approx(scalar.s0).epsilon(2e-5));
      CHECK(batch.s1 == Approx(scalar.s1).margin(2e-5 * scalar.s0));
      CHECK(batch.s2 == Approx(scalar.s2).margin(2e-5 * scalar.s0));
    }
  }
}

TEST_CASE("bad intensity parameters are refused with the field named", "[intensity][bad-input]") {
  auto inner = [] { return std::make_unique<RayleighSky>(); };
  CHECK_THROWS_WITH(IntensitySky(inner(), preetham(-1)), Catch::Contains("turbidity"));
  CHECK_THROWS_WITH(IntensitySky(inner(), preetham(1.5)), Catch::Contains("[2, 10]"));
  CHECK_THROWS_AS(IntensitySky(inner(), preetham(11)), std::invalid_argument);
  CHECK_THROWS_AS(IntensitySky(inner(), preetham(std::nan(""))), std::invalid_argument);
  CHECK_THROWS_WITH(intensity_model_from_name("perez"), Catch::Contains("uniform, rayleigh or preetham"));
  CHECK(intensity_model_from_name("preetham") == IntensityModel::preetham);
  CHECK(to_string(IntensityModel::uniform) == "uniform");
}
