// The sun's disc: unpolarized radiance within 0.2666° of the sun, hidden by thick cloud.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <vector>

#include "sky/clouds.h"
#include "sky/rayleigh.h"
#include "sky/sky_spec.h"
#include "sky/sun_disc.h"
#include "sky_test_util.h"

using namespace skypol::sky;
using namespace skypol::testing;

TEST_CASE("the disc adds unpolarized radiance within 0.2666 degrees of the sun", "[sun_disc]") {
  const SunDiscSky sky(std::make_unique<RayleighSky>(RayleighParams{0.8}), 1e5);
  const Sun sun = sun_at(100, 40);
  const Stokes centre = sky.stokes(sun.direction, perpendicular(sun.direction), sun);
  CHECK(centre.s0 == Approx(1e5 + 2.0));
  CHECK(centre.dolp() < 1e-12);
  const Eigen::Vector3d inside = enu_direction(100 * kRadPerDeg, 40.26 * kRadPerDeg);
  CHECK(sky.stokes(inside, perpendicular(inside), sun).s0 > 1e5);
  CHECK(sky.stokes(inside, perpendicular(inside), sun).dolp() < 1e-8);  // the sky's polarization is drowned
  const Eigen::Vector3d outside = enu_direction(100 * kRadPerDeg, 40.27 * kRadPerDeg);
  CHECK(sky.stokes(outside, perpendicular(outside), sun).s0 < 3.0);
  CHECK(sky.name() == "rayleigh");
}

TEST_CASE("thick cloud hides the disc; the factory puts the disc over the clouds", "[sun_disc][clouds]") {
  SkySpec spec;
  spec.sun_disc = true;
  spec.sun_disc_radiance = 1e5;
  spec.clouds.coverage = 0.5;
  spec.clouds.seed = 3;
  const auto sky = make_sky(spec);
  const auto* disc = dynamic_cast<const SunDiscSky*>(sky.get());
  REQUIRE(disc != nullptr);
  const auto* clouds = dynamic_cast<const CloudySky*>(&disc->inner());
  REQUIRE(clouds != nullptr);
  // Put the sun behind thick cloud, then in clear sky, by searching directions.
  bool hidden = false, shown = false;
  for (double az = 0; az < 360 && !(hidden && shown); az += 3) {
    for (double el = 5; el < 85; el += 3) {
      const Sun sun = sun_at(az, el);
      const double a = clouds->opacity(sun.direction);
      const Stokes s = sky->stokes(sun.direction, perpendicular(sun.direction), sun);
      const Stokes under = clouds->stokes(sun.direction, perpendicular(sun.direction), sun);
      CHECK(s.s0 == Approx(under.s0 + 1e5 * (1 - a)).epsilon(1e-12));
      if (a == 1.0) {
        hidden = true;
        CHECK(s.s0 < 10.0);  // only the glowing cloud
      }
      if (a == 0.0) {
        shown = true;
        CHECK(s.s0 > 1e5);
      }
    }
  }
  CHECK(hidden);
  CHECK(shown);
}

TEST_CASE("disc batch path equals the scalar path", "[sun_disc][batch]") {
  const SunDiscSky sky(std::make_unique<RayleighSky>(RayleighParams{0.7}), 500);
  const Sun sun = sun_at(33, 12);
  std::vector<ViewRay> rays;
  for (double off = -0.5; off <= 0.5; off += 0.01) {
    const Eigen::Vector3d d = enu_direction(33 * kRadPerDeg, (12 + off) * kRadPerDeg);
    rays.push_back({d.cast<float>(), perpendicular(d).cast<float>()});
  }
  const std::vector<BatchAndScalar> both = batch_and_scalar(sky, rays, sun);
  int in_disc = 0;
  for (std::size_t i = 0; i < both.size(); ++i) {
    const double off = -0.5 + 0.01 * static_cast<double>(i);
    if (std::abs(std::abs(off) - kSunAngularRadiusDeg) < 0.002) continue;  // float vs double at the rim
    CHECK(both[i].batch.s0 == Approx(both[i].scalar.s0).epsilon(1e-5));
    in_disc += both[i].scalar.s0 > 100 ? 1 : 0;
  }
  CHECK(in_disc == 53);  // −0.26° … +0.26° in 0.01° steps
  CHECK_THROWS_WITH(SunDiscSky(std::make_unique<RayleighSky>(), -1), Catch::Contains("sun_disc_radiance"));
}
