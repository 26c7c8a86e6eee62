// Procedural clouds: deterministic from the seed, coverage as asked, and the optics promised in
// clouds.h (brighter, less polarized, same AoLP under thin cloud).
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "sky/clouds.h"
#include "sky/rayleigh.h"
#include "sky_test_util.h"

using namespace skypol::sky;
using namespace skypol::testing;

namespace {
std::vector<Eigen::Vector3d> random_directions(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g;
  std::vector<Eigen::Vector3d> v;
  for (int i = 0; i < n; ++i) v.push_back(Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized());
  return v;
}

CloudySky clouds(double coverage, std::uint64_t seed, double scale_deg = 15) {
  CloudParams p;
  p.coverage = coverage;
  p.seed = seed;
  p.scale_deg = scale_deg;
  return CloudySky(std::make_unique<RayleighSky>(RayleighParams{0.8}), p);
}
}  // namespace

TEST_CASE("the same seed gives the same clouds, another seed other clouds", "[clouds]") {
  const CloudySky a = clouds(0.4, 1234), b = clouds(0.4, 1234), c = clouds(0.4, 1235);
  int differ = 0;
  for (const Eigen::Vector3d& d : random_directions(2000, 1)) {
    CHECK(a.opacity(d) == b.opacity(d));
    if (std::abs(a.opacity(d) - c.opacity(d)) > 0.5) ++differ;
  }
  CHECK(differ > 200);
}

TEST_CASE("coverage is the fraction of the sky under cloud", "[clouds]") {
  for (double coverage : {0.1, 0.3, 0.5, 0.8}) {
    for (std::uint64_t seed : {1u, 77u}) {
      const CloudySky sky = clouds(coverage, seed, 12);
      int cloudy = 0;
      const auto dirs = random_directions(20000, seed + 100);
      for (const Eigen::Vector3d& d : dirs) cloudy += sky.opacity(d) > 0.5 ? 1 : 0;
      INFO("coverage " << coverage << " seed " << seed);
      CHECK(static_cast<double>(cloudy) / static_cast<double>(dirs.size()) == Approx(coverage).margin(0.03));
    }
  }
  for (const Eigen::Vector3d& d : random_directions(500, 3)) {
    CHECK(clouds(0.0, 9).opacity(d) == 0.0);
    CHECK(clouds(1.0, 9).opacity(d) == 1.0);
  }
}

TEST_CASE("clouds raise S0, lower DoLP and keep the AoLP under thin cloud", "[clouds]") {
  const CloudySky sky = clouds(0.5, 42);
  const RayleighSky clear({0.8});
  const Sun sun = sun_at(150, 35);
  int thin = 0, thick = 0;
  for (const Eigen::Vector3d& d : random_directions(5000, 8)) {
    const Stokes c = clear.stokes(d, perpendicular(d), sun), s = sky.stokes(d, perpendicular(d), sun);
    const double a = sky.opacity(d);
    CHECK(s.s0 >= c.s0);
    CHECK(s.dolp() <= c.dolp() + 1e-12);
    CHECK(s.dolp() == Approx(c.dolp() * (1 - a) / (1 - a + 2.5 * a)).margin(1e-9));
    if (a > 0.05 && a < 0.95 && c.dolp() > 1e-3) {
      ++thin;
      CHECK(std::remainder(s.aolp() - c.aolp(), kPi) == Approx(0.0).margin(1e-9));
    }
    if (a == 1.0) {
      ++thick;
      CHECK(s.dolp() == 0.0);
      CHECK(s.s0 == Approx(2.5 * c.s0));
    }
  }
  CHECK(thin > 50);
  CHECK(thick > 50);
}

TEST_CASE("cloud opacity is continuous across the sky", "[clouds]") {
  const CloudySky sky = clouds(0.5, 5, 10);
  for (const Eigen::Vector3d& d : random_directions(3000, 4)) {
    const Eigen::Vector3d near = (d + 1e-4 * perpendicular(d)).normalized();  // 0.006° away
    CHECK(std::abs(sky.opacity(d) - sky.opacity(near)) < 0.02);
  }
}

TEST_CASE("cloudy batch path equals the scalar path", "[clouds][batch]") {
  const CloudySky sky = clouds(0.6, 99);
  const Sun sun = sun_at(10, 50);
  std::vector<ViewRay> rays;
  for (const Eigen::Vector3d& d : random_directions(1500, 6)) rays.push_back({d.cast<float>(), perpendicular(d).cast<float>()});
  for (const auto& [batch, scalar] : batch_and_scalar(sky, rays, sun)) {
    CHECK(batch.s0 == Approx(scalar.s0).epsilon(1e-5));
    CHECK(batch.s1 == Approx(scalar.s1).margin(1e-5));
    CHECK(batch.s2 == Approx(scalar.s2).margin(1e-5));
  }
}

TEST_CASE("bad cloud parameters name the field", "[clouds][bad-input]") {
  CHECK_THROWS_WITH(clouds(1.5, 0), Catch::Contains("clouds.coverage"));
  CHECK_THROWS_WITH(clouds(-0.1, 0), Catch::Contains("clouds.coverage"));
  CHECK_THROWS_WITH(clouds(0.5, 0, 0.1), Catch::Contains("clouds.scale_deg"));
  CloudParams p;
  p.brightness = 0.5;
  CHECK_THROWS_WITH(CloudySky(std::make_unique<RayleighSky>(), p), Catch::Contains("clouds.brightness"));
  p = {};
  p.softness = 0;
  CHECK_THROWS_WITH(CloudySky(std::make_unique<RayleighSky>(), p), Catch::Contains("clouds.softness"));
}
