// The five ideal radial mappings: closed-form pixels of known directions and exact round trips.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "camera/radial_lens.h"
#include "camera_test_util.h"
#include "sky/units.h"

using skypol::camera::Intrinsics;
using skypol::camera::Mapping;
using skypol::camera::RadialLens;
using skypol::testing::dir;
using skypol::testing::imx250;
using skypol::kPi, skypol::kRadPerDeg;

namespace {
}  // namespace

TEST_CASE("a direction 90° off-axis lands at r = f·π/2 on an equidistant lens", "[lens]") {
  const double f = 521.739;
  RadialLens lens(Mapping::equidistant, imx250(f), 92.5 * kRadPerDeg);
  // Towards camera +x (image right) and +y (image down).
  auto px = lens.project({1, 0, 0});
  REQUIRE(px);
  CHECK(px->x() == Approx(1223.5 + f * kPi / 2).epsilon(1e-14));
  CHECK(px->y() == Approx(1023.5).margin(1e-9));
  auto py = lens.project({0, 1, 0});
  REQUIRE(py);
  CHECK(py->x() == Approx(1223.5).margin(1e-9));
  CHECK(py->y() == Approx(1023.5 + f * kPi / 2).epsilon(1e-14));  // 1843.04 px
  // The axis lands on the principal point.
  auto pc = lens.project({0, 0, 5});
  REQUIRE(pc);
  CHECK(pc->x() == 1223.5);
  CHECK(pc->y() == 1023.5);
}

TEST_CASE("each mapping puts 60° off-axis at its closed-form radius", "[lens]") {
  const double f = 500;
  // r/f at θ = 60°: tan 60 = √3, 2 tan 30 = 2/√3, π/3, 2 sin 30 = 1, sin 60 = √3/2.
  struct Case { Mapping m; double r_over_f; double tmax; };
  const Case cases[] = {{Mapping::perspective, std::sqrt(3.0), 80 * kRadPerDeg},
                        {Mapping::stereographic, 2 / std::sqrt(3.0), 92.5 * kRadPerDeg},
                        {Mapping::equidistant, kPi / 3, 92.5 * kRadPerDeg},
                        {Mapping::equisolid, 1.0, 92.5 * kRadPerDeg},
                        {Mapping::orthographic, std::sqrt(3.0) / 2, 90 * kRadPerDeg}};
  for (const auto& c : cases) {
    RadialLens lens(c.m, imx250(f), c.tmax);
    // φ = 135°: direction towards image up-left.
    auto p = lens.project(dir(60 * kRadPerDeg, 135 * kRadPerDeg));
    REQUIRE(p);
    CHECK(p->x() == Approx(1223.5 - f * c.r_over_f / std::sqrt(2.0)).epsilon(1e-13));
    CHECK(p->y() == Approx(1023.5 + f * c.r_over_f / std::sqrt(2.0)).epsilon(1e-13));
  }
}

TEST_CASE("project(ray(p)) = p to 1e-6 px over the whole image circle, every mapping", "[lens]") {
  const double f = 521.739;
  struct Case { Mapping m; double tmax; };
  // A 185° lens where the mapping can image it; perspective and orthographic up to their limits.
  const Case cases[] = {{Mapping::perspective, 85 * kRadPerDeg},
                        {Mapping::stereographic, 92.5 * kRadPerDeg},
                        {Mapping::equidistant, 92.5 * kRadPerDeg},
                        {Mapping::equisolid, 92.5 * kRadPerDeg},
                        {Mapping::orthographic, 90 * kRadPerDeg}};
  for (const auto& c : cases) {
    Intrinsics k = imx250(f);
    k.fy = 1.01 * f;  // non-square pixels exercise fx ≠ fy
    RadialLens lens(c.m, k, c.tmax);
    const double r_max = lens.radius(c.tmax);
    double worst = 0, worst_norm = 0;
    int n_in = 0;
    // Polar grid in normalized image coordinates, including the principal point and the edge.
    for (int i = 0; i <= 400; ++i) {
      const double r = r_max * i / 400.0;
      for (int j = 0; j < 64; ++j) {
        const double phi = 2 * kPi * j / 64.0 + 0.1;
        const Eigen::Vector2d p(k.cx + k.fx * r * std::cos(phi), k.cy + k.fy * r * std::sin(phi));
        auto d = lens.ray(p);
        REQUIRE(d);
        worst_norm = std::max(worst_norm, std::abs(d->norm() - 1));
        auto q = lens.project(*d);
        REQUIRE(q);
        worst = std::max(worst, (*q - p).norm());
        ++n_in;
      }
    }
    WARN(lens.name() << ": worst round-trip error " << worst << " px over " << n_in << " pixels");
    CHECK(worst < 1e-6);
    CHECK(worst_norm < 1e-14);
    // Just outside the image circle: masked, not NaN.
    const Eigen::Vector2d out(k.cx + k.fx * r_max * 1.0001, k.cy);
    CHECK_FALSE(lens.ray(out));
    // And a direction beyond θmax is not imaged.
    CHECK_FALSE(lens.project(dir(c.tmax + 1e-6, 0.3)));
  }
}

TEST_CASE("ray of the corner pixels of a 185° fisheye is nullopt, never NaN", "[lens]") {
  RadialLens lens(Mapping::equidistant, imx250(), 92.5 * kRadPerDeg);
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(0, 0), Eigen::Vector2d(2447, 2047),
                                  Eigen::Vector2d(NAN, 3), Eigen::Vector2d(1e300, -1e300)})
    CHECK_FALSE(lens.ray(p));
  // 92.5° direction: on the edge, imaged; zero vector and straight back: not.
  CHECK(lens.project(dir(92.5 * kRadPerDeg, 1.0)));
  CHECK_FALSE(lens.project({0, 0, 0}));
  CHECK_FALSE(lens.project({0, 0, -1}));
}

TEST_CASE("non-physical radial lens parameters are rejected with the key named", "[lens]") {
  Intrinsics k = imx250(500);
  CHECK_THROWS_WITH(RadialLens(Mapping::perspective, k, 90 * kRadPerDeg),
                    Catch::Contains("perspective"));
  CHECK_THROWS_AS(RadialLens(Mapping::orthographic, k, 91 * kRadPerDeg), std::invalid_argument);
  CHECK_NOTHROW(RadialLens(Mapping::orthographic, k, 90 * kRadPerDeg));
  CHECK_THROWS_AS(RadialLens(Mapping::stereographic, k, 180 * kRadPerDeg), std::invalid_argument);
  CHECK_NOTHROW(RadialLens(Mapping::equidistant, k, 180 * kRadPerDeg));
  k.fx = 0;
  CHECK_THROWS_WITH(RadialLens(Mapping::equidistant, k, 1.0), Catch::Contains("fx must be > 0"));
  CHECK_THROWS_WITH(skypol::camera::parse_mapping("fisheye"),
                    Catch::Contains("equidistant") && Catch::Contains("fisheye"));
  CHECK(skypol::camera::parse_mapping("equisolid") == Mapping::equisolid);
  CHECK(skypol::camera::mapping_name(Mapping::orthographic) == "orthographic");
}
