// `skypol lens`: the shipped SkyPole camera against the equidistant closed form r = f·θ.
#include <catch2/catch.hpp>

#include <cmath>

#include "cli/cli_harness.h"
#include "sky/units.h"

using skypol::test::run;
using skypol::kPi, skypol::deg_from_rad;

TEST_CASE("lens gives the pixel of a direction and the direction of a pixel", "[cli]") {
  const std::string scene = std::string(SKYPOL_SOURCE_DIR) + "/scenes/skypole-marseille.toml";
  // Zenith camera, heading 0: North on the horizon is straight up from the centre, f·π/2 away,
  // with f = 1.8 mm / 3.45 µm.
  const double f = 1.8e3 / 3.45, v_north = 1023.5 - f * kPi / 2;
  const auto r = run("lens " + scene + " -d 0,0 -d 90,60 -p 1223.5,600");
  INFO(r.out);
  REQUIRE(r.code == 0);
  char north[64];
  std::snprintf(north, sizeof north, "pixel (1223.5000, %.4f)", v_north);
  CHECK_THAT(r.out, Catch::Contains(north));
  // East at 60° elevation (30° off the axis) images to the left of the centre (the sky seen from
  // below is mirrored: image-right is West).
  char east[64];
  std::snprintf(east, sizeof east, "pixel (%.4f, 1023.5000)", 1223.5 - f * kPi / 6);
  CHECK_THAT(r.out, Catch::Contains(east));
  // 423.5 px above the centre is θ = 423.5/f off the axis, towards North.
  char back[96];
  std::snprintf(back, sizeof back, "direction az    0.000 el %7.3f deg", 90 - deg_from_rad(423.5 / f));
  CHECK_THAT(r.out, Catch::Contains(back));
  CHECK(run("lens " + scene + " -p 1,2,3").code == 2);
}
