// [camera] image_circle_px with a calibration: the field of view ends at the image circle, not at
// the sensor's farthest corner (350° for the COLMAP example camera, whose corners are dark).
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "cli/cli_harness.h"
#include "sky/units.h"

using skypol::test::Result;
using skypol::test::run;
using skypol::test::TempDir;
using skypol::deg_from_rad;

namespace {

std::string scene(const std::string& camera_extra) {
  return std::string(R"([site]
latitude_deg = 43.3
longitude_deg = 5.4

[time]
start = "2022-09-23T10:00:00Z"
end = "2022-09-23T10:00:00Z"
step_min = 10

[camera]
calibration = ")") + SKYPOL_SOURCE_DIR + R"(/scenes/calibrations/cameras.txt"
calibration_format = "colmap"
calibration_camera = 1
)" + camera_extra;
}

// The number after "KEY": in JSON text.
double number(const std::string& json, const std::string& key, std::size_t from = 0) {
  const std::size_t at = json.find("\"" + key + "\": ", from);
  REQUIRE(at != std::string::npos);
  return std::stod(json.substr(at + key.size() + 4));
}

bool inside(const std::string& json) { return json.find("\"inside\": true") != std::string::npos; }

}  // namespace

TEST_CASE("image_circle_px ends a calibration's field of view at the image circle", "[cli][camera]") {
  TempDir dir;
  const Result corner = run("lens --json " + dir.write("corner.toml", scene("")));
  INFO(corner.out);
  REQUIRE(corner.code == 0);
  CHECK(number(corner.out, "fov_deg") > 340);  // the farthest corner's, past the horizon all round

  const Result circle = run("lens --json " + dir.write("circle.toml", scene("image_circle_px = 840\n")));
  INFO(circle.out);
  REQUIRE(circle.code == 0);
  const double fov = number(circle.out, "fov_deg"), cx = number(circle.out, "cx"), cy = number(circle.out, "cy");
  // The Fujinon's 185°, about: 840 px from the centre at fx = 521.9 px is θ ≈ 840 / 521.9 rad (the
  // equidistant part of the Kannala-Brandt polynomial; its small k1..k4 move it under a degree).
  CHECK(std::abs(fov - deg_from_rad(2 * 840 / 521.9)) < 3.0);
  // The circle's pixel that sees least far off the axis (along x: fx > fy) sees fov / 2, as the
  // lens itself says; a pixel just inside the circle is inside the field, one just beyond is not.
  auto at = [&](double u, double v) {
    const Result r = run("lens --json " + (dir.path / "circle.toml").string() + " -p " + std::to_string(u) + "," +
                         std::to_string(v));
    REQUIRE(r.code == 0);
    return r.out;
  };
  const std::string edge = at(cx + 840, cy);
  CHECK(std::abs(number(edge, "off_axis_deg", edge.find("answers")) - fov / 2) < 1e-6);
  CHECK(inside(at(cx + 838, cy)));
  CHECK_FALSE(inside(at(cx + 842, cy)));
  CHECK_FALSE(inside(at(cx, cy + 845)));
  CHECK(inside(at(cx - 590, cy - 580)));  // 827 px from the centre

  // Bad input names the key: both ways of giving the field, the key without a calibration, a
  // radius out of range.
  const Result both = run("lens " + dir.write("both.toml", scene("image_circle_px = 840\nfov_deg = 185\n")));
  CHECK(both.code == 2);
  CHECK_THAT(both.out, Catch::Contains("image_circle_px") && Catch::Contains("not both"));
  const Result model = run("lens " + dir.write("model.toml", R"([site]
latitude_deg = 43.3
longitude_deg = 5.4

[time]
start = "2022-09-23T10:00:00Z"
end = "2022-09-23T10:00:00Z"
step_min = 10

[camera]
lens_preset = "fujinon_fe185c057ha1"
image_circle_px = 840
)"));
  CHECK(model.code == 2);
  CHECK_THAT(model.out, Catch::Contains("camera.image_circle_px") && Catch::Contains("only with a calibration"));
  const Result zero = run("lens " + dir.write("zero.toml", scene("image_circle_px = 0\n")));
  CHECK(zero.code == 2);
  CHECK_THAT(zero.out, Catch::Contains("image_circle_px"));
}
